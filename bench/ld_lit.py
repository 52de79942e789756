#!/usr/bin/env python3
"""ld_lit.py: where the low-discrepancy gain goes on a sun map (issue 22's lit pixels).

bench/mitsuba_compare.py --regions measured, on bench_city (a diffuse sphere on a plane under city.hdr's
3e4 sun, direct lighting, one light + one BSDF sample), that Mitsuba's multijitter cuts the lit pixels'
relative variance 19x against its independent sampler, our zsobol only 8.8x against our random sampler.
This script renders the same scene (scene_variant at --res) with our renderer's strategies and samplers,
and optionally Mitsuba's, --seeds seeds each, interleaved, and prints the relative variance across seeds
of the whole image, the lit and the shadowed pixels (mitsuba_compare's pixel_classes and relvar_by_class),
the CPU seconds of our render loop, and each strategy's low-discrepancy gain (random over zsobol).

    python3 bench/ld_lit.py [--res 320 240] [--spp 64] [--seeds 4] [--threads 2]
                            [--configs default,map,...] [--mitsuba] [--scene scenes/bench_city.pbrt]
                            [--integrator direct|path] [--maxdepth 5]

--integrator path: the path tracer (maxdepth --maxdepth; Mitsuba's 'path' with max_depth one more, 1/1 only).

A configuration is a name (CONFIGS below: render's hidden options) run with zsobol and random; NAME@2 renders
with the light's "integer samples" [ 2 ] (two light + BSDF sample pairs per camera sample, or two light samples);
--extra 'name=--opt a --opt b' adds one. --mitsuba adds Mitsuba 3's direct integrator with 1/1 and 1/0
(light sample only) emitter/BSDF samples, independent and multijitter.

Measured (2026-12-02, 320x240, 4 seeds at 64 spp, 3 at 256; the shared 2-core machine; examples/render/README.md,
"Two product samples"): at 64 spp zsobol, lit pixels, the light sample alone: product 3.98e-4, the patch density
5.77e-4, Mitsuba multijitter 4.09e-4 (one common floor: the sphere's edge; the plane alone 4.4e-5 / 4.2e-5 /
1.0e-4); with the BSDF sample (MIS) 3.32e-4 / 4.35e-4 / 2.78e-4; two product samples (--env-sun-diffuse two)
2.16e-4. Whole / lit / shadowed, ours / Mitsuba at equal spp: default 0.69 / 1.19 / 0.60, two 0.59 / 0.78 / 0.57
(64 spp); 0.71 / 1.15 / 0.62 -> 0.53 / 0.65 / 0.54 (256 spp). But two loses 2.3-4.2x on scenes filled with shadow
(sun_shadow_object, sun_porch as directlighting): an option only. Chosen per pixel (--env-sun-diffuse twopixel: two
where the pixel's centre sees the sun, product MIS where not): 0.51 / 0.78 / 0.47 (64 spp), 0.47 / 0.65 / 0.45
(256 spp); random / independent 0.30 / 0.16 / 0.37; the shadow scenes 0.84x / 0.95x the default's (zsobol).
"""
import argparse
import os
import re
import resource
import shlex
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_compare as mc  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = {
    "default": [],  # product MIS at the diffuse vertices (el_envlight_sample_li_cos + BSDF sample)
    "light": ["--light-sampling", "light"],  # the product light sample alone
    "bsdf": ["--light-sampling", "bsdf"],
    "map": ["--env-sampling", "map"],  # the map alone with MIS (le()'s patch density under a sun map)
    "map-light": ["--env-sampling", "map", "--light-sampling", "light"],
    "map-pbrt": ["--env-sampling", "map", "--importance", "pbrt-v3"],
    "map-pbrt-light": ["--env-sampling", "map", "--importance", "pbrt-v3", "--light-sampling", "light"],
    "suncos": ["--env-sun-diffuse", "suncos"],
    "sun": ["--sun", "on"],
    "alone": ["--env-sun-diffuse", "alone"],  # the product light sample alone at diffuse vertices (MIS elsewhere)
    "two": ["--env-sun-diffuse", "two"],  # two product light samples at diffuse vertices (no BSDF sample's MIS)
    "twopixel": ["--env-sun-diffuse", "twopixel"],  # the same where the pixel's centre sees the sun
}


def render(args, scene, spp, seed, sampler, opts, out):
    cmd = [args.render, scene, "--spp", str(spp), "--nthreads", str(args.threads), "--quiet", "--stats",
           "--seed", str(seed), "--outfile", out, "--sampler", sampler] + opts
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        mc.die("%s failed: %s" % (" ".join(cmd), p.stderr.strip()))
    m = re.search(r"render\s+[0-9.]+ s\s+\(CPU ([0-9.]+) s\)", p.stdout + p.stderr)
    return mc.read_image(out), (float(m.group(1)) if m else float("nan"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--res", type=int, nargs=2, default=[320, 240])
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scene", default=os.path.join(ROOT, "scenes", "bench_city.pbrt"))
    ap.add_argument("--render", default=os.path.join(ROOT, "build", "bin", "render"))
    ap.add_argument("--configs", default="default,light,map,map-light")
    ap.add_argument("--samplers", default="zsobol,random")
    ap.add_argument("--extra", action="append", default=[], help="name=options (added to --configs)")
    ap.add_argument("--mitsuba", action="store_true")
    ap.add_argument("--integrator", choices=("direct", "path"), default="direct")
    ap.add_argument("--maxdepth", type=int, default=5, help="--integrator path: pbrt's maxdepth (bounces)")
    ap.add_argument("--save", help="write the images and classes to this .npz (for further analysis)")
    args = ap.parse_args()
    cfgs = [(n, CONFIGS[n.split("@")[0]]) for n in args.configs.split(",") if n]
    for e in args.extra:
        n, _, o = e.partition("=")
        cfgs.append((n, shlex.split(o)))
    work = tempfile.mkdtemp(prefix="el_ld_lit_")
    scene = os.path.join(work, "s.pbrt")
    text = mc.scene_variant(args.scene, tuple(args.res), args.integrator, 1, args.maxdepth)
    with open(scene, "w") as f:
        f.write(text)
    scene2 = os.path.join(work, "s2.pbrt")  # a configuration named NAME@2: the light's "integer samples" [ 2 ]
    with open(scene2, "w") as f:
        f.write(mc.scene_variant(args.scene, tuple(args.res), args.integrator, 2, args.maxdepth))
    sc = mc.parse_pbrt(scene, text)
    classes = mc.pixel_classes(sc)
    print("ld_lit: %s at %dx%d, %s, %d spp, %d seeds; lit %d, shadowed %d pixels" % (
        os.path.basename(args.scene), args.res[0], args.res[1], args.integrator, args.spp, args.seeds,
        int(classes["lit"].sum()), int(classes["shadowed"].sum())))
    runs = [(n + " " + s, s, o) for n, o in cfgs for s in args.samplers.split(",")]
    mr = None
    if args.mitsuba:
        import mitsuba as mi
        mr = mc.MiVarRunner(args.threads, work, "llvm_ad_rgb" if "llvm_ad_rgb" in mi.variants() else "scalar_rgb")
        for smp in ("independent", "multijitter"):
            for nb in ((1, 0) if args.integrator == "direct" else (1,)):
                runs.append(("mitsuba %s 1/%d" % (smp, nb), None, (smp, nb)))
    imgs, cpus = {}, {}
    for r in range(args.seeds):
        for name, smp, o in runs:
            if smp is None:
                d = mc.mitsuba_scene_dict(mr.mi, sc, args.spp, work, True, o[0])
                d["integrator"] = ({"type": "direct", "emitter_samples": 1, "bsdf_samples": o[1]} if args.integrator == "direct"
                                   else {"type": "path", "max_depth": args.maxdepth + 1, "rr_depth": 4})
                key = ("mi", o)
                if key not in mr.scenes:
                    mr.scenes[key] = mr.mi.load_dict(d)
                    mr.render(mr.scenes[key], args.spp, 999)  # warm-up (JIT)
                img, cpu = mr.render(mr.scenes[key], args.spp, r + 1)
            else:
                img, cpu = render(args, scene2 if name.split()[0].endswith("@2") else scene, args.spp, r + 1, smp, o, os.path.join(work, "o.pfm"))
            imgs.setdefault(name, []).append(img)
            cpus.setdefault(name, []).append(cpu)
    if args.save:
        import numpy as np
        np.savez_compressed(args.save, lit=classes["lit"], shadowed=classes["shadowed"],
                            **{k.replace(" ", "_").replace("/", "_"): np.stack(v) for k, v in imgs.items()})
    res = {}
    print("%-28s %10s %10s %10s %8s" % ("configuration", "whole", "lit", "shadowed", "CPU s"))
    for name, _, _ in runs:
        w = mc.relvar(imgs[name])
        c = mc.relvar_by_class(imgs[name], classes)
        res[name] = (w, c["lit"], c["shadowed"])
        cpu = sorted(cpus[name])[len(cpus[name]) // 2]
        print("%-28s %10.3g %10.3g %10.3g %8.3f" % (name, w, c["lit"], c["shadowed"], cpu))
    print("\nlow-discrepancy gain (random / zsobol; Mitsuba independent / multijitter): whole, lit, shadowed")
    for n, _ in cfgs:
        a, b = res.get(n + " random"), res.get(n + " zsobol")
        if a and b:
            print("%-20s %6.2f %6.2f %6.2f" % (n, a[0] / b[0], a[1] / b[1], a[2] / b[2]))
    for nb in (1, 0):
        a, b = res.get("mitsuba independent 1/%d" % nb), res.get("mitsuba multijitter 1/%d" % nb)
        if a and b:
            print("%-20s %6.2f %6.2f %6.2f" % ("mitsuba 1/%d" % nb, a[0] / b[0], a[1] / b[1], a[2] / b[2]))


if __name__ == "__main__":
    main()
