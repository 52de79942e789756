#!/usr/bin/env python3
"""compare_pfm.py: relative MSE between two linear PFM images, over the whole image and per region.

    python3 bench/pbrt_v3/compare_pfm.py TEST.pfm REF.pfm [--mask-from MASK.pfm]
    python3 bench/pbrt_v3/compare_pfm.py --blocks N IMAGE.pfm   (the N x N block means, as a C table)

relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01), the definition of
examples/03_infinite_light.c and the rest of the project. Standard library only (no numpy).

--mask-from MASK.pfm: the pixels of scenes/killeroo-simple.pbrt (pbrt-v3's repository, 700x700) split
into the killeroo of Ks .5, roughness .025 (the first in the file), the one of Ks .3, roughness .15
and the rest (floor, wall, light), from a material-ID render: MASK.pfm is that scene rendered by our renderer
lit by a constant sky alone, the first killeroo matte red, the second green, the light's sphere
yellow, the rest blue (compare.sh makes it); pixels with any yellow and 2 pixels around them are the
light's (at its edge a 2000-bright light's coverage dominates the error when two renders' pixel
samples differ: pbrt-v3's Sobol against Halton), every other belongs to the region of its largest
channel. Prints, per region, relMSE and the mean of each image (the bias, not the noise).
"""
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        data = f.read()
    # header: "PF\n" w h "\n" scale "\n", each a whitespace-separated token
    parts, pos = [], 0
    while len(parts) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        parts.append(data[start:pos].decode())
    pos += 1
    kind, w, h, scale = parts[0], int(parts[1]), int(parts[2]), float(parts[3])
    if kind != "PF":
        sys.exit("%s: only colour PFM (PF) is read, got %s" % (path, kind))
    endian = "<" if scale < 0 else ">"
    n = w * h * 3
    vals = struct.unpack_from(endian + "%df" % n, data, pos)
    # PFM stores rows bottom to top; flip so row 0 is the top
    rows = [vals[(h - 1 - y) * w * 3:(h - y) * w * 3] for y in range(h)]
    return w, h, [v for r in rows for v in r]


def blocks(path, n):
    """prints the n x n block means of an image as C initialisers, rows top to bottom"""
    w, h, a = read_pfm(path)
    if w % n or h % n:
        sys.exit("%s: %dx%d is not a multiple of %d" % (path, w, h, n))
    print("/* %s: %dx%d, the mean of each %dx%d block, rows top to bottom, {r, g, b} */" % (path, w, h, n, n))
    for by in range(h // n):
        row = []
        for bx in range(w // n):
            m = [0.0, 0.0, 0.0]
            for y in range(by * n, by * n + n):
                for x in range(bx * n, bx * n + n):
                    for c in range(3):
                        m[c] += a[3 * (y * w + x) + c] / (n * n)
            row.append("{%.5g, %.5g, %.5g}" % tuple(m))
        print("  " + ", ".join(row) + ",")


def main():
    args = sys.argv[1:]
    if len(args) == 3 and args[0] == "--blocks":
        blocks(args[2], int(args[1]))
        return
    mask_path = None
    if "--mask-from" in args:
        i = args.index("--mask-from")
        mask_path = args[i + 1]
        del args[i:i + 2]
    if len(args) != 2:
        sys.exit(__doc__)
    w, h, a = read_pfm(args[0])
    w2, h2, b = read_pfm(args[1])
    if (w, h) != (w2, h2):
        sys.exit("sizes differ: %dx%d and %dx%d" % (w, h, w2, h2))
    region = [0] * (w * h)
    names = ["all"]
    if mask_path:
        wm, hm, m = read_pfm(mask_path)
        if (wm, hm) != (w, h):
            sys.exit("mask size differs")
        names = ["all", "floor and wall", "killeroo Ks .5 rough .025", "killeroo Ks .3 rough .15",
                 "the light (any coverage)", "all but the light"]
        light = [False] * (w * h)
        for p in range(w * h):
            r, g, bl = m[3 * p], m[3 * p + 1], m[3 * p + 2]
            light[p] = r > 0.02 * bl and g > 0.02 * bl and 0.5 * g < r < 2 * g  # any yellow: the light
            region[p] = 2 if r > g and r > bl else (3 if g > r and g > bl else 1)
        for p in range(w * h):  # the light and 2 pixels around it
            if light[p]:
                x0, y0 = p % w, p // w
                for y in range(max(0, y0 - 2), min(h, y0 + 3)):
                    for x in range(max(0, x0 - 2), min(w, x0 + 3)):
                        region[y * w + x] = 4
    nr = len(names)
    err, cnt, ma, mb = [0.0] * nr, [0] * nr, [0.0] * nr, [0.0] * nr
    for p in range(w * h):
        for c in range(3):
            x, y = a[3 * p + c], b[3 * p + c]
            e = (x - y) * (x - y) / (y * y + 0.01)
            for k in ((0, region[p]) + ((5,) if region[p] != 4 else ()) if region[p] else (0,)):
                err[k] += e
                cnt[k] += 1
                ma[k] += x
                mb[k] += y
    for k in range(nr):
        if cnt[k]:
            print("%-30s pixels %7d  relMSE %.3e  mean %.4f vs %.4f (ratio %.4f)" % (
                names[k], cnt[k] // 3, err[k] / cnt[k], ma[k] / cnt[k], mb[k] / cnt[k],
                (ma[k] / mb[k]) if mb[k] else float("nan")))


if __name__ == "__main__":
    main()
