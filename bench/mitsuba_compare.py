#!/usr/bin/env python3
"""mitsuba_compare.py: our renderer against Mitsuba 3 on the same environment-lit scene.

The default run (variance mode; issues 13 and 14)
  Both renderers render scenes/bench_city.pbrt (the sun map: city.hdr, a 3e4 sun) and
  scenes/bench_studio.pbrt (the smooth map: studio.hdr), each with the directlighting and the path
  integrator (maxdepth 5; Mitsuba's 'direct' and 'path', max_depth 6 as it counts segments), at 16,
  64 and 256 spp, each configuration with --seeds seeds (default 3). Error is the RELATIVE VARIANCE
  ACROSS SEEDS: the mean over pixels and channels of the variance of the seeds' images over
  (mean^2 + 1e-2); no reference image, so the two renderers' half-texel conventions do not count (the
  means are compared separately: "bias check"). Configurations:
    Mitsuba (llvm_ad_rgb, else scalar_rgb): independent 1/1, multijitter 1/1, 2/2, 4/4, stratified
      1/1 (and 2/2, 4/4 unless --no-stratified-splitting); n/n = emitter_samples / bsdf_samples of
      'direct' (path: 1/1 only);
    ours: random 1/1, --our-sampler (default zsobol; 02sequence is the renderer's default) 1/1 and 2/2
      (the light's "integer samples", pbrt-v3's nsamples), and with --map-too the map alone
      (--env-sampling map, pbrt-v3's light sampling) against product sampling (the default).
  Runs are interleaved: every configuration once per seed round, so the machine's load falls on all.
  CPU seconds: ours, the render loop's (render --stats: "render ... (CPU x s)", all threads); Mitsuba,
  the process CPU time of mi.render() and reading the image back (which forces the JIT's evaluation),
  after one warm-up render per configuration (compilation). Fixed costs are printed apart: ours,
  parsing with the map load, Embree's build and the sampling tables (from --stats); Mitsuba,
  load_dict (map, its distribution, BVH) and the first render with its JIT compilation.
  Tables: (a) issue 13's equal-spp ratio, ours / Mitsuba with matched samplers (our random against
  independent, our low-discrepancy sampler against multijitter), one light + one BSDF sample
  (target <= 0.5); (b) issue 14's equal-time ratio: cost = relative variance x CPU s of our best
  configuration over Mitsuba's best at each spp (target <= 0.5); (c) issue 21's CPU per camera sample,
  ours / Mitsuba at equal spp with one light + one BSDF sample (target <= 1), beside (b) again (issue
  21's equal-time target <= 0.5); (d) with --regions or --mask, (a) and (b) for the lit and the
  shadowed pixels apart (issue 22).
    python3 bench/mitsuba_compare.py [--quick] [--seeds 3] [--var-res W H] [--var-spp 64,256]
                                     [--our-sampler 02sequence] [--map-too] [--no-stratified-splitting]
                                     [--threads 2] [--maxdepth 5] [--regions | --mask FILE]
                                     [--var-maps sun,smooth] [--var-integrators direct,path]
                                     [--variant NAME=OPTIONS ...] [--variant-integrators direct,path]
  --variant NAME=OPTIONS: ours with more render options (random and --our-sampler), on the integrators of
  --variant-integrators (default direct,path); its own (a) and (d) tables, and a candidate for (b)'s best.
  --var-maps, --var-integrators: run only these maps and integrators (shorter runs).
  --regions: pixel_classes() ray-casts the parsed scene in numpy (neither renderer's code) at 4x4
  positions per pixel and casts a shadow ray towards the map's brightest texel (sun_direction()): "lit"
  pixels see the sun from every position, "shadowed" from none (background, silhouettes and penumbrae
  are in neither; bench_city at 320x240: 32676 lit, 20781 shadowed). --mask FILE: the same two classes
  from a PGM (P2/P5) or PFM of the compared resolution (> 0.5 of its maximum: shadowed), read_mask().
  Other scripts can import pixel_classes, read_mask, relvar_by_class, scene_variant and parse_pbrt.
  --quick: 160x120, 16 and 64 spp, 2 seeds, fewer configurations (about 2 CPU minutes).
  --sampler-variance: our seven samplers alone (directlighting, both maps), the table of the render
  README's "Samplers" section.
  Mitsuba is installed from PyPI (pip install mitsuba numpy) when it is missing; its llvm variants
  need libLLVM (Debian: apt-get install libllvm19), else scalar_rgb is used.
  Measured (2026-12-02, --var-res 320 240 --var-spp 64,256 --seeds 3 --regions --no-stratified-splitting,
  the binary of commit 31bc383, 921 s on the shared 2-core machine at load average 4-7;
  examples/render/README.md, "Against Mitsuba 3"): (c) our CPU per camera sample 1.65-1.84x Mitsuba's
  (sun, direct), 1.25-1.35x (sun, path), 1.08-1.10x (smooth, direct), 1.25-1.34x (smooth, path); (a)
  zsobol / multijitter 0.69-0.79 (sun, direct), 0.94-0.98 (sun, path), 0.13-0.21 (smooth); (b) 1.27-1.32
  (sun, direct), 1.18-1.32 (sun, path), 0.13-0.14 (smooth, direct), 0.27 (smooth, path). The run before
  (the same day, before issue 21's third round): (c) 1.5-2.2x, (b) 3.1, 1.8-2.0, 0.23-0.25, 0.43-0.46.

The older measure (--reference; issue 5)
  Accuracy against time for direct lighting of a diffuse sphere on a plane under the city map
  (data/envmaps/city.hdr: a 3e4 sun, so nearly all the light comes from a few texels), 320x240:
  - Mitsuba 3 (variant llvm_ad_rgb: a vectorised LLVM JIT renderer), integrator 'direct' (one
    emitter sample + one BSDF sample per camera sample, combined by MIS, like pbrt-v3's
    EstimateDirect), sampler 'stratified', box pixel filter, 2 threads, at several spp;
  - when build/bin/render exists, our renderer on the same scene file at the same spp
    (`render SCENE --spp N --nthreads 2 --quiet --outfile x.exr`).
  Each renderer is compared with a high-spp reference of its OWN (so the table measures noise, not
  the small differences between the two renderers), and the two references are then compared with
  each other to show that they render the same scene (see "Cross-check" below).

  Relative MSE (the error measure of the tables):
      relMSE(x, ref) = mean over pixels p and channels c of (x_pc - ref_pc)^2 / (ref_pc^2 + 1e-2)
  The 1e-2 keeps black pixels from dominating.

  Times are seconds on 2 threads, wall clock and CPU (user + system of all threads; on a shared
  machine CPU seconds are the steadier measure). Mitsuba: mi.render() plus reading the image back into
  numpy (which forces the lazy JIT evaluation), after one warm-up render per spp so that kernel
  compilation (cached by Dr.Jit) is not counted; the median of 3 runs with different seeds. Ours: the
  render loop's own time from render's closing line ("N spp in T s"), which like Mitsuba's excludes
  parsing, loading the map and building the sampling distribution; and, for the record, the whole
  process (those plus writing the EXR). Medians of 3 runs with seeds 1, 2, 3.
  "relMSE x time" is the inverse efficiency (lower is better; for an unbiased renderer relMSE ~ 1/time,
  so the product is roughly constant across spp). The ratio of the two renderers' products is our
  relMSE divided by Mitsuba's at equal time; issue 5's target is a ratio of at most 0.5.

The scene
  Both renderers read ONE scene description: scenes/bench_city.pbrt when it exists (else the copy in
  FALLBACK_SCENE below). This script parses the small pbrt-v3 subset that the scene uses (LookAt,
  Translate/Rotate/Scale/Transform/ConcatTransform, AttributeBegin/End, Camera "perspective" fov,
  Film "image" x/yresolution, PixelFilter "box", LightSource "infinite" mapname/L/scale, Material
  "matte" Kd, Shape "sphere" radius and "trianglemesh" indices/P) and builds the same scene in Mitsuba.
  Anything else makes it stop with a message rather than compare different scenes.

  pbrt-v3 -> Mitsuba 3 conventions (verified by the "background check" in main(), which renders the
  environment alone with Mitsuba and compares it with pbrt_background(), a numpy evaluation of
  pbrt-v3's camera and light mapping; it also prints the error of the mirrored and flipped images):
  - Camera. pbrt's camera space has +x to the image's right (left-handed); Mitsuba's has +x to the
    image's LEFT. So Mitsuba's sensor to_world = (pbrt camera-to-world) * Scale(-1, 1, 1). pbrt's fov is
    on the shorter image axis: Mitsuba's fov_axis = "smaller".
  - Environment map. pbrt-v3's InfiniteAreaLight looks up (u, v) = (phi / 2pi, theta / pi) of the
    direction d = WorldToLight(w), with theta = acos(d.z), phi = atan2(d.y, d.x) in [0, 2pi): +z is the
    top row. Mitsuba's envmap uses (u, v) = (atan2(m.x, -m.z) / 2pi, acos(m.y) / pi) of its local
    direction m: +y is the top row. With m = (d.y, d.z, -d.x) the two agree, so
        Mitsuba envmap to_world = (pbrt LightToWorld) * M,   M = [[0,0,-1],[1,0,0],[0,1,0]]
    (M maps m back to d: M m = (-m.z, m.x, m.y) = (d.x, d.y, d.z)).
    Remaining difference: the two renderers' texel interpolation may differ by a fraction of a texel;
    the background check bounds it (measured: relMSE 1.7e-4, mean absolute difference 0.56%).
  - Materials. pbrt's matte (sigma 0) is Lambertian and two-sided; Mitsuba's 'diffuse' is one-sided,
    so it is wrapped in 'twosided'.

Cross-check of the two references: the per-channel mean of each reference, the relative difference of
the means, and the mean absolute pixel difference divided by the mean pixel value.

Setup (this script installs nothing):
    pip install mitsuba numpy           # Mitsuba 3 (tested with mitsuba 3.9.1)
    apt-get install libllvm19           # Debian: the LLVM that the llvm_* variants load at run time
Run (from the repository root, after `cmake --build build` for our side):
    python3 bench/mitsuba_compare.py [--spp 4,16,64,256] [--ref-spp 8192] [--render build/bin/render]
                                     [--scene scenes/bench_city.pbrt] [--threads 2] [--outdir out/mitsuba]
Samplers (--samplers S1,S2,... [--mitsuba-samplers stratified,multijitter,ldsampler]): each of our
samplers (render --sampler S) and each Mitsuba sampler at every --spp, the runs of both sides
interleaved; both references (each side's own, at --ref-spp, in two halves whose relMSE / 4 estimates
the reference's own noise, subtracted as "corrected") and then a table of the equal-spp relMSE ratio
ours / Mitsuba per sampler pair: error per sample, independent of the two renderers' speeds.
    python3 bench/mitsuba_compare.py --samplers stratified,halton,sobol,02sequence,zsobol,paddedsobol \
        --mitsuba-samplers stratified,multijitter,ldsampler --spp 16,64,256 --ref-spp 4096
References are cached in --outdir (keyed by scene text and reference spp); delete them to recompute.
Running everything from scratch takes about 15 CPU minutes (the two 8192-spp references).

Measured here (2026-12-01, quiet 2-core machine, Mitsuba 3.9.1, --spp 4,16,64,256 --ref-spp 4096;
tutorials/05-appendix-fast-paths.md, A3.11, has the table): background check relMSE 1.7e-4 (mirrored 2.0,
upside down 5.5); the references agree to 1.8e-4 in the mean and 0.28% in mean absolute difference;
at 64 spp Mitsuba 0.655-0.660 CPU s and relMSE 1.56e-3, ours 1.550-1.578 CPU s and relMSE 1.64e-3:
our relMSE at equal CPU time is 2.5x Mitsuba's (2.5-2.7x from 16 to 256 spp; target: 0.5x); the gap
is speed per sample, not accuracy per sample.
"""
import argparse
import hashlib
import math
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Used only when scenes/bench_city.pbrt does not exist; same scene family (z is up, map unrotated).
FALLBACK_SCENE = """
LookAt 0 -6 2.5   0 0 0.8   0 0 1
Camera "perspective" "float fov" [ 35 ]
Film "image" "integer xresolution" [ 320 ] "integer yresolution" [ 240 ]
PixelFilter "box"
Sampler "stratified" "integer xsamples" [ 8 ] "integer ysamples" [ 8 ]
Integrator "directlighting"
WorldBegin
LightSource "infinite" "string mapname" [ "../data/envmaps/city.hdr" ]
AttributeBegin
  Material "matte" "rgb Kd" [ 0.7 0.7 0.7 ]
  Translate 0 0 1
  Shape "sphere" "float radius" [ 1 ]
AttributeEnd
AttributeBegin
  Material "matte" "rgb Kd" [ 0.5 0.5 0.5 ]
  Shape "trianglemesh" "integer indices" [ 0 1 2 0 2 3 ]
        "point P" [ -20 -20 0  20 -20 0  20 20 0  -20 20 0 ]
AttributeEnd
WorldEnd
"""


def die(msg):
    sys.stderr.write("mitsuba_compare: " + msg + "\n")
    sys.exit(1)


# --------------------------------------------------------------------------------------------------
# A tiny pbrt-v3 parser for the subset above (4x4 matrices as nested lists, row-major, column vectors)
# --------------------------------------------------------------------------------------------------
def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def mat_identity():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def mat_inverse(m):
    import numpy as np
    return np.linalg.inv(np.array(m, dtype=float)).tolist()


def mat_translate(x, y, z):
    m = mat_identity()
    m[0][3], m[1][3], m[2][3] = x, y, z
    return m


def mat_scale(x, y, z):
    m = mat_identity()
    m[0][0], m[1][1], m[2][2] = x, y, z
    return m


def mat_rotate(deg, x, y, z):
    # pbrt-v3 Rotate(theta, axis): Rodrigues' rotation about the normalised axis.
    n = math.sqrt(x * x + y * y + z * z)
    a = [x / n, y / n, z / n]
    s, c = math.sin(math.radians(deg)), math.cos(math.radians(deg))
    m = mat_identity()
    m[0][0] = a[0] * a[0] + (1 - a[0] * a[0]) * c
    m[0][1] = a[0] * a[1] * (1 - c) - a[2] * s
    m[0][2] = a[0] * a[2] * (1 - c) + a[1] * s
    m[1][0] = a[0] * a[1] * (1 - c) + a[2] * s
    m[1][1] = a[1] * a[1] + (1 - a[1] * a[1]) * c
    m[1][2] = a[1] * a[2] * (1 - c) - a[0] * s
    m[2][0] = a[0] * a[2] * (1 - c) - a[1] * s
    m[2][1] = a[1] * a[2] * (1 - c) + a[0] * s
    m[2][2] = a[2] * a[2] + (1 - a[2] * a[2]) * c
    return m


def mat_lookat(ex, ey, ez, lx, ly, lz, ux, uy, uz):
    # pbrt-v3 LookAt: builds camera-to-world (right = cross(up, dir), newUp = cross(dir, right)) and
    # returns its inverse, world-to-camera, which is multiplied into the CTM.
    def norm(v):
        n = math.sqrt(sum(t * t for t in v))
        return [t / n for t in v]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    d = norm([lx - ex, ly - ey, lz - ez])
    right = norm(cross(norm([ux, uy, uz]), d))
    up = cross(d, right)
    c2w = [[right[0], up[0], d[0], ex], [right[1], up[1], d[1], ey],
           [right[2], up[2], d[2], ez], [0, 0, 0, 1]]
    return mat_inverse(c2w)


def tokenize(text):
    toks = []
    for m in re.finditer(r'"[^"]*"|\[|\]|[^\s\[\]"#]+|#[^\n]*', text):
        t = m.group(0)
        if t.startswith("#"):
            continue
        toks.append(t)
    return toks


def parse_params(toks, i):
    """Reads '"type name" value-or-[values]' pairs; returns (dict name -> (type, [values]), i)."""
    params = {}
    while i < len(toks) and toks[i].startswith('"') and len(toks[i][1:-1].split()) == 2:
        typ, name = toks[i][1:-1].split()
        i += 1
        vals = []
        if toks[i] == "[":
            i += 1
            while toks[i] != "]":
                vals.append(toks[i])
                i += 1
            i += 1
        else:
            vals.append(toks[i])
            i += 1
        if typ in ("float", "integer", "point", "point3", "normal", "rgb", "color", "vector"):
            vals = [float(v) for v in vals]
        else:
            vals = [v.strip('"') for v in vals]
        params[name] = (typ, vals)
    return params, i


def parse_pbrt(path, text):
    base = os.path.dirname(os.path.abspath(path))
    toks = tokenize(text)
    ctm, stack = mat_identity(), []
    material = {"Kd": [0.5, 0.5, 0.5]}  # pbrt-v3's default material: matte, Kd 0.5
    scene = {"camera_to_world": None, "fov": 90.0, "xres": 1280, "yres": 720, "lights": [],
             "shapes": [], "filter": "box"}
    i = 0

    def nums(n):
        nonlocal i
        v = [float(t) for t in toks[i:i + n]]
        i += n
        return v

    while i < len(toks):
        d = toks[i]
        i += 1
        if d == "LookAt":
            ctm = mat_mul(ctm, mat_lookat(*nums(9)))
        elif d == "Translate":
            ctm = mat_mul(ctm, mat_translate(*nums(3)))
        elif d == "Scale":
            ctm = mat_mul(ctm, mat_scale(*nums(3)))
        elif d == "Rotate":
            ctm = mat_mul(ctm, mat_rotate(*nums(4)))
        elif d in ("Transform", "ConcatTransform"):
            assert toks[i] == "["
            i += 1
            v = nums(16)
            i += 1
            m = [[v[c * 4 + r] for c in range(4)] for r in range(4)]  # pbrt lists column-major
            ctm = m if d == "Transform" else mat_mul(ctm, m)
        elif d == "Identity":
            ctm = mat_identity()
        elif d in ("AttributeBegin", "TransformBegin"):
            stack.append((ctm, dict(material)))
        elif d in ("AttributeEnd", "TransformEnd"):
            ctm, mat = stack.pop()
            if d == "AttributeEnd":
                material = mat
        elif d == "WorldBegin":
            ctm = mat_identity()
        elif d == "WorldEnd":
            pass
        else:
            kind = toks[i].strip('"')
            i += 1
            p, i = parse_params(toks, i)
            if d == "Camera":
                if kind != "perspective":
                    die("%s: Camera %s not supported here" % (path, kind))
                scene["camera_to_world"] = mat_inverse(ctm)
                scene["fov"] = p.get("fov", ("float", [90.0]))[1][0]
            elif d == "Film":
                scene["xres"] = int(p.get("xresolution", ("", [1280]))[1][0])
                scene["yres"] = int(p.get("yresolution", ("", [720]))[1][0])
            elif d == "PixelFilter":
                scene["filter"] = kind
            elif d in ("Sampler", "Integrator"):
                scene[d.lower()] = kind
            elif d == "LightSource":
                if kind != "infinite":
                    die("%s: LightSource %s not supported here" % (path, kind))
                mapname = p.get("mapname", ("", [""]))[1][0]
                if mapname and not os.path.isabs(mapname):
                    mapname = os.path.join(base, mapname)
                scale = p.get("scale", ("", [1, 1, 1]))[1]
                L = p.get("L", ("", [1, 1, 1]))[1]
                if len(scale) == 1:
                    scale = scale * 3
                scene["lights"].append({"to_world": ctm, "mapname": mapname,
                                        "scale": [scale[k] * L[k] for k in range(3)]})
            elif d == "Material":
                if kind != "matte" or ("Kd" in p and p["Kd"][0] not in ("rgb", "color")):
                    die("%s: only Material \"matte\" with an rgb Kd is supported here" % path)
                material = {"Kd": p.get("Kd", ("", [0.5, 0.5, 0.5]))[1]}
            elif d == "Shape":
                if kind == "sphere":
                    r = p.get("radius", ("", [1.0]))[1][0]
                    scene["shapes"].append({"type": "sphere", "to_world": ctm, "radius": r,
                                            "Kd": material["Kd"]})
                elif kind == "trianglemesh":
                    scene["shapes"].append({"type": "trianglemesh", "to_world": ctm,
                                            "indices": [int(v) for v in p["indices"][1]],
                                            "P": p["P"][1], "Kd": material["Kd"]})
                else:
                    die("%s: Shape %s not supported here" % (path, kind))
            else:
                die("%s: directive %s not supported here" % (path, d))
    if scene["camera_to_world"] is None:
        die("%s: no Camera" % path)
    return scene


# --------------------------------------------------------------------------------------------------
# Mitsuba side
# --------------------------------------------------------------------------------------------------
M_PBRT_TO_MITSUBA_ENV = [[0, 0, -1, 0], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 1]]


def mitsuba_scene_dict(mi, sc, spp, workdir, with_shapes=True, sampler="stratified"):
    T = mi.ScalarTransform4f
    d = {"type": "scene",
         "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 1},
         "sensor": {"type": "perspective", "fov": sc["fov"], "fov_axis": "smaller",
                    # pbrt camera space (+x right) -> Mitsuba camera space (+x left)
                    "to_world": T(mat_mul(sc["camera_to_world"], mat_scale(-1, 1, 1))),
                    "film": {"type": "hdrfilm", "width": sc["xres"], "height": sc["yres"],
                             "rfilter": {"type": "box"}, "pixel_format": "rgb"},
                    "sampler": {"type": sampler, "sample_count": spp}}}
    if sc["filter"] != "box":
        die("PixelFilter %s: only box is compared here" % sc["filter"])
    for k, light in enumerate(sc["lights"]):
        e = {"type": "envmap", "to_world": T(mat_mul(light["to_world"], M_PBRT_TO_MITSUBA_ENV))}
        s = light["scale"]
        if light["mapname"]:
            e["filename"] = light["mapname"]
            if not (s[0] == s[1] == s[2]):
                die("a coloured scale on an image map is not compared here")
            e["scale"] = s[0]
        else:
            e = {"type": "constant", "radiance": {"type": "rgb", "value": s}}
        d["light%d" % k] = e
    if not with_shapes:
        return d
    for k, shp in enumerate(sc["shapes"]):
        bsdf = {"type": "twosided", "bsdf": {"type": "diffuse",
                                             "reflectance": {"type": "rgb", "value": shp["Kd"]}}}
        if shp["type"] == "sphere":
            d["shape%d" % k] = {"type": "sphere", "bsdf": bsdf,
                                "to_world": T(mat_mul(shp["to_world"],
                                                      mat_scale(shp["radius"], shp["radius"],
                                                                shp["radius"])))}
        else:
            P, idx = shp["P"], shp["indices"]
            ply = os.path.join(workdir, "mesh%d.ply" % k)
            with open(ply, "w") as f:
                f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\n"
                        "property float y\nproperty float z\nelement face %d\n"
                        "property list uchar int vertex_indices\nend_header\n"
                        % (len(P) // 3, len(idx) // 3))
                for v in range(len(P) // 3):
                    f.write("%.9g %.9g %.9g\n" % tuple(P[3 * v:3 * v + 3]))
                for t in range(len(idx) // 3):
                    f.write("3 %d %d %d\n" % tuple(idx[3 * t:3 * t + 3]))
            d["shape%d" % k] = {"type": "ply", "filename": ply, "bsdf": bsdf,
                                "face_normals": True, "to_world": T(shp["to_world"])}
    return d


def relmse(x, ref):
    import numpy as np
    return float(np.mean((x - ref) ** 2 / (ref * ref + 1e-2)))


class MitsubaRunner:
    def __init__(self, sc, threads, workdir):
        import drjit as dr
        import mitsuba as mi
        mi.set_variant("llvm_ad_rgb")
        dr.set_thread_count(threads)
        self.mi, self.dr, self.sc, self.workdir = mi, dr, sc, workdir
        self.scenes = {}

    def scene(self, spp, with_shapes=True, sampler="stratified"):
        key = (spp, with_shapes, sampler)
        if key not in self.scenes:
            self.scenes[key] = self.mi.load_dict(
                mitsuba_scene_dict(self.mi, self.sc, spp, self.workdir, with_shapes, sampler))
        return self.scenes[key]

    def render(self, spp, seed, with_shapes=True, sampler="stratified"):
        import numpy as np
        scene = self.scene(spp, with_shapes, sampler)
        r0 = resource.getrusage(resource.RUSAGE_SELF)
        t0 = time.perf_counter()
        img = self.mi.render(scene, spp=spp, seed=seed)
        arr = np.array(img, dtype=np.float64)  # forces evaluation of the JIT kernels
        t = time.perf_counter() - t0
        r1 = resource.getrusage(resource.RUSAGE_SELF)
        self.last_cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        return arr, t


def read_image(path):
    import numpy as np
    import mitsuba as mi
    return np.array(mi.Bitmap(path), dtype=np.float64)[..., :3]


def pbrt_background(sc, envpath, sub=4):
    """pbrt-v3's camera and InfiniteAreaLight mapping evaluated in numpy, for the orientation check:
    bilinear texel lookup with pbrt's s * w - 0.5 convention (Repeat in u, Clamp in v), averaged over
    sub x sub stratified positions in each pixel (the box filter)."""
    import numpy as np
    w, h = sc["xres"], sc["yres"]
    env = read_image(envpath)
    H, W = env.shape[:2]
    aspect = w / h
    sw = (aspect, 1.0) if aspect > 1 else (1.0, 1.0 / aspect)
    t = math.tan(math.radians(sc["fov"]) / 2)
    c2w = np.array(sc["camera_to_world"])[:3, :3]
    light = sc["lights"][0]
    w2l = np.linalg.inv(np.array(light["to_world"])[:3, :3])
    acc = np.zeros((h, w, 3))
    for sy_ in range(sub):
        for sx_ in range(sub):
            px, py = np.meshgrid(np.arange(w) + (sx_ + 0.5) / sub, np.arange(h) + (sy_ + 0.5) / sub)
            sx = -sw[0] + 2 * sw[0] * px / w           # raster x -> screen x (left to right)
            sy = sw[1] - 2 * sw[1] * py / h            # raster y (down) -> screen y (up)
            dc = np.stack([sx * t, sy * t, np.ones_like(sx)], axis=-1)
            dl = (dc @ c2w.T) @ w2l.T
            dl /= np.linalg.norm(dl, axis=-1, keepdims=True)
            theta = np.arccos(np.clip(dl[..., 2], -1, 1))
            phi = np.arctan2(dl[..., 1], dl[..., 0])
            phi = np.where(phi < 0, phi + 2 * math.pi, phi)
            s_ = phi / (2 * math.pi) * W - 0.5
            t_ = theta / math.pi * H - 0.5
            x0, y0 = np.floor(s_).astype(int), np.floor(t_).astype(int)
            fx, fy = (s_ - x0)[..., None], (t_ - y0)[..., None]
            x1, y1 = (x0 + 1) % W, np.clip(y0 + 1, 0, H - 1)
            x0, y0 = x0 % W, np.clip(y0, 0, H - 1)
            acc += ((1 - fy) * ((1 - fx) * env[y0, x0] + fx * env[y0, x1]) +
                    fy * ((1 - fx) * env[y1, x0] + fx * env[y1, x1]))
    return acc / (sub * sub) * np.array(light["scale"])


# --------------------------------------------------------------------------------------------------
# Pixel classes: lit and shadowed pixels reported apart (issue 22)
# --------------------------------------------------------------------------------------------------
def sun_direction(sc):
    """the world direction (unit, towards the light) of the first map's brightest texel's centre, by
    pbrt-v3's mapping (row v: theta = pi (v + 1/2) / H, column u: phi = 2 pi (u + 1/2) / W, in the
    light's space, then its LightToWorld)"""
    import numpy as np
    light = sc["lights"][0]
    env = read_image(light["mapname"])
    H, W = env.shape[:2]
    v, u = np.unravel_index(np.argmax(env @ np.array([0.2126, 0.7152, 0.0722])), (H, W))
    th, ph = math.pi * (v + 0.5) / H, 2 * math.pi * (u + 0.5) / W
    d = np.array(light["to_world"])[:3, :3] @ np.array([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
    return d / np.linalg.norm(d)


def ray_cast(sc, o, d):
    """nearest hit distance (inf: none) of rays o + t d (arrays (..., 3)) against the parsed scene's
    spheres (any affine to_world: solved in object space) and triangle meshes (P by to_world), t > 1e-4"""
    import numpy as np
    best = np.full(o.shape[:-1], np.inf)
    for shp in sc["shapes"]:
        M = np.array(shp["to_world"])
        if shp["type"] == "sphere":
            Mi = np.linalg.inv(M)
            oo, dd = o @ Mi[:3, :3].T + Mi[:3, 3], d @ Mi[:3, :3].T
            A, B = (dd * dd).sum(-1), 2 * (dd * oo).sum(-1)
            C = (oo * oo).sum(-1) - shp["radius"] ** 2
            disc = B * B - 4 * A * C
            sq = np.sqrt(np.maximum(disc, 0))
            for t in ((-B - sq) / (2 * A), (-B + sq) / (2 * A)):
                ok = (disc >= 0) & (t > 1e-4) & (t < best)
                best = np.where(ok, t, best)
        else:
            P = np.array(shp["P"], dtype=np.float64).reshape(-1, 3) @ M[:3, :3].T + M[:3, 3]
            idx = shp["indices"]
            for k in range(0, len(idx), 3):  # Moller-Trumbore
                p0, p1, p2 = P[idx[k]], P[idx[k + 1]], P[idx[k + 2]]
                e1, e2 = p1 - p0, p2 - p0
                pv = np.cross(d, e2)
                det = (pv * e1).sum(-1)
                det = np.where(np.abs(det) < 1e-12, 1e-12, det)
                tv = o - p0
                uu = (tv * pv).sum(-1) / det
                qv = np.cross(tv, e1)
                vv = (d * qv).sum(-1) / det
                t = (e2 * qv).sum(-1) / det
                ok = (uu >= 0) & (vv >= 0) & (uu + vv <= 1) & (t > 1e-4) & (t < best)
                best = np.where(ok, t, best)
    return best


def pixel_classes(sc, sub=4):
    """{"lit", "shadowed"}: boolean (h, w) masks from the scene's own geometry (numpy ray casting, not
    either renderer): at sub x sub positions in each pixel the camera ray's hit and a shadow ray towards
    the map's brightest texel (sun_direction); "lit": every position hits and sees the sun, "shadowed":
    every position hits and none sees it. Pixels of the background, of silhouettes and of penumbrae
    (mixed positions) are in neither."""
    import numpy as np
    w, h = sc["xres"], sc["yres"]
    aspect = w / h
    sw = (aspect, 1.0) if aspect > 1 else (1.0, 1.0 / aspect)
    t = math.tan(math.radians(sc["fov"]) / 2)
    c2w = np.array(sc["camera_to_world"])
    sun = sun_direction(sc)
    hit_all, lit_all, lit_none = np.ones((h, w), bool), np.ones((h, w), bool), np.ones((h, w), bool)
    for sy_ in range(sub):
        for sx_ in range(sub):
            px, py = np.meshgrid(np.arange(w) + (sx_ + 0.5) / sub, np.arange(h) + (sy_ + 0.5) / sub)
            dc = np.stack([(-sw[0] + 2 * sw[0] * px / w) * t, (sw[1] - 2 * sw[1] * py / h) * t, np.ones_like(px)], -1)
            d = dc @ c2w[:3, :3].T
            d /= np.linalg.norm(d, axis=-1, keepdims=True)
            o = np.broadcast_to(c2w[:3, 3], d.shape)
            th = ray_cast(sc, o, d)
            hit = np.isfinite(th)
            p = o + d * np.where(hit, th, 0)[..., None]
            ts = ray_cast(sc, p + 1e-4 * sun, np.broadcast_to(sun, d.shape))
            sees = hit & ~np.isfinite(ts)
            hit_all &= hit
            lit_all &= sees
            lit_none &= ~sees
    return {"lit": hit_all & lit_all, "shadowed": hit_all & lit_none}


def read_mask(path, w, h):
    """--mask: a PGM (P2 or P5, 8 or 16 bits) or PFM of w x h pixels (PFM: first channel; rows bottom
    to top as the format says); {"lit": value <= 0.5 of the maximum (PGM) or <= 0.5 (PFM), "shadowed":
    above}"""
    import numpy as np
    with open(path, "rb") as f:
        data = f.read()
    magic = data[:2]
    if magic in (b"P2", b"P5"):
        toks, pos = [], 2
        while len(toks) < 3:  # width, height, maxval (comments skipped)
            m = re.compile(rb"\s*(#[^\n]*\n\s*)*(\d+)").match(data, pos)
            if not m:
                die("%s: not a PGM header" % path)
            toks.append(int(m.group(2)))
            pos = m.end()
        mw, mh, maxval = toks
        if magic == b"P2":
            v = np.array(data[pos:].split()[:mw * mh], dtype=np.float64)
        else:
            pos += 1
            if len(data) - pos < mw * mh * (2 if maxval > 255 else 1):
                die("%s: truncated PGM" % path)
            v = np.frombuffer(data, dtype=">u2" if maxval > 255 else np.uint8, count=mw * mh, offset=pos).astype(np.float64)
        if v.size != mw * mh:
            die("%s: truncated PGM" % path)
        img = v.reshape(mh, mw) / max(maxval, 1)
    elif magic in (b"Pf", b"PF"):
        lines, pos = [], 0
        try:
            for _ in range(3):
                e = data.index(b"\n", pos)
                lines.append(data[pos:e].decode().strip())
                pos = e + 1
            mw, mh = map(int, lines[1].split())
            sc_ = float(lines[2])
        except ValueError:
            die("%s: not a PFM header" % path)
        nc = 1 if magic == b"Pf" else 3
        if len(data) - pos < mw * mh * nc * 4:
            die("%s: truncated PFM" % path)
        v = np.frombuffer(data, dtype="<f4" if sc_ < 0 else ">f4", count=mw * mh * nc, offset=pos)
        img = v.reshape(mh, mw, nc)[::-1, :, 0].astype(np.float64)
    else:
        die("%s: --mask takes a PGM (P2/P5) or PFM file" % path)
    if (mw, mh) != (w, h):
        die("%s: the mask is %dx%d, the images %dx%d" % (path, mw, mh, w, h))
    return {"lit": img <= 0.5, "shadowed": img > 0.5}


def relvar_by_class(imgs, classes):
    """relvar over each class's pixels ({name: value})"""
    import numpy as np
    a = np.stack(imgs)
    m = a.mean(axis=0)
    q = a.var(axis=0, ddof=1) / (m * m + 1e-2)
    return {k: float(np.mean(q[c])) if c.any() else float("nan") for k, c in classes.items()}


def write_background_scene(text, scene_dir, path):
    """The scene file with its shapes removed (for our renderer's background image), its map path
    made absolute so that the copy can live elsewhere."""
    def absolute(m):
        name = m.group(2)
        return m.group(1) + (name if os.path.isabs(name) else os.path.join(scene_dir, name)) + '"'
    text = re.sub(r'("string mapname"\s*\[?\s*")([^"]*)"', absolute, text)
    out, skip = [], False
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("Shape"):
            skip = True
            continue
        if skip and (s.startswith('"') or s.startswith("[") or (s and s[0] in "-0123456789]")):
            continue
        skip = False
        out.append(line)
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def fmt_table(rows, header):
    widths = [max(len(str(r[k])) for r in rows + [header]) for k in range(len(header))]
    lines = ["  ".join(str(h).rjust(widths[k]) for k, h in enumerate(header))]
    for r in rows:
        lines.append("  ".join(str(v).rjust(widths[k]) for k, v in enumerate(r)))
    return "\n".join(lines)


def run_render(args, scene_file, spp, out, seed=0, sampler=None):
    """our renderer on scene_file; returns (image, wall s, render-loop s, CPU s)"""
    cmd = [args.render, scene_file, "--spp", str(spp), "--nthreads", str(args.threads),
           "--quiet", "--seed", str(seed), "--outfile", out]
    if sampler:
        cmd += ["--sampler", sampler]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    t = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        die("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()))
    m = re.search(r"spp in ([0-9.eE+-]+) s", p.stdout + p.stderr)
    return (read_image(out), t, (float(m.group(1)) if m else float("nan")),
            (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime))


def sampler_mode(args, mr, scene_path, tag, spps, workdir):
    """--samplers: relMSE per sample of each of our samplers against each Mitsuba sampler.

    For each spp and run (seeds 1..runs), interleaved: every Mitsuba sampler, then every one of ours.
    Each renderer is compared with its own reference (Mitsuba: its stratified sampler at --ref-spp;
    ours: the scene's sampler at --ref-spp), so the two renderers' conventions (half-texel offsets,
    filtering) do not count. Each reference is rendered as two halves with different seeds: its own
    noise, relMSE(half 1, half 2) / 4, is printed and subtracted ("corrected"): at 256 spp the
    low-discrepancy samplers' error is not far above it. The ratio table is ours / Mitsuba at equal
    spp (error per sample), corrected values."""
    import numpy as np
    ours = [x for x in args.samplers.split(",") if x]
    mits = [x for x in args.mitsuba_samplers.split(",") if x]
    # Mitsuba reference noise: two halves of --ref-spp (cached like the reference)
    halves = []
    for h in range(2):
        hp = os.path.join(args.outdir, "mitsuba_ref_half%d_%s.npy" % (h, tag))
        if os.path.exists(hp):
            halves.append(np.load(hp))
            continue
        chunk = min(1024, args.ref_spp // 2)
        n = max(1, (args.ref_spp // 2) // chunk)
        acc = None
        for k in range(n):
            img, _ = mr.render(chunk, 5000 + 100 * h + k)
            acc = img if acc is None else acc + img
        halves.append(acc / n)
        np.save(hp, halves[-1])
    mref = 0.5 * (halves[0] + halves[1])
    mnoise = relmse(halves[0], halves[1]) / 4
    ohalves = []
    for h in range(2):
        op = os.path.join(args.outdir, "ours_ref_half%d_%s.exr" % (h, tag))
        if not os.path.exists(op):
            t0 = time.perf_counter()
            run_render(args, scene_path, args.ref_spp // 2, op, seed=12345 + h)
            print("our reference half %d: %d spp in %.1f s" % (h, args.ref_spp // 2, time.perf_counter() - t0))
        ohalves.append(read_image(op))
    oref = 0.5 * (ohalves[0] + ohalves[1])
    onoise = relmse(ohalves[0], ohalves[1]) / 4
    print("references (%d spp each, as two halves): noise Mitsuba %.3g, ours %.3g" % (args.ref_spp, mnoise, onoise))
    res = {}  # (side, sampler, spp) -> lists of (relMSE, render s, CPU s)
    for spp in spps:
        for ms in mits:
            mr.render(spp, 7, sampler=ms)  # warm-up: JIT compilation
        for r in range(args.runs):
            for ms in mits:
                img, t = mr.render(spp, r + 1, sampler=ms)
                res.setdefault(("mitsuba", ms, spp), []).append((relmse(img, mref), t, mr.last_cpu))
            for os_ in ours:
                img, t, tr, c = run_render(args, scene_path, spp, os.path.join(workdir, "o.exr"), seed=r + 1,
                                           sampler=os_)
                res.setdefault(("ours", os_, spp), []).append((relmse(img, oref), tr, c))
    rows = []
    for (side, smp, spp), v in sorted(res.items(), key=lambda kv: (kv[0][2], kv[0][0], kv[0][1])):
        e = statistics.mean(x[0] for x in v)
        t = statistics.median(x[1] for x in v)
        c = statistics.median(x[2] for x in v)
        noise = mnoise if side == "mitsuba" else onoise
        rows.append([side, smp, spp, "%.3g" % e, "%.3g" % (e - noise), "%.3f" % t, "%.3f" % c])
    print("\nrelMSE against each renderer's own reference (mean of %d runs), render wall s and CPU s (medians):"
          % args.runs)
    print(fmt_table(rows, ["renderer", "sampler", "spp", "relMSE", "corrected", "render s", "CPU s"]))
    print("\nequal-spp relMSE ratio ours / Mitsuba (corrected values; < 1: less error per sample than Mitsuba):")
    header = ["ours \\ Mitsuba", "spp"] + mits
    rows = []
    for os_ in ours:
        for spp in spps:
            eo = statistics.mean(x[0] for x in res[("ours", os_, spp)]) - onoise
            row = [os_, spp]
            for ms in mits:
                em = statistics.mean(x[0] for x in res[("mitsuba", ms, spp)]) - mnoise
                row.append("%.2f" % (eo / em) if em > 0 else "-")
            rows.append(row)
    print(fmt_table(rows, header))


# --------------------------------------------------------------------------------------------------
# Variance mode (the default): relative variance across seeds, equal spp and equal CPU time
# --------------------------------------------------------------------------------------------------
VAR_SCENES = [("sun", "bench_city.pbrt"), ("smooth", "bench_studio.pbrt")]


def scene_variant(path, res=None, integrator="direct", nsamples=1, maxdepth=5):
    """The scene file's text with its map path made absolute, the resolution replaced (res = (w, h)),
    the Integrator replaced (directlighting or path with maxdepth), and the infinite light's
    "integer samples" (pbrt-v3's nsamples: light + BSDF sample pairs per camera sample)."""
    with open(path) as f:
        text = f.read()
    base = os.path.dirname(os.path.abspath(path))
    text = re.sub(r'("string mapname"\s*\[?\s*")([^"]*)"',
                  lambda m: m.group(1) + (m.group(2) if os.path.isabs(m.group(2)) else os.path.join(base, m.group(2))) + '"',
                  text)
    if res:
        text = re.sub(r'"integer xresolution"\s*\[?\s*\d+\s*\]?', '"integer xresolution" [ %d ]' % res[0], text)
        text = re.sub(r'"integer yresolution"\s*\[?\s*\d+\s*\]?', '"integer yresolution" [ %d ]' % res[1], text)
    integ = ('Integrator "directlighting" "integer maxdepth" [ %d ]' % maxdepth if integrator == "direct"
             else 'Integrator "path" "integer maxdepth" [ %d ]' % maxdepth)
    text = re.sub(r'^Integrator.*$', integ, text, flags=re.M)
    if nsamples != 1:
        text = re.sub(r'(LightSource "infinite")', r'\1 "integer samples" [ %d ]' % nsamples, text)
    return text


def relvar(imgs):
    """mean over pixels and channels of the variance across seeds over (mean^2 + 1e-2)"""
    import numpy as np
    a = np.stack(imgs)
    m = a.mean(axis=0)
    v = a.var(axis=0, ddof=1)
    return float(np.mean(v / (m * m + 1e-2)))


class OursRunner:
    def __init__(self, args, workdir):
        self.args, self.workdir = args, workdir
        self.fixed = {}

    def render(self, scene_file, spp, seed, sampler, env_sampling=None, extra=()):
        """(image, CPU s of the render loop, CPU s of the whole process); the fixed costs from --stats;
        extra: more render options (--variant)"""
        out = os.path.join(self.workdir, "o.exr")
        cmd = [self.args.render, scene_file, "--spp", str(spp), "--nthreads", str(self.args.threads),
               "--quiet", "--stats", "--seed", str(seed), "--outfile", out, "--sampler", sampler]
        if env_sampling:
            cmd += ["--env-sampling", env_sampling]
        cmd += list(extra)
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        p = subprocess.run(cmd, capture_output=True, text=True)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if p.returncode != 0:
            die("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()))
        cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        txt = p.stdout + p.stderr

        def num(rx):
            m = re.search(rx, txt)
            return float(m.group(1)) if m else 0.0
        # single-threaded setup: parsing with the map load, Embree's build, the sampling tables
        fx = {"parse (map load)": num(r"parse\s+([0-9.]+) s"), "embree build": num(r"embree build\s+([0-9.]+) s"),
              "sampling tables": num(r"env distribution\s+\S+\s+([0-9.]+) s")}
        self.fixed.setdefault(scene_file, fx)
        loop_cpu = num(r"render\s+[0-9.]+ s\s+\(CPU ([0-9.]+) s\)")  # the render loop's CPU seconds, all threads
        return read_image(out), loop_cpu if loop_cpu > 0 else cpu - sum(fx.values()), cpu


class MiVarRunner:
    def __init__(self, threads, workdir, variant):
        import drjit as dr
        import mitsuba as mi
        mi.set_variant(variant)
        dr.set_thread_count(threads)
        self.mi, self.dr, self.workdir, self.variant = mi, dr, workdir, variant
        self.scenes, self.load_s, self.compile_s = {}, {}, {}

    def scene(self, sc_key, sc, integ, ns, sampler, maxdepth):
        key = (sc_key, integ, ns, sampler)
        if key not in self.scenes:
            d = mitsuba_scene_dict(self.mi, sc, 16, self.workdir, True, sampler)
            if integ == "direct":
                d["integrator"] = {"type": "direct", "emitter_samples": ns, "bsdf_samples": ns}
            else:  # pbrt's maxdepth counts bounces; Mitsuba's max_depth counts path segments
                d["integrator"] = {"type": "path", "max_depth": maxdepth + 1, "rr_depth": 4}
            t0 = time.perf_counter()
            self.scenes[key] = self.mi.load_dict(d)
            self.load_s.setdefault(sc_key, time.perf_counter() - t0)
        return self.scenes[key]

    def render(self, scene, spp, seed):
        import numpy as np
        r0 = resource.getrusage(resource.RUSAGE_SELF)
        img = self.mi.render(scene, spp=spp, seed=seed)
        arr = np.array(img, dtype=np.float64)  # forces the lazy JIT evaluation
        r1 = resource.getrusage(resource.RUSAGE_SELF)
        return arr, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)

    def drop(self, sc_key):
        for k in [k for k in self.scenes if k[0] == sc_key]:
            del self.scenes[k]
        import gc
        gc.collect()


def variance_mode(args):
    """Issue 13's equal-spp ratio and issue 14's equal-time cost, from the variance across seeds."""
    import numpy as np
    quick = args.quick
    res = (160, 120) if quick else (tuple(args.var_res) if args.var_res else None)
    spps = [16, 64] if quick else [16, 64, 256]
    if args.var_spp:
        spps = [int(x) for x in args.var_spp.split(",")]
    seeds = 2 if quick else args.seeds
    ld = args.our_sampler
    integs = [i for i in args.var_integrators.split(",") if i]
    var_integs = [i for i in args.variant_integrators.split(",") if i]  # the integrators the --variant options run on
    var_scenes = [(k, f) for k, f in VAR_SCENES if k in args.var_maps.split(",")]
    for i in integs + var_integs:
        if i not in ("direct", "path"):
            die("--var-integrators / --variant-integrators: direct or path, not %r" % i)
    if not var_scenes:
        die("--var-maps: none of %s" % ",".join(k for k, _ in VAR_SCENES))
    maxdepth = args.maxdepth
    workdir = tempfile.mkdtemp(prefix="el_mitsuba_var_")
    variant = "llvm_ad_rgb"
    try:
        import mitsuba as mi
        if variant not in mi.variants():
            variant = "scalar_rgb"
        mi.set_variant(variant)
    except Exception:  # llvm not loadable
        variant = "scalar_rgb"
    mr = MiVarRunner(args.threads, workdir, variant)
    ours = OursRunner(args, workdir)
    # the configurations: (side, name, integrator filter, sampler, light/BSDF pairs)
    cfgs = [("mitsuba", "independent 1/1", None, "independent", 1),
            ("mitsuba", "multijitter 1/1", None, "multijitter", 1),
            ("mitsuba", "multijitter 2/2", "direct", "multijitter", 2),
            ("mitsuba", "stratified 1/1", None, "stratified", 1),
            ("ours", "random 1/1", None, "random", 1),
            ("ours", "%s 1/1" % ld, None, ld, 1),
            ("ours", "%s 2/2" % ld, "direct", ld, 2)]
    if not quick:
        cfgs += [("mitsuba", "multijitter 4/4", "direct", "multijitter", 4)]
        if not args.no_stratified_splitting:
            cfgs += [("mitsuba", "stratified 2/2", "direct", "stratified", 2),
                     ("mitsuba", "stratified 4/4", "direct", "stratified", 4)]
    if args.map_too:
        cfgs += [("ours", "%s 1/1, map alone" % ld, None, ld, 1)]
    variant_opts = {}  # --variant NAME=OPTIONS: ours with more render options, --variant-integrators, both samplers
    for v in args.variant:
        name, _, opts = v.partition("=")
        for smp in ("random", ld):
            cfgs += [("ours", "%s 1/1 %s" % (smp, name), i, smp, 1) for i in var_integs]
            variant_opts["%s 1/1 %s" % (smp, name)] = opts.split()
    print("variance mode: %s x %s, spp %s, %d seeds per configuration, %d threads, path maxdepth %d; Mitsuba %s %s; "
          "load average %.2f %.2f %.2f" % (("%dx%d" % res if res else "scene resolution", ",".join(n for n, _ in var_scenes),
                                            ",".join(map(str, spps)), seeds, args.threads, maxdepth, mi.__version__, variant)
                                           + os.getloadavg()))
    t_start = time.time()
    regions = {}  # (scene) -> {"lit": mask, "shadowed": mask}: --regions (the scene's geometry) or --mask FILE
    results = {}  # (scene, integ, spp, side, name) -> (relvar, median CPU s, mean image)
    by_region = {}  # the same keys -> {"lit": relvar, "shadowed": relvar}
    for sc_key, fname in var_scenes:
        path = os.path.join(ROOT, "scenes", fname)
        for integ in integs:
            files = {}
            for ns in (1, 2, 4):
                files[ns] = os.path.join(workdir, "%s_%s_%d.pbrt" % (sc_key, integ, ns))
                with open(files[ns], "w") as f:
                    f.write(scene_variant(path, res, integ, ns, maxdepth))
            sc = parse_pbrt(files[1], scene_variant(path, res, integ, 1, maxdepth))
            if (args.regions or args.mask) and sc_key not in regions:
                regions[sc_key] = read_mask(args.mask, sc["xres"], sc["yres"]) if args.mask else pixel_classes(sc)
                print("  %s: %s" % (sc_key, ", ".join("%s %d pixels" % (k, int(v.sum())) for k, v in regions[sc_key].items())))
            mine = [c for c in cfgs if c[2] in (None, integ)]
            for spp in spps:
                imgs, cpus = {}, {}
                for c in mine:  # Mitsuba's warm-up render (JIT compilation, timed apart; once per configuration)
                    if c[0] == "mitsuba" and spp == spps[0]:
                        t0 = time.perf_counter()
                        mr.render(mr.scene(sc_key, sc, integ, c[4], c[3], maxdepth), spp, 999)
                        mr.compile_s.setdefault((sc_key, integ, c[1]), time.perf_counter() - t0)
                for r in range(seeds):  # interleaved: every configuration once per round
                    for c in mine:
                        if c[0] == "mitsuba":
                            img, cpu = mr.render(mr.scene(sc_key, sc, integ, c[4], c[3], maxdepth), spp, r + 1)
                        else:
                            env = "map" if "map alone" in c[1] else None
                            img, cpu, _ = ours.render(files[c[4]], spp, r + 1, c[3], env, variant_opts.get(c[1], ()))
                        imgs.setdefault(c[1], []).append(img)
                        cpus.setdefault(c[1], []).append(cpu)
                for c in mine:
                    results[(sc_key, integ, spp, c[0], c[1])] = (relvar(imgs[c[1]]), statistics.median(cpus[c[1]]),
                                                              np.mean(imgs[c[1]], axis=0))
                    if sc_key in regions:
                        by_region[(sc_key, integ, spp, c[0], c[1])] = relvar_by_class(imgs[c[1]], regions[sc_key])
                for c in mine:
                    v = results[(sc_key, integ, spp, c[0], c[1])]
                    extra = "".join(", %s %.3g" % kv for kv in by_region.get((sc_key, integ, spp, c[0], c[1]), {}).items())
                    print("  %s %s %d %s %s: relvar %.3g%s, CPU %.3f s" % (sc_key, integ, spp, c[0], c[1], v[0], extra, v[1]))
                sys.stdout.flush()
        mr.drop(sc_key)
    print()
    # ---- the tables ----
    rows = []
    for (sc_key, integ, spp, side, name), (v, c, _) in sorted(results.items()):
        rows.append([sc_key, integ, spp, side, name, "%.3g" % v, "%.3f" % c, "%.3g" % (v * c)])
    print("\nrelative variance across %d seeds (mean over pixels of var / (mean^2 + 1e-2)), CPU s of the render "
          "(median), cost = relvar x CPU s:" % seeds)
    print(fmt_table(rows, ["map", "integrator", "spp", "renderer", "configuration", "rel. variance", "CPU s", "cost"]))
    print("\n(a) equal spp, matched samplers, one light + one BSDF sample: relvar ours / relvar Mitsuba "
          "(issue 13's target <= 0.5)")
    rows = []
    for sc_key, _ in var_scenes:
        for integ in integs:
            for spp in spps:
                g = lambda side, name: results.get((sc_key, integ, spp, side, name), (float("nan"),))[0]
                rows.append([sc_key, integ, spp, "%.2f" % (g("ours", "random 1/1") / g("mitsuba", "independent 1/1")),
                             "%.2f" % (g("ours", "%s 1/1" % ld) / g("mitsuba", "multijitter 1/1"))])
    print(fmt_table(rows, ["map", "integrator", "spp", "random / independent", "%s / multijitter" % ld]))
    for v in args.variant:  # the same ratios for each --variant (its options replace the default's strategy)
        name = v.partition("=")[0]
        rows = []
        for sc_key, _ in var_scenes:
            for integ in [i for i in integs if i in var_integs]:
                for spp in spps:
                    g = lambda side, cfg: results.get((sc_key, integ, spp, side, cfg), (float("nan"),))[0]
                    rows.append([sc_key, integ, spp, "%.2f" % (g("ours", "random 1/1 " + name) / g("mitsuba", "independent 1/1")),
                                 "%.2f" % (g("ours", "%s 1/1 %s" % (ld, name)) / g("mitsuba", "multijitter 1/1"))])
        print("\n(a) for --variant %s" % v)
        print(fmt_table(rows, ["map", "integrator", "spp", "random / independent", "%s / multijitter" % ld]))
    print("\n(b) equal time: cost (relvar x CPU s) of our best configuration over Mitsuba's best "
          "(issue 14's target <= 0.5)")

    def best(sc_key, integ, spp):
        """(cost, configuration) of Mitsuba's and of our cheapest configuration (cost = relvar x CPU s; ours
        without the map-alone comparison runs); None for a side with no result"""
        m = [(v[0] * v[1], k[4]) for k, v in results.items() if k[:4] == (sc_key, integ, spp, "mitsuba")]
        o = [(v[0] * v[1], k[4]) for k, v in results.items() if k[:4] == (sc_key, integ, spp, "ours")
             and "map alone" not in k[4]]
        return (min(m) if m else None), (min(o) if o else None)

    rows = []
    for sc_key, _ in var_scenes:
        for integ in integs:
            for spp in spps:
                bm, bo = best(sc_key, integ, spp)
                if bm is None or bo is None:
                    continue
                rows.append([sc_key, integ, spp, "%.3g (%s)" % bo, "%.3g (%s)" % bm, "%.2f" % (bo[0] / bm[0])])
    print(fmt_table(rows, ["map", "integrator", "spp", "ours best", "Mitsuba best", "ratio"]))
    print("\n(c) CPU per camera sample (the render loop's CPU s at equal spp and resolution), ours / Mitsuba, one light + "
          "one BSDF sample (issue 21's target <= 1), and the equal-time ratio of (b) again (issue 21's target <= 0.5)")
    rows = []
    for sc_key, _ in var_scenes:
        for integ in integs:
            for spp in spps:
                g = lambda side, name: results.get((sc_key, integ, spp, side, name), (float("nan"), float("nan")))[1]
                bm, bo = best(sc_key, integ, spp)
                rows.append([sc_key, integ, spp, "%.3f / %.3f = %.2f" % (g("ours", "%s 1/1" % ld), g("mitsuba", "multijitter 1/1"),
                                                                       g("ours", "%s 1/1" % ld) / g("mitsuba", "multijitter 1/1")),
                             "%.2f" % (g("ours", "random 1/1") / g("mitsuba", "independent 1/1")),
                             "%.2f" % (bo[0] / bm[0]) if bm and bo else "-"])
    print(fmt_table(rows, ["map", "integrator", "spp", "CPU s %s / multijitter 1/1" % ld, "random / independent", "equal time"]))
    if by_region:
        print("\n(d) by region (%s): relvar ours / Mitsuba at equal spp (%s 1/1 / multijitter 1/1; random / independent) "
              "and the equal-time ratio (best / best, cost = the region's relvar x the whole image's CPU s)"
              % ("--mask " + args.mask if args.mask else "--regions: lit = every position of the pixel sees the sun, "
                 "shadowed = none does", ld))
        rows = []
        for sc_key, _ in var_scenes:
            for integ in integs:
                for spp in spps:
                    for reg in ("lit", "shadowed"):
                        g = lambda side, name: by_region.get((sc_key, integ, spp, side, name), {}).get(reg, float("nan"))
                        m = [(by_region[k][reg] * v[1], k[4]) for k, v in results.items()
                             if k[:4] == (sc_key, integ, spp, "mitsuba") and k in by_region]
                        o = [(by_region[k][reg] * v[1], k[4]) for k, v in results.items()
                             if k[:4] == (sc_key, integ, spp, "ours") and k in by_region and "map alone" not in k[4]]
                        rows.append([sc_key, integ, spp, reg, "%.2f" % (g("ours", "%s 1/1" % ld) / g("mitsuba", "multijitter 1/1")),
                                     "%.2f" % (g("ours", "random 1/1") / g("mitsuba", "independent 1/1")),
                                     "%.2f (%s / %s)" % (min(o)[0] / min(m)[0], min(o)[1], min(m)[1]) if m and o else "-"])
        print(fmt_table(rows, ["map", "integrator", "spp", "region", "%s / multijitter" % ld, "random / independent",
                               "equal time"]))
        for v in args.variant:  # the same equal-spp ratios by region for each --variant
            name = v.partition("=")[0]
            rows = []
            for sc_key, _ in var_scenes:
                for integ in [i for i in integs if i in var_integs]:
                    for spp in spps:
                        for reg in ("lit", "shadowed"):
                            g = lambda side, name: by_region.get((sc_key, integ, spp, side, name), {}).get(reg, float("nan"))
                            rows.append([sc_key, integ, spp, reg,
                                         "%.2f" % (g("ours", "%s 1/1 %s" % (ld, name)) / g("mitsuba", "multijitter 1/1")),
                                         "%.2f" % (g("ours", "random 1/1 " + name) / g("mitsuba", "independent 1/1"))])
            print("\n(d) for --variant %s" % v)
            print(fmt_table(rows, ["map", "integrator", "spp", "region", "%s / multijitter" % ld, "random / independent"]))
    print("\nbias check: relative difference of the image means, ours (%s 1/1) against Mitsuba (multijitter 1/1), "
          "at %d spp:" % (ld, spps[-1]))
    for sc_key, _ in var_scenes:
        for integ in integs:
            a = results.get((sc_key, integ, spps[-1], "ours", "%s 1/1" % ld))
            b = results.get((sc_key, integ, spps[-1], "mitsuba", "multijitter 1/1"))
            if a and b:
                print("  %s %s: %+.4f" % (sc_key, integ, (a[2].mean() - b[2].mean()) / b[2].mean()))
    print("\nfixed costs (not in the CPU seconds above):")
    for f, fx in sorted(ours.fixed.items()):
        if f.endswith("_1.pbrt"):
            print("  ours %-22s %s" % (os.path.basename(f), ", ".join("%s %.3f s" % kv for kv in fx.items())))
    for k, t in mr.load_s.items():
        print("  Mitsuba %-8s load_dict (map load, its distribution, BVH) %.3f s" % (k, t))
    for k, t in sorted(mr.compile_s.items()):
        print("  Mitsuba %-8s %-6s %-16s first render (JIT compilation included) %.2f s" % (k[0], k[1], k[2], t))
    print("\nwall time %.0f s; load average at the end %.2f %.2f %.2f" % ((time.time() - t_start,) + os.getloadavg()))
    shutil.rmtree(workdir, ignore_errors=True)


def sampler_variance_mode(args):
    """issue 14's sampler choice: our samplers' relative variance across seeds (direct lighting, MIS,
    one light + one BSDF sample) on the sun and the smooth map"""
    samplers = args.samplers.split(",") if args.samplers else \
        ["random", "stratified", "halton", "sobol", "02sequence", "zsobol", "paddedsobol"]
    quick = args.quick
    res = (160, 120) if quick else (tuple(args.var_res) if args.var_res else (320, 240))
    spps = [16, 64] if quick else [16, 64, 256]
    seeds = 2 if quick else args.seeds
    import mitsuba as mi
    mi.set_variant("scalar_rgb")  # (read_image's Bitmap)
    workdir = tempfile.mkdtemp(prefix="el_samplers_var_")
    ours = OursRunner(args, workdir)
    print("our samplers: relative variance across %d seeds, directlighting (MIS, 1 light + 1 BSDF sample), "
          "%dx%d, %d threads" % (seeds, res[0], res[1], args.threads))
    rows = []
    for sc_key, fname in var_scenes:
        f = os.path.join(workdir, "%s.pbrt" % sc_key)
        with open(f, "w") as fh:
            fh.write(scene_variant(os.path.join(ROOT, "scenes", fname), res, "direct", 1))
        for spp in spps:
            imgs, cpus = {}, {}
            for r in range(seeds):
                for s in samplers:
                    img, cpu, _ = ours.render(f, spp, r + 1, s)
                    imgs.setdefault(s, []).append(img)
                    cpus.setdefault(s, []).append(cpu)
            base = relvar(imgs["random"]) if "random" in imgs else float("nan")
            for s in samplers:
                v = relvar(imgs[s])
                rows.append([sc_key, spp, s, "%.3g" % v, "%.3f" % (v / base), "%.3f" % statistics.median(cpus[s]),
                             "%.3g" % (v * statistics.median(cpus[s]))])
                print("  %s %d %s %.3g (%.3f of random)" % (sc_key, spp, s, v, v / base))
            sys.stdout.flush()
    print()
    print(fmt_table(rows, ["map", "spp", "sampler", "rel. variance", "vs random", "CPU s", "cost"]))
    shutil.rmtree(workdir, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "bench_city.pbrt"))
    ap.add_argument("--spp", default="4,16,64,256")
    ap.add_argument("--ref-spp", type=int, default=8192)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--render", default=os.path.join(ROOT, "build", "bin", "render"))
    ap.add_argument("--outdir", default=os.path.join(ROOT, "out", "mitsuba"))
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--samplers", default="",
                    help="comma-separated samplers for our side (render --sampler), e.g. "
                         "stratified,halton,sobol,02sequence,zsobol,paddedsobol; then both sides are run per "
                         "sampler, interleaved, and an equal-spp relMSE ratio table is printed")
    ap.add_argument("--mitsuba-samplers", default="stratified,multijitter",
                    help="comma-separated Mitsuba 3 samplers for --samplers mode (independent, stratified, "
                         "multijitter, orthogonal, ldsampler)")
    ap.add_argument("--reference", action="store_true",
                    help="the older measure: relMSE against each renderer's own high-spp reference")
    ap.add_argument("--sampler-variance", action="store_true",
                    help="our samplers only: relative variance across seeds on the sun and the smooth map")
    ap.add_argument("--quick", action="store_true", help="160x120, 16 and 64 spp, 2 seeds, fewer configurations")
    ap.add_argument("--seeds", type=int, default=3, help="seeds per configuration in the variance modes")
    ap.add_argument("--our-sampler", default="zsobol", help="our low-discrepancy sampler in the variance mode")
    ap.add_argument("--variant", action="append", default=[],
                    help="variance mode: NAME=OPTIONS, ours with more render options (--variant-integrators, random and the "
                         "low-discrepancy sampler), e.g. 'twopixel=--env-sun-diffuse twopixel'; in (b)'s best and its own (a)")
    ap.add_argument("--variant-integrators", default="direct,path",
                    help="variance mode: the integrators the --variant options run on (default direct,path)")
    ap.add_argument("--var-integrators", default="direct,path", help="variance mode: the integrators to run (default direct,path)")
    ap.add_argument("--var-maps", default=",".join(k for k, _ in VAR_SCENES),
                    help="variance mode: the maps to run (default %s)" % ",".join(k for k, _ in VAR_SCENES))
    ap.add_argument("--map-too", action="store_true", help="variance mode: also ours with the map alone (no product)")
    ap.add_argument("--var-res", type=int, nargs=2, default=None,
                    help="resolution of the variance modes (default: the scene's, 320x240; --sampler-variance 320x240)")
    ap.add_argument("--var-spp", default="", help="variance mode: the sample counts (default 16,64,256)")
    ap.add_argument("--maxdepth", type=int, default=5, help="variance mode: both integrators' maxdepth (pbrt's bounces)")
    ap.add_argument("--regions", action="store_true",
                    help="variance mode: also report lit and shadowed pixels apart (classified by ray casting the "
                         "scene towards the map's brightest texel: pixel_classes)")
    ap.add_argument("--mask", default="", help="variance mode: lit (<= 0.5) and shadowed (> 0.5) pixels from a PGM or PFM "
                    "of the compared resolution")
    ap.add_argument("--no-stratified-splitting", action="store_true",
                    help="variance mode: leave out Mitsuba's stratified 2/2 and 4/4 (its multijitter is the stronger)")
    args = ap.parse_args()
    try:
        import numpy as np
        import mitsuba  # noqa: F401
    except ImportError:
        if args.sampler_variance:
            import numpy as np  # noqa: F401 (our side alone: numpy, and Mitsuba's Bitmap for EXR reading)
        print("installing Mitsuba 3 from PyPI: pip install mitsuba numpy")
        subprocess.run([sys.executable, "-m", "pip", "install", "mitsuba", "numpy"], check=False)
        try:
            import numpy as np  # noqa: F811
            import mitsuba  # noqa: F401,F811
        except ImportError as e:
            die("%s\n  install: pip install mitsuba numpy; apt-get install libllvm19" % e)
    if args.sampler_variance:
        sampler_variance_mode(args)
        return
    if not args.reference and not args.samplers:
        variance_mode(args)
        return

    spps = [int(s) for s in args.spp.split(",")]
    os.makedirs(args.outdir, exist_ok=True)
    if os.path.exists(args.scene):
        scene_path = args.scene
        with open(scene_path) as f:
            text = f.read()
    else:
        scene_path = os.path.join(args.outdir, "bench_city_fallback.pbrt")
        text = FALLBACK_SCENE.replace("../data/envmaps/city.hdr",
                                      os.path.join(ROOT, "data", "envmaps", "city.hdr"))
        with open(scene_path, "w") as f:
            f.write(text)
        print("note: %s does not exist; using the fallback scene %s" % (args.scene, scene_path))
    sc = parse_pbrt(scene_path, text)
    tag = hashlib.sha1((text + str(args.ref_spp)).encode()).hexdigest()[:10]
    workdir = tempfile.mkdtemp(prefix="el_mitsuba_")
    print("scene %s: %dx%d, fov %g, %d shape(s), %d light(s); %d threads"
          % (os.path.relpath(scene_path, ROOT), sc["xres"], sc["yres"], sc["fov"],
             len(sc["shapes"]), len(sc["lights"]), args.threads))

    mr = MitsubaRunner(sc, args.threads, workdir)

    # ---- orientation check: the environment alone, Mitsuba against pbrt-v3's mapping in numpy ----
    bg, _ = mr.render(16, 0, with_shapes=False)
    if sc["lights"] and sc["lights"][0]["mapname"]:
        ref_bg = pbrt_background(sc, sc["lights"][0]["mapname"])
        mi_flip = bg[:, ::-1]
        print("background check (environment only: Mitsuba at 16 spp against pbrt-v3's mapping in numpy, "
              "bilinear, 4x4 per pixel): relMSE %.3g; the same mirrored %.3g; upside down %.3g"
              % (relmse(bg, ref_bg), relmse(mi_flip, ref_bg), relmse(bg[::-1], ref_bg)))
        import mitsuba as mi
        mi.Bitmap(bg.astype(np.float32)).write(os.path.join(args.outdir, "mitsuba_background.exr"))
        mi.Bitmap(ref_bg.astype(np.float32)).write(os.path.join(args.outdir, "pbrt_model_background.exr"))

    if args.samplers:  # its own references, in halves
        sampler_mode(args, mr, scene_path, tag, spps, workdir)
        shutil.rmtree(workdir, ignore_errors=True)
        return

    # ---- Mitsuba reference (cached) ----
    ref_path = os.path.join(args.outdir, "mitsuba_ref_%s.npy" % tag)
    if os.path.exists(ref_path):
        mref = np.load(ref_path)
    else:
        chunk = min(1024, args.ref_spp)
        n = max(1, args.ref_spp // chunk)
        t0 = time.perf_counter()
        acc = None
        for k in range(n):
            img, _ = mr.render(chunk, 1000 + k)
            acc = img if acc is None else acc + img
        mref = acc / n
        np.save(ref_path, mref)
        print("Mitsuba reference: %d spp in %.1f s" % (n * chunk, time.perf_counter() - t0))
    import mitsuba as mi
    mi.Bitmap(mref.astype(np.float32)).write(os.path.join(args.outdir, "mitsuba_ref.exr"))

    # ---- Mitsuba at each spp ----
    rows, mit = [], {}
    for spp in spps:
        t0 = time.perf_counter()
        mr.render(spp, 7)  # warm-up: JIT compilation
        tcompile = time.perf_counter() - t0
        times, cpus, errs = [], [], []
        for r in range(args.runs):
            img, t = mr.render(spp, r + 1)
            times.append(t)
            cpus.append(mr.last_cpu)
            errs.append(relmse(img, mref))
        t, c, e = statistics.median(times), statistics.median(cpus), statistics.mean(errs)
        mit[spp] = (t, c, e)
        rows.append([spp, "%.3f" % t, "%.3f" % c, "%.3f" % tcompile, "%.3g" % e, "%.3g" % (e * t),
                     "%.3g" % (e * c)])
    print("\nMitsuba 3 %s (llvm_ad_rgb, integrator direct, sampler stratified, box filter)"
          % mi.__version__)
    print(fmt_table(rows, ["spp", "wall s", "CPU s", "1st run s", "relMSE", "relMSE x wall",
                           "relMSE x CPU"]))

    # ---- ours ----
    if not os.path.exists(args.render):
        print("\nour renderer: %s not found (build it first); Mitsuba side only" % args.render)
        return
    def run_ours(scene_file, spp, out, seed=0):
        cmd = [args.render, scene_file, "--spp", str(spp), "--nthreads", str(args.threads),
               "--quiet", "--seed", str(seed), "--outfile", out]
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        t = time.perf_counter() - t0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        run_ours.last_cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        if p.returncode != 0:
            die("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr.strip()))
        # the closing line "render: F: W x H, N spp in T s (total T2 s): ..." gives the render alone
        m = re.search(r"spp in ([0-9.eE+-]+) s", p.stdout + p.stderr)
        return read_image(out), t, (float(m.group(1)) if m else float("nan"))

    oref_path = os.path.join(args.outdir, "ours_ref_%s.exr" % tag)
    if not os.path.exists(oref_path):
        t0 = time.perf_counter()
        run_ours(scene_path, args.ref_spp, oref_path, seed=12345)
        print("our reference: %d spp in %.1f s" % (args.ref_spp, time.perf_counter() - t0))
    oref = read_image(oref_path)
    rows = []
    for spp in spps:
        times, rtimes, cpus, errs = [], [], [], []
        for r in range(args.runs):
            img, t, tr = run_ours(scene_path, spp, os.path.join(workdir, "ours_%d.exr" % spp),
                                  seed=r + 1)
            times.append(t)
            rtimes.append(tr)
            cpus.append(run_ours.last_cpu)
            errs.append(relmse(img, oref))
        t, tr, c, e = (statistics.median(times), statistics.median(rtimes), statistics.median(cpus),
                       statistics.mean(errs))
        mt, mc, me = mit[spp]
        rows.append([spp, "%.3f" % t, "%.3f" % tr, "%.3f" % c, "%.3g" % e, "%.3g" % (e * tr),
                     "%.2f" % ((e * tr) / (me * mt)), "%.2f" % ((e * c) / (me * mc)),
                     "%.2f" % ((e * t) / (me * mt))])
    print("\nours (%s; sampler and integrator as in the scene file)" % os.path.relpath(args.render, ROOT))
    print(fmt_table(rows, ["spp", "process s", "render s", "CPU s", "relMSE", "relMSE x render s",
                           "ratio render", "ratio CPU", "ratio process"]))
    print("ratio = (ours relMSE x time) / (Mitsuba relMSE x time) at the same spp: our relMSE over "
          "Mitsuba's at equal\ntime, since relMSE ~ 1/time. render: our render loop's wall time against "
          "Mitsuba's render wall time;\nCPU: CPU seconds of our whole process against those of Mitsuba's "
          "render call (steadier on a\nshared machine); process: our whole process's wall time. "
          "Target from issue 5: ratio <= 0.5.")

    # ---- cross-check: the two references render the same scene ----
    mm, om = mref.mean(axis=(0, 1)), oref.mean(axis=(0, 1))
    print("\ncross-check of the references (same scene file):")
    print("  mean RGB  Mitsuba %s   ours %s   relative difference %s"
          % (np.array2string(mm, precision=4), np.array2string(om, precision=4),
             np.array2string((om - mm) / mm, precision=4)))
    print("  mean |ours - Mitsuba| / mean(Mitsuba) = %.4f;  relMSE(ours ref, Mitsuba ref) = %.3g"
          % (np.mean(np.abs(oref - mref)) / np.mean(mref), relmse(oref, mref)))
    bgscene = os.path.join(workdir, "background.pbrt")
    write_background_scene(text, os.path.dirname(os.path.abspath(scene_path)), bgscene)
    try:
        obg = run_ours(bgscene, 16, os.path.join(args.outdir, "ours_background.exr"))[0]
        print("  background only (16 spp): relMSE(ours, Mitsuba) %.3g, relMSE(ours, pbrt-v3 mapping) %.3g"
              % (relmse(obg, bg), relmse(obg, pbrt_background(sc, sc["lights"][0]["mapname"]))))
    except SystemExit:
        print("  (our renderer could not render the background-only scene)")
    shutil.rmtree(workdir, ignore_errors=True)


if __name__ == "__main__":
    main()
