#!/usr/bin/env python3
"""make_sun_map.py: writes data/envmaps/sunrise.hdr, the generated sun map of issue 22's scenes
(scenes/sun_shadow_object.pbrt, scenes/sun_porch.pbrt). 512 x 256, equirectangular, row 0 at the zenith,
light space z up (pbrt-v3's mapping: phi = 2 pi u, theta = pi v). A sky brighter towards the horizon and
the sun, a dim ground, and a sun disc of 0.5 degree radius at 25 degrees elevation (azimuth 288 degrees)
that holds 75% of the map's power (its texels ~10^4 times the sky). Flat (not run-length encoded) RGBE.
CC0. Run: python3 bench/make_sun_map.py [out.hdr]"""
import math, sys
import numpy as np

W, H = 512, 256
EL, AZ, RAD, SHARE = math.radians(25.0), math.radians(288.0), math.radians(0.5), 0.75

def make():
    th = math.pi * (np.arange(H) + 0.5) / H
    ph = 2 * math.pi * (np.arange(W) + 0.5) / W
    T, P = np.meshgrid(th, ph, indexing="ij")
    d = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
    sun = np.array([math.cos(EL) * math.cos(AZ), math.cos(EL) * math.sin(AZ), math.sin(EL)])
    c = np.clip(d @ sun, -1, 1)
    ang = np.arccos(c)
    z = d[..., 2]
    sky = np.where(z > 0, 0.15 + 0.5 * np.exp(-z * 4), 0.03)
    glow = np.where(z > -0.02, 2.0 * np.exp(-ang / 0.15), 0.0)
    img = np.stack([sky * 0.8 + glow, sky * 0.9 + glow * 0.7, sky * 1.3 + glow * 0.4], -1)
    # the disc: texels whose centre lies within RAD of the sun, at least the sun's own texel
    disc = ang < RAD
    disc[np.unravel_index(np.argmin(ang), ang.shape)] = True
    texel_sa = (2 * math.pi / W) * (math.pi / H) * np.sin(T)
    lum = img @ np.array([0.2126, 0.7152, 0.0722])
    rest = float((lum * texel_sa)[~disc].sum())
    disc_sa = float(texel_sa[disc].sum())
    L = SHARE / (1 - SHARE) * rest / disc_sa  # the disc's luminance
    col = np.array([1.0, 0.85, 0.6])
    col = col / (col @ np.array([0.2126, 0.7152, 0.0722]))
    img[disc] = L * col
    return img.astype(np.float32), int(disc.sum()), L

def rgbe(img):
    m = img.max(-1)
    e = np.zeros(m.shape, np.int32)
    f, ex = np.frexp(m)
    ok = m > 1e-32
    e[ok] = ex[ok]
    scale = np.where(ok, np.ldexp(1.0, -e) * 256.0, 0.0)
    out = np.zeros(img.shape[:2] + (4,), np.uint8)
    out[..., :3] = np.clip(img * scale[..., None], 0, 255).astype(np.uint8)
    out[..., 3] = np.where(ok, e + 128, 0).astype(np.uint8)
    return out

if __name__ == "__main__":
    path = sys.argv[1] if len(sys.argv) > 1 else "data/envmaps/sunrise.hdr"
    img, n, L = make()
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W))
        f.write(rgbe(img).tobytes())
    print("%s: %dx%d, sun %d texels of luminance %.4g" % (path, W, H, n, L))
