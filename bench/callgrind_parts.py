#!/usr/bin/env python3
"""callgrind_parts.py: instructions per camera sample of the renderer's loop, by part.

Reads two callgrind outputs of `bench_render --callgrind samples N` (N1 < N2 camera samples, the same
options otherwise) and prints, per part, (Ir(N2) - Ir(N1)) / (samples(N2) - samples(N1)): the difference
removes every fixed cost (scene loading, the light's tables, lazily built ones included, thread start).

Parts (by the function's name, its source file, and for inlined code the file it was inlined from):
  sampler   examples/render/sampler*.c, lowdiscrepancy.c, elr_sampler_* / elr_zsobol_* / elr_randomize
  light     envlight.h, distribution2d.h, mipmap.h, lights.c, lightdistrib.c, sun.c (the sun cache),
            elr_light_*, elr_sun_*
  bsdf      reflection.c, materials.c, textures.c, elr_bsdf_*
  film      film.h, film.c, el_film_*
  embree    libembree3 and the renderer's intersection code (shapes.c: the sphere callbacks and
            triangle hits; scene.c: elr_intersect, elr_occluded, the wave's Embree calls)
  camera    camera.c
  loop      the per-tile loops and integrators (render*.c, integrator*.c): bookkeeping
Shared helpers (transform.c, spectrum.c, libm, libc: they call into no part) belong to no part: their
cost (inclusive) is charged to the part of the function that called them; everything else (setup,
the bench's own loops) is "other", which the difference of two runs leaves near 0. Self cost of code inlined from elr_internal.h
stays with the function it was inlined into.

Run (from the build directory; one thread, directlighting, zsobol, 16 spp; about 3 minutes each):
  valgrind --tool=callgrind --callgrind-out-file=cg.1 bin/bench_render --callgrind samples 25600 --sampler zsobol
  valgrind --tool=callgrind --callgrind-out-file=cg.2 bin/bench_render --callgrind samples 51200 --sampler zsobol
  python3 ../bench/callgrind_parts.py cg.1 cg.2 25600 51200
(or `sh ../bench/callgrind_parts.sh [bench_render options]`, which does all three). --top K also lists
the K costliest functions of each part (self, per sample).
"""
import re
import sys
from collections import defaultdict

PARTS = ["sampler", "light", "bsdf", "film", "embree", "camera", "loop", "other"]

FILE_RULES = [  # (regex on the source file, part)
    (r"(^|/)examples/render/(sampler[^/]*|lowdiscrepancy)\.c$", "sampler"),
    (r"(^|/)(envlight|distribution2d|mipmap|blockedarray)\.h$", "light"),
    (r"(^|/)examples/render/(lights|lightdistrib|envlight_impl|sun)\.c$", "light"),
    (r"(^|/)examples/render/(reflection|materials|textures)\.c$", "bsdf"),
    (r"(^|/)film\.h$", "film"),
    (r"(^|/)examples/render/film\.c$", "film"),
    (r"(^|/)examples/render/(shapes|loopsubdiv)\.c$", "embree"),
    (r"(^|/)examples/render/camera\.c$", "camera"),
    (r"(^|/)examples/render/(render|render_wave|integrator[^/]*|interaction|stats)\.c$", "loop"),
]
FN_RULES = [  # (regex on the function's name, part): first match wins, before the file rules
    (r"^(elr_sampler_|elr_zsobol|elr__zsobol|elr_randomize|elr_sobol|elr__fast_owen|elr_dim_hash|elr_paddedsobol|elr_halton|elr_stratified|elr_zerotwo)", "sampler"),
    (r"^(el_envlight|el_distribution|el_mipmap|elr_light|elr__env_samples|elr_sun_|elr__sun)", "light"),
    (r"^(elr_bsdf|elr_material)", "bsdf"),
    (r"^(el_film|elr_film)", "film"),
    (r"^(elr_intersect|elr_occluded|elr_raw_intersect|elr_wave_intersect|elr_wave_occluded|elr__wave_|elr_sphere_|elr_triangle_|elr_disk_|elr_wave_hit|elr__sph|elr__disk)", "embree"),
    (r"^(rtc|embree::)", "embree"),
    (r"^(elr_camera|elr_generate_ray)", "camera"),
]
SHARED_FILES = r"(^|/)examples/render/(transform|spectrum|elr_internal)\.[ch]$"


def part_of(fn, fl, ob):
    for rx, p in FN_RULES:
        if re.search(rx, fn):
            return p
    if "libembree" in ob:
        return "embree"
    if re.search(SHARED_FILES, fl):
        return None
    for rx, p in FILE_RULES:
        if re.search(rx, fl):
            return p
    return None  # libm, libc, transform.c...: charged to the caller


def is_helper(fn, fl, ob):
    """a shared helper that calls into no part: its inclusive cost goes to its caller's part"""
    return bool(re.search(r"lib(m|c)[.-]", ob) or re.search(SHARED_FILES, fl))


def parse(path):
    """self[(fn, file of the code)] and the function's own file and object, and call edges
    calls[(caller fn, callee fn)] = inclusive Ir"""
    names = {"fn": {}, "fl": {}, "ob": {}}
    selfc = defaultdict(int)
    calls = defaultdict(int)
    fn_file, fn_ob = {}, {}
    fn = fl = fi = ob = ""
    cfn = None
    pending_call = False

    def name(kind, rest):
        m = re.match(r"\((\d+)\)(?: (.*))?$", rest)
        if not m:
            return rest
        if m.group(2) is not None:
            names[kind][m.group(1)] = m.group(2)
        return names[kind].get(m.group(1), "?")

    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if not line:
                continue
            c = line[0]
            if c.isdigit() or c in "+-*":
                cost = line.split()
                ir = int(cost[1]) if len(cost) > 1 else 0
                if pending_call:
                    calls[(fn, cfn)] += ir
                    pending_call = False
                else:
                    selfc[(fn, fi or fl)] += ir
                continue
            key, _, rest = line.partition("=")
            if key == "ob":
                ob = name("ob", rest)
            elif key == "cob":
                name("ob", rest)
            elif key == "fl":
                fl = name("fl", rest); fi = ""
            elif key in ("fi", "fe"):
                fi = name("fl", rest)
                if fi == fl:
                    fi = ""
            elif key in ("cfi", "cfl"):
                name("fl", rest)
            elif key == "fn":
                fn = name("fn", rest); fi = ""
                fn_file.setdefault(fn, fl); fn_ob.setdefault(fn, ob)
            elif key == "cfn":
                cfn = name("fn", rest)
            elif key == "calls":
                pending_call = True
    return selfc, calls, fn_file, fn_ob


def by_part(path):
    selfc, calls, fn_file, fn_ob = parse(path)
    fpart = {fn: part_of(fn, fn_file.get(fn, ""), fn_ob.get(fn, "")) for fn in fn_file}
    parts = defaultdict(int)
    funcs = defaultdict(int)
    for (fn, fl), ir in selfc.items():
        p = fpart.get(fn)
        if p is None:
            continue  # a shared helper: counted through its callers' edges below
        # code inlined from a library header counts for the library's part
        q = None
        for rx, pp in FILE_RULES:
            if pp in ("light", "film") and re.search(rx, fl):
                q = pp
        parts[q or p] += ir
        funcs[(q or p, fn)] += ir
    for (caller, callee), ir in calls.items():
        pc, pe = fpart.get(caller), fpart.get(callee)
        if pc is not None and pe is None and is_helper(callee, fn_file.get(callee, ""), fn_ob.get(callee, "")):
            parts[pc] += ir
            funcs[(pc, callee + " (called)")] += ir
    # shared helpers called from nowhere assigned (start-up, the bench's own setup): "other"
    total = sum(ir for ir in selfc.values())
    parts["other"] = total - sum(parts[p] for p in PARTS if p != "other")
    return parts, funcs, total


def main():
    args = [a for a in sys.argv[1:]]
    top = 0
    if "--top" in args:
        i = args.index("--top"); top = int(args[i + 1]); del args[i:i + 2]
    if len(args) != 4:
        sys.exit(__doc__)
    f1, f2, n1, n2 = args[0], args[1], int(args[2]), int(args[3])
    p1, fn1, t1 = by_part(f1)
    p2, fn2, t2 = by_part(f2)
    dn = n2 - n1
    print("instructions per camera sample, (Ir(%d) - Ir(%d)) / %d:" % (n2, n1, dn))
    for p in PARTS:
        print("  %-8s %7.0f" % (p, (p2[p] - p1[p]) / dn))
    print("  %-8s %7.0f" % ("total", (t2 - t1) / dn))
    if top:
        for p in PARTS:
            rows = sorted(((fn2[k] - fn1.get(k, 0)) / dn, k[1]) for k in fn2 if k[0] == p)
            rows = [r for r in rows if r[0] >= 1][::-1][:top]
            if rows:
                print("%s: " % p + ", ".join("%s %.0f" % (n, v) for v, n in rows))


if __name__ == "__main__":
    main()
