#!/usr/bin/env python3
"""mitsuba_sun.py: issue 22's sun scenes against Mitsuba 3, the sun cache off and on (equal samples).

Imports bench/mitsuba_compare.py's scene translation and error measure (its own file is left alone).
For scenes/sun_shadow_object.pbrt (direct lighting), scenes/sun_porch.pbrt (path, maxdepth 3) and
scenes/bench_city.pbrt (direct): plastic materials are made matte (the translation knows matte only),
160x120, SPP samples per pixel, SEEDS seeds; Mitsuba 'direct' (1 emitter + 1 BSDF sample) or 'path'
with the independent sampler, ours with the random sampler, --sun off and --sun on. Error: the relative
variance across seeds (mitsuba_compare.relvar: mean over pixels and channels of var / (mean^2 + 1e-2)),
over the whole image and over the SHADOWED pixels: those whose mean luminance (Mitsuba's) is below 0.3
of the image's 95th percentile (a sun scene's shadow: the sky alone). Printed: each and the ratio ours /
Mitsuba (issue 22's target: <= 0.5).
    python3 bench/mitsuba_sun.py [SPP [SEEDS [THREADS]]]        (64, 4, 2)"""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_compare as mc  # noqa: E402

SCENES = [("sun_shadow_object.pbrt", "direct", 5), ("sun_porch.pbrt", "path", 3), ("bench_city.pbrt", "direct", 5)]


def relvar_mask(imgs, mask):
    import numpy as np
    a = np.stack(imgs)
    m = a.mean(axis=0)
    v = a.var(axis=0, ddof=1)
    r = v / (m * m + 1e-2)
    return float(np.mean(r[mask]))


def main():
    import numpy as np
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 64
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    threads = int(sys.argv[3]) if len(sys.argv) > 3 else 2
    render = os.path.join(mc.ROOT, "build", "bin", "render")
    work = tempfile.mkdtemp(prefix="el_mitsuba_sun_")
    import mitsuba as mi
    variant = "llvm_ad_rgb"
    try:
        mi.set_variant(variant)
    except Exception:
        variant = "scalar_rgb"
    mr = mc.MiVarRunner(threads, work, variant)
    print("mitsuba_sun: 160x120, %d spp, %d seeds, %d threads; Mitsuba %s %s (independent), ours random"
          % (spp, seeds, threads, mi.__version__, variant))
    for fname, integ, depth in SCENES:
        text = mc.scene_variant(os.path.join(mc.ROOT, "scenes", fname), res=(160, 120), integrator=integ, maxdepth=depth)
        text = re.sub(r'Material "plastic" "rgb Kd" (\[[^\]]*\]).*', r'Material "matte" "rgb Kd" \1', text)
        text = re.sub(r'^Sampler.*$', 'Sampler "random" "integer pixelsamples" [ %d ]' % spp, text, flags=re.M)
        sf = os.path.join(work, fname)
        with open(sf, "w") as f:
            f.write(text)
        sc = mc.parse_pbrt(sf, text)
        scene = mr.scene(fname, sc, integ, 1, "independent", depth)
        mimgs = [mr.render(scene, spp, 7 + k)[0] for k in range(seeds)]
        ours = {}
        for sun in ("off", "on"):
            imgs = []
            for k in range(seeds):
                out = os.path.join(work, "o.exr")
                subprocess.run([render, sf, "--spp", str(spp), "--nthreads", str(threads), "--quiet", "--seed", str(k + 1),
                                "--sampler", "random", "--sun", sun, "--outfile", out], check=True, capture_output=True)
                imgs.append(mc.read_image(out))
            ours[sun] = imgs
        lum = np.stack(mimgs).mean(axis=0) @ np.array([0.2126, 0.7152, 0.0722])
        shadow = lum < 0.3 * np.percentile(lum, 95)
        mask3 = np.repeat(shadow[..., None], 3, axis=2)
        allm = np.ones_like(mask3, dtype=bool)
        rm = (mc.relvar(mimgs), relvar_mask(mimgs, mask3))
        print("%s (%s, %d%% of the pixels shadowed):" % (fname, integ, int(round(100 * shadow.mean()))))
        print("  %-22s image %.4g  shadowed %.4g" % ("Mitsuba", rm[0], rm[1]))
        for sun in ("off", "on"):
            r = (relvar_mask(ours[sun], allm), relvar_mask(ours[sun], mask3))
            print("  %-22s image %.4g  shadowed %.4g   ours / Mitsuba: image %.2f, shadowed %.2f"
                  % ("ours, --sun " + sun, r[0], r[1], r[0] / rm[0], r[1] / rm[1]))
        mr.drop(fname)


if __name__ == "__main__":
    main()
