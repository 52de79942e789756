#!/usr/bin/env python3
"""bench/report.py: what accuracy costs in time, measured on this machine, as plots.

    python3 bench/report.py [--quick] [--build build] [--out docs]

Runs the benchmarks' CSV modes (bench_mipmap, bench_envlight, bench_film --csv) and the renderer
(build/bin/render on generated variants of scenes/bench_city.pbrt and scenes/bench_studio.pbrt), then
writes OUT/accuracy-vs-time.md with its plots in OUT/img/*.png. `sh scripts/report.sh` builds what this
needs first; call that. --quick: tiny sizes, one repeat (CI runs it so the command cannot rot; its
numbers are not meant to be read). Every measured number in the report comes from this run.

Times are medians of repeated runs, the options of a family interleaved within every repeat (the
machine is shared). The benchmarks time their own loops with the thread's CPU time; renders run on
one thread and are timed by the render loop's CPU time (render --stats), without parsing, Embree and
the light's tables, which the environment light family plots on their own.
"""
import argparse
import csv
import datetime
import io
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
import check_report  # noqa: E402 (bench/ is on the path when run as a script)
from check_report import EXPECTED_PLOTS  # noqa: E402


# ---------------------------------------------------------------------------------------------------
# The machine, the build, the caption under every plot
# ---------------------------------------------------------------------------------------------------
def machine_info(build):
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    cache = {}
    try:
        with open(os.path.join(build, "CMakeCache.txt")) as f:
            for line in f:
                m = re.match(r"^([A-Za-z_]+):[A-Z]+=(.*)$", line.strip())
                if m:
                    cache[m.group(1)] = m.group(2)
    except OSError:
        pass
    cc = cache.get("CMAKE_C_COMPILER", "cc")
    try:
        ccv = subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    except (OSError, IndexError):
        ccv = cc
    btype = cache.get("CMAKE_BUILD_TYPE", "")
    flags = (cache.get("CMAKE_C_FLAGS", "") + " " + cache.get("CMAKE_C_FLAGS_" + btype.upper(), "")).strip()
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip()
    except OSError:
        commit = "?"
    return {
        "cpu": cpu, "nproc": os.cpu_count() or 1, "date": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"),
        "cc": ccv, "flags": "%s %s (benchmarks add -O3)" % (btype, flags), "commit": commit,
    }


def caption(fig, info, default):
    fig.text(0.01, 0.005, "%s, %d cores; %s; %s; %s; envlight %s. Default: %s" % (
        info["cpu"], info["nproc"], info["date"], info["cc"], info["flags"], info["commit"], default),
        fontsize=6.5, color="0.3", ha="left", va="bottom", wrap=True)


def new_fig(ncols=1):
    fig, axes = plt.subplots(1, ncols, figsize=(6.2 * ncols, 4.6), squeeze=False)
    return fig, list(axes[0])


def save(fig, out, name, info, default):
    caption(fig, info, default)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    path = os.path.join(out, "img", name + ".png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return "img/%s.png" % name


def style(label, default):
    return dict(lw=2.6 if label == default else 1.3, marker="o", ms=4, label=label + (" [default]" if label == default else ""))


# ---------------------------------------------------------------------------------------------------
# Every measurement goes through measured(): saved to OUT/measurements.json, so that --replot can
# redraw the plots and the text from a run's numbers without measuring again.
# ---------------------------------------------------------------------------------------------------
MEAS = {}
REPLOT = False


def measured(key, fn):
    if REPLOT:
        if key not in MEAS:
            sys.exit("report.py: --replot: %s is not in measurements.json" % key)
        return MEAS[key]
    MEAS[key] = fn()
    return MEAS[key]


# ---------------------------------------------------------------------------------------------------
# Running things
# ---------------------------------------------------------------------------------------------------
def run_csv(build, prog, quick):
    return measured("csv:" + prog, lambda: run_csv_now(build, prog, quick))


def run_csv_now(build, prog, quick):
    cmd = [os.path.join(build, "bin", prog), "--csv"] + (["--quick"] if quick else [])
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("report.py: %s failed (exit %d):\n%s" % (" ".join(cmd), p.returncode, p.stderr))
    print("  %s: %.1f s" % (" ".join(cmd[1:] and [prog] + cmd[1:]), time.time() - t0), flush=True)
    rows = list(csv.reader(io.StringIO(p.stdout)))
    return rows[1:]


def read_pfm(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            raise ValueError("%s: not an RGB PFM" % path)
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.fromfile(f, dtype="<f4" if scale < 0 else ">f4", count=w * h * 3)
    return data.reshape(h, w, 3).astype(np.float64)


def make_scene(base, path, res, material=None, light_samples=None):
    """A variant of a scene of scenes/: resolution, the sphere's material, the light's "samples"."""
    with open(os.path.join(ROOT, "scenes", base)) as f:
        s = f.read()
    s = re.sub(r'"integer xresolution" \[ \d+ \]', '"integer xresolution" [ %d ]' % res[0], s)
    s = re.sub(r'"integer yresolution" \[ \d+ \]', '"integer yresolution" [ %d ]' % res[1], s)
    s = s.replace('"../data/', '"%s/data/' % ROOT)
    if material:
        s = s.replace('Material "matte" "rgb Kd" [ 0.6 0.6 0.6 ]', material, 1)
    if light_samples:
        s = re.sub(r'(LightSource "infinite" [^\n]*)', r'\1 "integer samples" [ %d ]' % light_samples, s, count=1)
    with open(path, "w") as f:
        f.write(s)
    return path


RENDER_CPU = re.compile(r"\n  render +[0-9.]+ s +\(CPU ([0-9.]+) s\)")


def render(build, scene, tmp, spp, seed, args=(), nthreads=1):
    out = os.path.join(tmp, "out_%d.pfm" % os.getpid())
    cmd = [os.path.join(build, "bin", "render"), scene, "--outfile", out, "--spp", str(spp), "--seed", str(seed),
           "--nthreads", str(nthreads), "--quiet", "--stats"] + list(args)
    p = subprocess.run(cmd, capture_output=True, text=True)
    m = RENDER_CPU.search(p.stderr + p.stdout)
    if p.returncode != 0 or not m:
        sys.exit("report.py: %s failed (exit %d):\n%s%s" % (" ".join(cmd), p.returncode, p.stdout, p.stderr))
    return read_pfm(out), max(float(m.group(1)), 1e-4)  # the render loop's CPU time (--stats)


def relmse(img, ref):
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + 1e-2)))


class Reference:
    """A reference image: two independent halves (zsobol, different seeds) averaged; its own noise,
    relMSE(A, B) / 4 for the average, is taken off every measured relMSE."""

    def __init__(self, build, scene, tmp, spp):
        a, _ = render(build, scene, tmp, spp, 1001, ["--sampler", "zsobol"], nthreads=os.cpu_count() or 1)
        b, _ = render(build, scene, tmp, spp, 2002, ["--sampler", "zsobol"], nthreads=os.cpu_count() or 1)
        self.img = 0.5 * (a + b)
        self.spp = 2 * spp
        self.noise = relmse(a, b) / 4  # relMSE(a, b) ~ 2 sigma^2 / R^2; the average has sigma^2 / 2

    def error(self, img):
        return max(relmse(img, self.img) - self.noise, 1e-12)


def sweep(build, tmp, scene, ref, options, spps, reps):
    return measured("sweep:%s:%s" % (os.path.basename(scene), options[0][0]),
                    lambda: sweep_now(build, tmp, scene, ref, options, spps, reps))


def sweep_now(build, tmp, scene, ref, options, spps, reps):
    """options: [(label, [render args])]. Returns {label: [(spp, median time, mean relMSE)]}.
    Interleaved: every repeat renders every (spp, option) once, with its own seed."""
    times = {(o, s): [] for o, _ in options for s in spps}
    errs = {(o, s): [] for o, _ in options for s in spps}
    for r in range(reps):
        for s in spps:
            for label, args in options:
                img, t = render(build, scene, tmp, s, 1 + r, args)
                times[(label, s)].append(t)
                errs[(label, s)].append(ref.error(img))
    return {o: [(s, statistics.median(times[(o, s)]), statistics.mean(errs[(o, s)])) for s in spps]
            for o, _ in options}


def per_spp(pts):
    """The render loop's cost is linear in spp; on a shared machine one render's time is noisy, so each
    option's curve uses one cost per spp pooled over all its runs: sum of the median times / sum of spp
    (dominated by the longest, least noisy runs). Returns [(spp, spp * cost, relMSE)] and the cost."""
    c = sum(p[1] for p in pts) / sum(p[0] for p in pts)
    return [(p[0], p[0] * c, p[2]) for p in pts], c


def pooled(res_s):
    return {k: per_spp(v)[0] for k, v in res_s.items()}


# ---------------------------------------------------------------------------------------------------
# Reading the plots: crossovers and efficiencies
# ---------------------------------------------------------------------------------------------------
def crossover(a, b):
    """a, b: [(time, error)] sorted by time. The first time where the two curves (piecewise linear in
    log-log) change order, or None."""
    if len(a) < 2 or len(b) < 2:
        return None
    lo, hi = max(a[0][0], b[0][0]), min(a[-1][0], b[-1][0])
    if not lo < hi:
        return None

    def at(c, t):
        xs = [math.log(p[0]) for p in c]
        ys = [math.log(p[1]) for p in c]
        return float(np.interp(math.log(t), xs, ys))

    ts = np.exp(np.linspace(math.log(lo), math.log(hi), 200))
    d = [at(a, t) - at(b, t) for t in ts]
    for i in range(1, len(d)):
        if d[i - 1] * d[i] < 0:
            return float(ts[i])
    return None


def fmt_t(sec):
    if sec < 1e-6:
        return "%.0f ns" % (sec * 1e9)
    if sec < 1e-3:
        return "%.1f us" % (sec * 1e6)
    if sec < 1:
        return "%.1f ms" % (sec * 1e3)
    return "%.2f s" % sec


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------------
# The families
# ---------------------------------------------------------------------------------------------------
def family_mipmap(args, info, md):
    rows = run_csv(args.build, "bench_mipmap", args.quick)
    look = [r for r in rows if r[0] == "lookup"]
    build = [r for r in rows if r[0] == "build"]
    default = "EWA max aniso 8 (default)"
    fig, (ax,) = new_fig()
    names = list(dict.fromkeys(r[1] for r in look))
    for n in names:
        pts = [(float(r[3]), float(r[4]), r[2]) for r in look if r[1] == n]
        kw = style(n.replace(" (default)", ""), default.replace(" (default)", ""))
        if n.startswith("pbrt"):
            kw["ls"] = "--"
        ax.plot([p[0] for p in pts], [p[1] for p in pts], **kw)
        for x, y, a in pts:
            ax.annotate(a, (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xscale("log"); ax.set_yscale("log")
    ax.set_xlabel("ns per lookup (one thread, CPU time, median)")
    ax.set_ylabel("rms relative error vs supersampled footprint")
    ax.set_title("MIP map lookups: error against time (labels: footprint anisotropy)")
    ax.legend(fontsize=7); ax.grid(True, which="both", alpha=0.3)
    img1 = save(fig, args.out, "mipmap_lookups", info, "EWA, max anisotropy 8 (pbrt's)")

    fig, (ax,) = new_fig()
    for n in dict.fromkeys(r[1] for r in build):
        pts = [(float(r[3]), float(r[4]), r[2]) for r in build if r[1] == n]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], **style(n.replace(" (default)", ""), "Lanczos to a power of two"))
        for x, y, w in pts:
            ax.annotate(w, (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xscale("log"); ax.set_yscale("log")
    ax.set_xlabel("build ms (init + every level; CPU time, median)")
    ax.set_ylabel("rms relative error of EWA lookups vs the input's footprint")
    ax.set_title("MIP map pyramid build (labels: input width; height = width / 2)")
    ax.legend(fontsize=7); ax.grid(True, which="both", alpha=0.3)
    img2 = save(fig, args.out, "mipmap_build", info, "Lanczos resampling to a power of two (pbrt's)")

    by = {(r[1], r[2]): (float(r[3]), float(r[4])) for r in look}
    trows = []
    for n in names:
        trows.append([n] + ["%.0f ns, %.3f" % by[(n, a)] for a in ("1", "8", "64")])
    ewa8, ewa64, tri = by[(default, "64")], by[("EWA max aniso 64", "64")], by[("trilinear", "64")]
    p_ewa = by.get(("pbrt-v3 port: EWA", "8")); o_ewa = by[(default, "8")]
    brows = [[r[1], r[2], "%.2f ms" % float(r[3]), "%.3f" % float(r[4])] for r in build]
    md.append("""## MIP map lookups

![MIP map lookups](%s)

A 2048x1024 RGB texture with detail at every scale (bench_mipmap's chequerboard whose frequency rises
along u, over colour ramps, with a fine diagonal stripe), 512x256 in --quick. Footprints: the major axis
log-uniform in [1e-3, 3e-2] of the texture (2 to 60 texels), the minor axis 1, 8 or 64 times shorter,
random orientation. **Reference**: pbrt's Gaussian filter over the *unclamped* ellipse, integrated with
32x32 stratified point lookups of level 0, so an anisotropy clamp counts as error. Error: rms over the
queries of the relative RGB error. Time: ns per lookup over %s random queries (thread CPU time, median
of the repeats, the filters interleaved). The dashed curves are bench_mipmap's literal port of pbrt-v3's
MIPMap (BlockedArray, its EWA and trilinear); they give the same values as ours (bench_mipmap checks the
difference), so only their time differs.

%s

Read off the plot: trilinear is the fastest filtered lookup (%.0f ns at anisotropy 64) but its error
stays at %.2f there, because its isotropic footprint must cover the major axis; EWA with pbrt's clamp of
8 reaches %.3f for %.0f ns; lifting the clamp to 64 gives %.3f for %.0f ns. At anisotropy 1 every
EWA variant gives the same answer and the clamp costs nothing. %s

- **Student's first renderer**: trilinear (`el_mipmap_lookup` with a width): one call, no differentials
  needed, %.0fx cheaper than EWA at anisotropy 8 here; it blurs at grazing angles (the error above)
  but does not alias.
- **Production renderer**: EWA (`el_mipmap_lookup_differentials`), the default clamp 8; raise
  `max_anisotropy` to 64 only for scenes with large grazing textured planes (floors, roads), where the
  error drops further for the cost shown.
- **Real-time preview**: trilinear; %s

### Pyramid build

![MIP map build](%s)

A width x width/2 input whose width is not a power of two (%s). **Lanczos** (the default, pbrt's):
level 0 is resampled up to the next power of two with pbrt's 4-tap Lanczos weights, then 2x2 box
levels. **keep_resolution**: level 0 is the input as is and the upper levels are exact area averages.
Error: EWA lookups (anisotropy-1 footprints) against the supersampled footprint of the *input* (not of
the resampled image). Time: init + every level, CPU time, median.

%s

keep_resolution never resamples, so it skips the Lanczos pass and its interpolation error (here %s
the build time and %s the error of the default at the largest input); pick it
(`opt.keep_resolution = 1`) when your textures are not powers of two and you do not need pbrt's
pixel-for-pixel behaviour. Keep the default when you compare images with pbrt-v3.
""" % (img1, "%d" % (4000 if args.quick else 100000),
       table(["filter", "anisotropy 1 (ns, error)", "8", "64"], trows),
       tri[0], tri[1], ewa8[1], ewa8[0], ewa64[1], ewa64[0],
       ("The pbrt-v3 port's EWA takes %.0f ns at anisotropy 8 against our %.0f ns (%.1fx)." % (p_ewa[0], o_ewa[0], p_ewa[0] / o_ewa[0])) if p_ewa else "",
       by[(default, "8")][0] / by[("trilinear", "8")][0],
       ("point (%.0f ns) and bilinear (%.0f ns) are no faster than trilinear (%.0f ns) at anisotropy 8 here and alias."
        % (by[("point", "8")][0], by[("bilinear", "8")][0], by[("trilinear", "8")][0]))
       if min(by[("point", "8")][0], by[("bilinear", "8")][0]) > 0.9 * by[("trilinear", "8")][0] else
       ("point (%.0f ns) is faster than trilinear (%.0f ns) but aliases." % (by[("point", "8")][0], by[("trilinear", "8")][0])),
       img2, ", ".join(dict.fromkeys(r[2] for r in build)),
       table(["method", "input width", "build", "error"], brows),
       "%.2fx" % (float(build[-1][3]) / float(build[-2][3])), "%.2fx" % (float(build[-1][4]) / float(build[-2][4]))))
    return {"trilinear64": tri, "ewa8_64": ewa8}


def family_envlight(args, info, md):
    rows = run_csv(args.build, "bench_envlight", args.quick)
    var = [r for r in rows if r[0] == "envvar"]
    build = [r for r in rows if r[0] == "envbuild"]
    nsamp = 20000 if args.quick else 400000
    default = "CELL_AVERAGE (default)"
    imgs = {}
    summary = {}
    for mapname, key in (("city (sun)", "city"), ("studio (smooth)", "studio")):
        rs = [r for r in var if r[1] == mapname]
        fig, (a1, a2) = new_fig(2)
        n = np.logspace(0, 4, 30)
        eff = {}
        for r in rs:
            label, rv, ns, rb2 = r[2], float(r[3]), float(r[4]), float(r[5])
            floor = max(rb2 - rv / nsamp, 0.0)  # the squared bias, the measurement's own noise taken off
            err = rv / n + floor
            kw = style(label.replace(" (default)", ""), default.replace(" (default)", ""))
            kw.pop("marker")
            if label.startswith("PBRT_V3"):
                kw["ls"] = "--"
            a1.plot(n, err, **kw)
            a2.plot(n * ns * 1e-9, err, **kw)
            eff[label] = (rv, ns, floor)
        for ax in (a1, a2):
            ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
            ax.set_ylabel("relMSE of the irradiance estimate")
        a1.set_xlabel("estimates (one light sample each; MIS pair: two samples)")
        a2.set_xlabel("seconds (one thread, CPU time)")
        a1.set_title("Environment importance, %s: relMSE vs samples" % mapname, fontsize=9)
        a2.set_title("relMSE vs time", fontsize=9)
        a2.legend(fontsize=6.5)
        imgs[key] = save(fig, args.out, "envlight_variance_" + key, info, "CELL_AVERAGE importance, guide-table sampler")
        summary[key] = eff

    fig, (a1, a2) = new_fig(2)
    for name in dict.fromkeys(r[1] for r in build):
        pts = [(int(r[2]), float(r[3]), int(r[4])) for r in build if r[1] == name]
        kw = style(name.replace(" (default)", ""), "CELL_AVERAGE")
        if name.startswith("PBRT_V3"):
            kw["ls"] = "--"
        a1.plot([p[0] for p in pts], [p[1] for p in pts], **kw)
        a2.plot([p[0] for p in pts], [p[2] / 2 ** 20 for p in pts], **kw)
    for ax in (a1, a2):
        ax.set_xscale("log", base=2); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
        ax.set_xlabel("map width (height = width / 2)")
    a1.set_ylabel("init + sampling tables, ms (CPU time)"); a2.set_ylabel("el_envlight_bytes, MiB")
    a1.set_title("Environment light: build time vs resolution", fontsize=9)
    a2.set_title("memory vs resolution", fontsize=9)
    a1.legend(fontsize=7)
    imgs["build"] = save(fig, args.out, "envlight_build", info, "CELL_AVERAGE")

    def eff_rows(eff):
        base = eff[default][0] * eff[default][1]
        out = []
        for k, (rv, ns, floor) in eff.items():
            out.append([k, "%.3g" % rv, "%.0f" % ns, "%.3g" % (rv * ns), "%.2g" % floor, "%.2f" % (base / (rv * ns))])
        return out

    c, s = summary["city"], summary["studio"]

    def ratio(m, a, b):
        return (m[a][0] * m[a][1]) / (m[b][0] * m[b][1])
    brow = [[r[1], r[2], "%.1f ms" % float(r[3]), "%.1f MiB" % (int(r[4]) / 2 ** 20)] for r in build]
    md.append("""## Environment light importance sampling

![city](%s)
![studio](%s)

The estimate: the irradiance (luminance) E(n) of a diffuse point, mean over three normals (up, the
horizon, below), from one sample per estimate (uniform sphere, cosine = BSDF sampling, or
`el_envlight_sample_li` with each importance map; `el_envlight_sample_li_cos` for product sampling; the
MIS pairs draw one light and one cosine sample, balance heuristic). Maps: `data/envmaps/city.hdr` (a
3e4 sun: the hard case) and `data/envmaps/studio.hdr` (smooth soft light), 1024x512, CC0.
**Reference**: a quadrature of the bilinear reconstruction (2x2 midpoints per texel). Measured: the
relative variance per estimate over %d estimates per normal, and the squared relative bias (the floor
a biased strategy cannot go below; TEXEL is biased with a bilinear `le`, pbrt-v3 issue #62); the
curves are relMSE(N) = variance / N + bias^2. Time: CPU ns per estimate (sample, pdf, radiance, cosine),
median of interleaved repeats. The dashed curve is pbrt-v3's importance map (2x resolution, point
lookups) sampled by our sampler, the closest the library comes to pbrt-v3's own.

Efficiency relative to the default (1 / (variance x time), default = 1):

city (sun):

%s

studio (smooth):

%s

Read off the plots: on the sun map the product sampler (`el_envlight_sample_li_cos`) is %.0fx as
efficient as the default (it samples the cosine too, so no sample falls below the normal's horizon);
the MIS pair is %.1fx (compensated: %.1fx); cosine (BSDF) sampling alone is %.0fx *less* efficient. On the smooth map the spread is smaller
(product %.1fx, cosine %.1fx less efficient), and there the MIS pair is %.2fx (compensated %.2fx):
its cosine half costs more than it helps for a diffuse point under soft light. The curves are computed
from the measured variance and bias (independent samples: variance / N), so they are parallel lines and
the unbiased strategies never cross; TEXEL meets its bias floor at about N = %s on the
sun map.

- **Student's first renderer**: `el_envlight_sample_li` with the defaults (CELL_AVERAGE): unbiased,
  one call, the tables are built lazily on first use.
- **Production renderer**: MIS of `el_envlight_sample_li` with the BSDF (as the renderer does), or
  `el_envlight_sample_li_cos` for diffuse lobes when the normal is known; compensation
  (`opt.compensated = 1`) with MIS: more efficient than the plain MIS pair on both maps here.
- **Real-time preview**: the default tables, few samples; avoid TEXEL (biased) and cosine sampling on
  sun maps.

### Build time and memory

![build](%s)

Generated city-like maps (bench_envlight's make_map: sky gradient, texture noise, a 3e4 sun), width
512 to 8192 (to 1024 in --quick), the whole `el_envlight_init` + `el_envlight_prepare_sampling` (or
`el_envlight_prepare_product`), CPU time, median of 3 repeats (1 above 2048), and `el_envlight_bytes`.
PBRT_V3 at 8192 is left out; at 8192 the default cap gives CELL_AVERAGE a 4096x2048
importance map (the section [big maps](#big-environment-maps) prices the cap).

%s
""" % (imgs["city"], imgs["studio"], nsamp,
       table(["strategy", "rel. variance", "ns/estimate", "variance x ns (time to unit variance)", "bias^2", "efficiency"], eff_rows(c)),
       table(["strategy", "rel. variance", "ns/estimate", "variance x ns (time to unit variance)", "bias^2", "efficiency"], eff_rows(s)),
       ratio(c, default, "product sample_li_cos"), ratio(c, default, "MIS pair (light + cosine)"),
       ratio(c, default, "MIS pair compensated"),
       ratio(c, "cosine (BSDF)", default), ratio(s, default, "product sample_li_cos"), ratio(s, "cosine (BSDF)", default),
       ratio(s, default, "MIS pair (light + cosine)"), ratio(s, default, "MIS pair compensated"),
       ("%.0f" % (c["TEXEL"][0] / c["TEXEL"][2])) if c["TEXEL"][2] > 0 else "(no measurable bias)",
       imgs["build"], table(["importance", "width", "build", "memory"], brow)))
    return summary


def family_bigmaps(args, info, md):
    """Big maps (issue 24): bench_bigmaps' build cost per size and configuration, the cap's variance, and
    pbrt-v4's equal-area maps against lat-long ones. Tables only."""
    rows = run_csv(args.build, "bench_bigmaps", args.quick)
    bld = [r for r in rows if r[0] == "bigmap_build"]
    cap = [r for r in rows if r[0] == "bigmap_cap"]
    mp = [r for r in rows if r[0] == "bigmap_mapping"]
    t1 = []
    for r in bld:
        f = [float(x) for x in r[4:16]]
        t1.append(["%sx%s" % (r[2], r[3]), r[1], "%.0f" % f[0], "%s x %s" % (r[16], r[17]),
                   "%.0f / %.0f" % (f[4], f[1]), "%.0f / %.0f" % (f[5], f[2]), "%.0f" % (f[4] + f[5]),
                   "%.0f MB (%.3fx)" % (f[7], f[9]), "%.0f / %.0f" % (f[6], f[3]), "%.0f MB (%.2fx)" % (f[8], f[11])])
    t2 = [["no cap" if r[1] == "-1" else r[1], "%s x %s" % (r[4], r[5]), r[6], r[7], r[8], r[9], "%.0f" % float(r[10]), r[11]]
          for r in cap]
    t3 = [[r[1], "%s x %s" % (r[2], r[3]), r[4], r[5], r[6], r[7]] for r in mp]
    big = bld[-1][2] + "x" + bld[-1][3] if bld else "?"
    md.append("""## Big environment maps

bench_bigmaps (issue 24): a generated lat-long map (sky gradient with texel noise, dark ground, a sun of
0.5 degree diameter and radiance 1e5 at 30 degrees elevation, about half the map's power), 1024x512 to %s
(%s in --quick). Configurations: **copy nocap (before)** is the library before issue 24 (a copy of the image,
importance map at its resolution: `importance_cap = -1`); **copy cap (default)** the default now (the
importance map capped at `EL_ENVLIGHT_IMPORTANCE_CAP` = 4096 x 2048 exact cell averages); **no_copy cap**
adds `options.no_copy = 1` (the caller's pixels used in place). Times: CPU (user + system, single thread) /
wall milliseconds of `el_envlight_init`, `el_envlight_prepare_sampling` and `el_envlight_prepare_product`;
the machine was loaded (wall times up to 5x the CPU times). Peak: VmHWM above the caller's image (reset
through /proc/self/clear_refs before each configuration), in MB and as a fraction of the image's bytes,
after the sampling tables and after the product tables.

%s

The cap's variance on the %s map: relative variance per sample of sample_li's estimate of the map's
luminance integral (lum(le) / pdf: how well the density follows the map), and of the irradiance of a
surface facing up and one facing the sun; bias in standard errors against the exact integral; the
sampling tables' build (CPU ms, the caller's pixels) and size.

%s

pbrt-v4's equal-area maps (`options.mapping = EL_ENVLIGHT_MAPPING_EQUAL_AREA`, sampled natively) against a
lat-long map of the same texel count: CPU ns per call (2^20 calls) and the tables' build (CPU ms).

%s

- **Student's first renderer**: the defaults; maps up to 4096x2048 are unchanged by the cap.
- **Production renderer**: for 8k and 16k maps keep the image and pass `no_copy = 1` (init reads it once,
  the light adds 0.05x of a 16k image); raise `importance_cap` (or -1) on sun maps when the memory is
  there: the table above prices each step.
- **Real-time preview**: `importance_cap = 1024` or 2048 (4.7 / 18 MB of tables) and few samples.
""" % (big, "2048x1024", table(["map", "configuration", "image MB", "importance", "init ms CPU / wall", "sampling ms CPU / wall",
                                 "init + sampling CPU ms", "peak after sampling", "product ms CPU / wall", "peak after product"], t1),
       cap[0][2] + "x" + cap[0][3] if cap else "?",
       table(["cap", "importance", "rel. var. lum", "rel. var. E up", "rel. var. E sun", "bias / se", "build ms", "tables MB"], t2),
       table(["mapping", "map", "sample_li ns", "pdf_li ns", "le ns", "tables ms"], t3)))


def render_family(args, info, md, tmp, refs, res):
    spps = [1, 4] if args.quick else [1, 4, 16, 64]
    reps = 1 if args.quick else 3
    out = {}
    # ---- light strategies (a glossy sphere, so that BSDF sampling has a chance) ----
    strat = [("MIS", ["--light-sampling", "mis"]), ("light only", ["--light-sampling", "light"]),
             ("BSDF only", ["--light-sampling", "bsdf"]), ("MIS + compensation", ["--light-sampling", "mis", "--compensated", "1"]),
             ("MIS, map alone (pbrt-v3)", ["--light-sampling", "mis", "--env-sampling", "map"]),
             ("MIS, map alone, cell-average", ["--light-sampling", "mis", "--env-sampling", "map", "--importance", "cellaverage"])]
    strat_imgs = {}
    strat_res = {}
    for key in ("city", "studio"):
        ref = refs["glossy_" + key]
        t0 = time.time()
        raw = sweep(args.build, tmp, ref.scene, ref, strat, spps, reps)
        res_s = pooled(raw)
        print("  render strategies on %s: %.1f s" % (key, time.time() - t0), flush=True)
        fig, (ax,) = new_fig()
        for label, pts in res_s.items():
            ax.plot([p[1] for p in pts], [p[2] for p in pts], **style(label, "MIS"))
        for label, pts in res_s.items():
            if label == "MIS":
                for s, t, e in pts:
                    ax.annotate("%d spp" % s, (t, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
        ax.set_xlabel("render CPU seconds (1 thread, median)"); ax.set_ylabel("relMSE vs reference")
        ax.set_title("Renderer light strategies, glossy sphere under %s" % key, fontsize=9)
        ax.legend(fontsize=7)
        strat_imgs[key] = save(fig, args.out, "render_strategies_" + key, info,
                               "MIS (power heuristic), product sampling (map x cosine), no compensation")
        strat_res[key] = res_s
    out["strategies"] = strat_res
    # ---- samplers (the matte scenes as bench_render has them) ----
    samplers = ["random", "stratified", "halton", "sobol", "02sequence", "zsobol", "paddedsobol"]
    samp_imgs = {}
    samp_res = {}
    for key in ("city", "studio"):
        ref = refs["matte_" + key]
        t0 = time.time()
        raw = sweep(args.build, tmp, ref.scene, ref, [(s, ["--sampler", s]) for s in samplers], spps, reps)
        res_s = pooled(raw)
        print("  render samplers on %s: %.1f s" % (key, time.time() - t0), flush=True)
        fig, (a1, a2) = new_fig(2)
        for label, pts in res_s.items():
            kw = style(label, "stratified")
            a1.plot([p[0] for p in pts], [p[2] for p in pts], **kw)
            a2.plot([p[1] for p in pts], [p[2] for p in pts], **kw)
        for ax in (a1, a2):
            ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
            ax.set_ylabel("relMSE vs reference")
        a1.set_xlabel("samples per pixel"); a2.set_xlabel("render CPU seconds (1 thread, median)")
        a1.set_title("Samplers, matte scene under %s: relMSE vs spp" % key, fontsize=9)
        a2.set_title("relMSE vs time", fontsize=9)
        a1.legend(fontsize=7)
        samp_imgs[key] = save(fig, args.out, "render_samplers_" + key, info, "the scene's Sampler (bench scenes: stratified)")
        samp_res[key] = res_s
    out["samplers"] = samp_res
    # ---- splitting: the infinite light's "samples" ----
    splits = [1, 4, 16] if not args.quick else [1, 4]
    ref = refs["matte_city"]
    scenes = {} if REPLOT else {k: make_scene("bench_city.pbrt", os.path.join(tmp, "split%d.pbrt" % k), res, light_samples=k) for k in splits}
    sp_spps = [1, 4, 16] if not args.quick else [1, 4]

    def split_now():
        times, errs = {}, {}
        t0 = time.time()
        for r in range(reps):
            for s in sp_spps:
                for k in splits:
                    img, t = render(args.build, scenes[k], tmp, s, 1 + r)
                    times.setdefault((k, s), []).append(t)
                    errs.setdefault((k, s), []).append(ref.error(img))
        print("  render splitting: %.1f s" % (time.time() - t0), flush=True)
        return [[k, [(s, statistics.median(times[(k, s)]), statistics.mean(errs[(k, s)])) for s in sp_spps]]
                for k in splits]
    split_list = measured("splitting", split_now)
    fig, (ax,) = new_fig()
    split_res = {}
    for k, pts in split_list:
        pts = per_spp(pts)[0]
        split_res[k] = pts
        ax.plot([p[1] for p in pts], [p[2] for p in pts], **style("%d light + %d BSDF samples" % (k, k), "1 light + 1 BSDF samples"))
        for s, t, e in pts:
            ax.annotate("%d spp" % s, (t, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
    ax.set_xlabel("render CPU seconds (1 thread, median)"); ax.set_ylabel("relMSE vs reference")
    ax.set_title('Splitting: the infinite light\'s "samples" per camera sample (city, matte)', fontsize=9)
    ax.legend(fontsize=7)
    split_img = save(fig, args.out, "render_splitting", info, '"samples" 1')
    out["splitting"] = split_res

    def rows_of(res_s):
        return [[lab, "%.2f ms" % (1e3 * pts[0][1] / pts[0][0])] + ["%.3g" % e for s, t, e in pts] for lab, pts in res_s.items()]

    def cross_text(res_s, a, b):
        c = crossover([(p[1], p[2]) for p in res_s[a]], [(p[1], p[2]) for p in res_s[b]])
        return ("%s and %s cross at about %s of render time" % (a, b, fmt_t(c))) if c else ("%s and %s do not cross in the measured range" % (a, b))

    def best(res_s, i):
        return min(res_s, key=lambda k: res_s[k][i][2])

    def eff(res_s, a, b, i=-1):
        """how many times as efficient a is as b at point i (1 / (relMSE x time))"""
        return (res_s[b][i][2] * res_s[b][i][1]) / (res_s[a][i][2] * res_s[a][i][1])

    def near_best(res_s, i=-1, tol=1.15):
        b = res_s[best(res_s, i)][i][2]
        return [k for k in res_s if res_s[k][i][2] <= tol * b]

    ref_txt = ", ".join("%s: %d spp (noise %.2g)" % (k, r.spp, r.noise) for k, r in sorted(refs.items()))
    head = ["option", "CPU per spp"] + ["%d spp: relMSE" % s for s in spps]
    sc, ss = strat_res["city"], strat_res["studio"]
    pc, ps = samp_res["city"], samp_res["studio"]
    costs = [pts[0][1] / pts[0][0] for res_s in (pc, ps) for pts in res_s.values()]
    sp_eff = ["samples %d: %.2fx" % (k, eff(split_res, k, 1)) for k in splits[1:]]
    sp_eq = []
    for k in splits[1:]:  # k light samples at s spp against 1 light sample at k*s spp (equal shading work)
        for s in sp_spps:
            if k * s in sp_spps:
                e1 = [p for p in split_res[1] if p[0] == k * s][0]
                ek = [p for p in split_res[k] if p[0] == s][0]
                sp_eq.append("%d spp x %d light samples: relMSE %.3g in %s; %d spp x 1: %.3g in %s" % (
                    s, k, ek[2], fmt_t(ek[1]), k * s, e1[2], fmt_t(e1[1])))
    split_wins = all(eff(split_res, k, 1) > 1 for k in splits[1:])
    ec, es = eff(sc, "MIS + compensation", "MIS"), eff(ss, "MIS + compensation", "MIS")
    comp_text = ("measured %.2fx the efficiency of plain MIS on city and %.2fx on studio: %s" % (
        ec, es, "turn it on" if min(ec, es) > 1.05 else "leave it off" if max(ec, es) < 0.95 else
        "within this run's noise of plain MIS; the environment-light family above shows its gain per sample"))
    md.append("""## Renderer: light strategies

![city](%s)
![studio](%s)

`build/bin/render` on variants of `scenes/bench_city.pbrt` and `scenes/bench_studio.pbrt` (a sphere
on a plane under the map, direct lighting) at %dx%d, the sphere made glossy (`plastic`, roughness 0.01,
so that BSDF sampling has something to gain). Options are the renderer's `--light-sampling
light|bsdf|mis`, `--compensated 1`, `--env-sampling map` (pbrt-v3's strategy: the map alone, with
pbrt-v3's importance map; the renderer's default is product sampling of the map times the cosine,
`el_envlight_sample_li_cos`) and, with it, `--importance cellaverage`. **Reference**: zsobol, two independent halves averaged, the reference's own noise
(relMSE of the halves / 4) taken off every number (%s). relMSE = mean over pixels and channels of
(I - R)^2 / (R^2 + 0.01), the mean over %d repeats with different seeds. **Time**: the render loop's CPU
time (one thread; `render --stats`, without parsing and table builds), median of the %d repeats with all
options interleaved; since the loop's cost is linear in spp and one render's time is noisy on this shared
machine, each curve uses one cost per spp pooled over its runs (sum of the medians / sum of spp: the
"CPU per spp" column; the raw medians are in measurements.json).

city:

%s

studio:

%s

Read off the plots: %s; %s on the sun map; %s on the studio map. Lowest error at %d spp: %s on city, %s
on studio. At %d spp, MIS is %.1fx as efficient (1 / (relMSE x time)) as light sampling alone on city
and %.1fx on studio; BSDF sampling alone is %.0fx less efficient than MIS on city. Compensation: %.2fx
the efficiency of MIS on city, %.2fx on studio. Product sampling (the default) against the map alone
(pbrt-v3's importance): %.2fx the efficiency on city, %.2fx on studio; the map alone with envlight's cell
averages against pbrt-v3's importance map: %.2fx on city, %.2fx on studio.

- **Student's first renderer**: light sampling only is the shortest correct code; on the smooth map MIS
  has %.2fx its efficiency, but on the sun map with a glossy sphere MIS is %.1fx ahead: move to MIS as
  soon as there is a glossy material.
- **Production renderer**: MIS (the default): never far behind, far ahead where it matters.
  Compensation (`"bool compensated" true` on the light) %s.
- **Real-time preview**: MIS at 1-4 spp; BSDF-only sampling is never competitive under these maps.

## Renderer: samplers

![city](%s)
![studio](%s)

The matte scenes as they are (the bench scenes bench_render --samplers uses), at %dx%d, `--sampler S`
with pbrt's parameters; spp %s (the Sobol'-type samplers round up to a power of two, so these are
exact). Same reference and timing as above.

city:

%s

studio:

%s

Read off the plots: at %d spp the lowest error is %s on city and %s on studio; within 15%% of the best:
%s on city, %s on studio. Random sampling's error at %d spp is %.1fx the best on city and %.1fx on studio;
pbrt-v3's unscrambled global sobol is %.1fx the best on city. The cost per sample varies by %.0f%% from
the cheapest to the dearest sampler in this run (the samplers' own cost and this machine's noise are not
told apart here; `bench_render --callgrind samples N --sampler S` counts instructions); the error per
sample varies far more. %s on studio.

- **Student's first renderer**: stratified (what pbrt-v3's scenes use): simple to write, and at %d spp
  %.1fx the best error on city, %.1fx on studio.
- **Production renderer**: %s: within 15%% of the lowest error at %d spp on both maps here, and
  randomized, so unbiased at any spp (zsobol and paddedsobol are pbrt-v4's).
- **Real-time preview**: zsobol at low spp (pbrt-v4's default).

## Renderer: splitting

![splitting](%s)

`"integer samples" [k]` on the infinite light of bench_city.pbrt (matte, %dx%d): directlighting draws k
light samples and k BSDF samples per camera sample (MIS). Curves per k, points per spp (%s); the
scene's stratified sampler. Same reference and timing as above.

%s

Efficiency at the largest spp against samples 1: %s. At equal shading work: %s.

Read off the plot: %s. Splitting saves the camera rays, intersections and film work of the extra camera
samples; on this cheap scene (two primitives) that saving is small, and splitting %s. More camera
samples also antialias edges and textures, which splitting never does.

- **Student's first renderer**: samples 1, more spp.
- **Production renderer**: %s; splitting can pay where camera rays are expensive (many
  triangles, deep paths) and the variance is in the lighting; that is not measured here: measure on
  your own scenes.
- **Real-time preview**: 1 spp with samples 4-16 gives the smoothest first frame when only one camera
  sample per pixel fits in the budget.
""" % (strat_imgs["city"], strat_imgs["studio"], res[0], res[1], ref_txt, reps, reps,
       table(head, rows_of(sc)), table(head, rows_of(ss)),
       cross_text(sc, "MIS", "light only"), cross_text(sc, "MIS", "BSDF only"), cross_text(ss, "MIS", "BSDF only"),
       spps[-1], best(sc, -1), best(ss, -1), spps[-1],
       eff(sc, "MIS", "light only"), eff(ss, "MIS", "light only"), eff(sc, "MIS", "BSDF only"),
       eff(sc, "MIS + compensation", "MIS"), eff(ss, "MIS + compensation", "MIS"),
       eff(sc, "MIS", "MIS, map alone (pbrt-v3)"), eff(ss, "MIS", "MIS, map alone (pbrt-v3)"),
       eff(sc, "MIS, map alone, cell-average", "MIS, map alone (pbrt-v3)"), eff(ss, "MIS, map alone, cell-average", "MIS, map alone (pbrt-v3)"),
       eff(ss, "MIS", "light only"), eff(sc, "MIS", "light only"),
       comp_text,
       samp_imgs["city"], samp_imgs["studio"], res[0], res[1], ", ".join(map(str, spps)),
       table(head, rows_of(pc)), table(head, rows_of(ps)),
       spps[-1], best(pc, -1), best(ps, -1), ", ".join(near_best(pc)), ", ".join(near_best(ps)),
       spps[-1], pc["random"][-1][2] / pc[best(pc, -1)][-1][2], ps["random"][-1][2] / ps[best(ps, -1)][-1][2],
       pc["sobol"][-1][2] / pc[best(pc, -1)][-1][2], 100 * (max(costs) / min(costs) - 1),
       cross_text(ps, "random", "zsobol"),
       spps[-1], pc["stratified"][-1][2] / pc[best(pc, -1)][-1][2], ps["stratified"][-1][2] / ps[best(ps, -1)][-1][2],
       ", ".join(k for k in near_best(pc) if k in near_best(ps)), spps[-1],
       split_img, res[0], res[1], ", ".join(map(str, sp_spps)),
       table(["light samples", "CPU per spp"] + ["%d spp: relMSE" % s for s in sp_spps],
             [["%d" % k, "%.2f ms" % (1e3 * split_res[k][0][1] / split_res[k][0][0])] + ["%.3g" % e for s, t, e in split_res[k]]
              for k in splits]),
       "; ".join(sp_eff), "; ".join(sp_eq) if sp_eq else "(no pair at equal work in this run)",
       "; ".join(cross_text({("samples %d" % k): v for k, v in split_res.items()}, "samples 1", "samples %d" % k)
                 for k in splits[1:]),
       "loses here" if not split_wins else "does not win here",
       "samples 1 on scenes like this one" if not split_wins else "samples %d on scenes like this one" % splits[-1]))
    return out


def family_film(args, info, md):
    rows = run_csv(args.build, "bench_film", args.quick)
    fl = [r for r in rows if r[0] == "filter"]
    di = [r for r in rows if r[0] == "dither"]
    fig, (a1, a2) = new_fig(2)
    colors = {}
    for name in dict.fromkeys(r[1] for r in fl):
        for w in ("table", "exact"):
            pts = [(float(r[4]), float(r[5]), float(r[6]), r[3]) for r in fl if r[1] == name and r[2] == w]
            kw = style(name + ("" if w == "table" else " (exact weights)"), "box")
            if w == "exact":
                kw["ls"] = "--"; kw["lw"] = 1; kw["color"] = colors[name]
            ln, = a1.plot([p[0] for p in pts], [p[1] for p in pts], **kw)
            a2.plot([p[0] for p in pts], [p[2] for p in pts], **kw)
            colors[name] = ln.get_color()
            if name == "box" and w == "table":
                for x, y, z, s in pts:
                    a1.annotate(s + " spp", (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    for ax in (a1, a2):
        ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
        ax.set_xlabel("ms per 96x96 image (CPU time, median)")
    a1.set_ylabel("aliasing: rms(pixel - 0.5) above Nyquist"); a2.set_ylabel("detail loss: rms vs chart, below 0.2 c/px")
    a1.set_title("Pixel filters on a zone plate: aliasing vs time", fontsize=9)
    a2.set_title("blur vs time", fontsize=9)
    a1.legend(fontsize=6)
    img1 = save(fig, args.out, "film_filters", info, "box (pbrt-v3's default filter; film.h's all-zero options), 16x16 weight table")

    fig, (ax,) = new_fig()
    for r in di:
        ax.plot([float(r[2])], [float(r[3])], "o", ms=7, label=r[1] + ": per pixel")
        ax.plot([float(r[2])], [float(r[4])], "s", ms=7, label=r[1] + ": 8x8 average (banding)")
    ax.set_xscale("log"); ax.set_yscale("log"); ax.grid(True, which="both", alpha=0.3)
    ax.set_xlabel("ns per pixel (el_film_to_srgb8, CPU time, median)"); ax.set_ylabel("rms error after 8-bit decode (linear)")
    ax.set_title("8-bit output of a slow ramp: rounding vs TPDF dithering", fontsize=9)
    ax.legend(fontsize=7)
    img2 = save(fig, args.out, "film_dither", info, "round to nearest (pbrt's), no dithering")

    def at(name, w, i):
        pts = [r for r in fl if r[1] == name and r[2] == w]
        return pts[-1][i]
    last_spp = fl[-1][3]
    frows = [[r[1], r[2], r[3], "%.2f ms" % float(r[4]), "%.3g" % float(r[5]), "%.3g" % float(r[6])] for r in fl
             if r[2] == "table" or r[3] == last_spp]
    drows = [[r[1], "%.1f" % float(r[2]), "%.3g" % float(r[3]), "%.3g" % float(r[4])] for r in di]
    cx = crossover([(float(r[4]), float(r[5])) for r in fl if r[1] == "box" and r[2] == "table"],
                   [(float(r[4]), float(r[5])) for r in fl if r[1] == "triangle" and r[2] == "table"])
    md.append("""## Film: pixel filters and 8-bit output

![filters](%s)

A 96x96 film of a zone plate 0.5 + 0.5 cos(k r^2), whose local frequency rises from 0 at the centre to
1 cycle per pixel at the corners (twice the Nyquist limit); SPP jittered samples per pixel, the same
samples for every filter; `el_film_add_sample` with each of pbrt's filters at pbrt's radii, with the
16x16 weight table (the default, pbrt's) and with exact weights (dashed); the default filter is box
(pbrt-v3's). **Reference**: the ideal
antialiased image is flat grey (0.5) where the chart's frequency exceeds Nyquist; the left plot's error
is what is left there (aliasing plus noise), the right plot's is the blur: the difference from the
chart's value at pixel centres where its frequency is below 0.2 cycles/pixel. Time: CPU time of the whole
image (sample positions, chart, film), median of 3 interleaved repeats.

%s

Read off the plots: box aliases most, and its aliasing stays at %s however many samples (a box passes
much of what lies above Nyquist); triangle suppresses aliasing best (%s at the largest spp) but blurs
the most (%s); gaussian and Mitchell sit between; Lanczos (pbrt's "sinc") keeps the most detail (%s)
but its negative lobes make it unstable at 1 spp (aliasing error %s) and it is the slowest. %s. Exact weights cost %sx the table's time for Lanczos and change its aliasing error by %s at the largest
spp: keep the table.

- **Student's first renderer**: box (pbrt-v3's default, the simplest), knowing that its aliasing does
  not go away with more samples; gaussian is the one-line change that fixes that.
- **Production renderer**: gaussian or Mitchell with the table, at 16+ spp.
- **Real-time preview**: box or triangle at 1-4 spp; never Lanczos at low spp.

![dither](%s)

`el_film_to_srgb8` of a linear ramp from 0.10 to 0.12 over 1024 pixels (about 8 sRGB codes): the
decoded 8-bit value against the true one, per pixel and after an 8x8 box average (the banding one sees
from a distance).

%s

Dithering raises the per-pixel error %.1fx but cuts the banding error by %.1fx, for %.1fx the time of
the conversion. Turn it on (`o.dither = 1`) for any 8-bit image of smooth gradients (skies); leave it off when
images are compared bit for bit.
""" % (img1, table(["filter", "weights", "spp", "time", "aliasing", "detail loss"], frows),
       "%.3f" % float(at("box", "table", 5)), "%.4f" % float(at("triangle", "table", 5)),
       "%.3f" % float(at("triangle", "table", 6)), "%.3f" % float(at("lanczos", "table", 6)),
       "%.2f" % float([r for r in fl if r[1] == "lanczos" and r[2] == "table"][0][5]),
       ("box and triangle cross at %s per image" % fmt_t(cx / 1e3)) if cx else "box and triangle do not cross in the measured range",
       "%.1f" % (float(at("lanczos", "exact", 4)) / float(at("lanczos", "table", 4))),
       "%.0f%%" % (100 * abs(float(at("lanczos", "exact", 5)) / float(at("lanczos", "table", 5)) - 1)),
       img2, table(["mode", "ns/pixel", "per-pixel rms", "8x8 banding rms"], drows),
       float(di[1][3]) / float(di[0][3]), float(di[0][4]) / float(di[1][4]), float(di[1][2]) / float(di[0][2])))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="tiny sizes, one repeat (CI)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="the CMake build directory")
    ap.add_argument("--out", default=None, help="output directory (default docs/, build/report-quick with --quick)")
    ap.add_argument("--replot", action="store_true", help="redraw from OUT/measurements.json without measuring")
    args = ap.parse_args()
    global REPLOT, MEAS
    if args.out is None:
        args.out = os.path.join(ROOT, "build", "report-quick") if args.quick else os.path.join(ROOT, "docs")
    os.makedirs(os.path.join(args.out, "img"), exist_ok=True)
    tmp = os.path.join(args.build, "report-tmp")
    os.makedirs(tmp, exist_ok=True)
    jpath = os.path.join(args.out, "measurements.json")
    if args.replot:
        REPLOT = True
        with open(jpath) as f:
            MEAS = json.load(f)
        if MEAS.get("quick") != args.quick:
            sys.exit("report.py: --replot: %s was measured %s --quick" % (jpath, "with" if MEAS.get("quick") else "without"))
    MEAS["quick"] = args.quick
    info = measured("info", lambda: machine_info(args.build))
    t_start = time.time()
    try:
        load = measured("load_start", lambda: os.getloadavg())
    except OSError:
        load = (0, 0, 0)
    md = []
    print("report.py: measuring (%s)" % ("quick" if args.quick else "full"), flush=True)
    family_mipmap(args, info, md)
    family_envlight(args, info, md)
    family_bigmaps(args, info, md)
    res = (32, 24) if args.quick else (128, 96)
    ref_spp = 64 if args.quick else 512
    glossy = 'Material "plastic" "rgb Kd" [ 0.3 0.3 0.3 ] "rgb Ks" [ 0.5 0.5 0.5 ] "float roughness" 0.01'
    refs = {}
    t0 = time.time()
    for key, base in (("city", "bench_city.pbrt"), ("studio", "bench_studio.pbrt")):
        for kind, mat in (("matte", None), ("glossy", glossy)):
            scene = os.path.join(tmp, "%s_%s.pbrt" % (kind, key))
            if REPLOT:
                ref = Reference.__new__(Reference)
            else:
                make_scene(base, scene, res, material=mat)
                ref = Reference(args.build, scene, tmp, ref_spp)
            d = measured("ref:%s_%s" % (kind, key), lambda: {"spp": ref.spp, "noise": ref.noise})
            ref.spp, ref.noise, ref.scene = d["spp"], d["noise"], scene
            refs["%s_%s" % (kind, key)] = ref
    print("  references: %.1f s" % (time.time() - t0), flush=True)
    render_family(args, info, md, tmp, refs, res)
    family_film(args, info, md)
    elapsed = measured("elapsed", lambda: time.time() - t_start)
    try:
        load_end = measured("load_end", lambda: os.getloadavg())
    except OSError:
        load_end = (0, 0, 0)
    if not REPLOT:
        with open(jpath, "w") as f:
            json.dump(MEAS, f, indent=0)
    head = """# What accuracy costs in time

Generated by `sh scripts/report.sh`%s (bench/report.py) on %s. Machine: %s, %d cores; %s; build: %s;
envlight commit %s. The whole run took %.0f s. The machine is shared: other work was running during the
measurements (load average %.1f at the start, %.1f at the end; on the day of the committed run, other
helpers were building on the same two cores), so every time is a median of repeats with the options
interleaved, and benchmark loops are timed in the thread's CPU time. Small differences (under about
10%%) between two curves are within this machine's noise.

Every plot is log-log: error against time (or memory), one curve per option, the default drawn thick
and marked "[default]", the machine, date and build under each plot. Each section says what the error
is measured against, then which option to pick for a student's first renderer, a production renderer
and a real-time preview, and where the curves cross.

Contents: [MIP map lookups](#mip-map-lookups) · [environment light importance](#environment-light-importance-sampling) ·
[big maps](#big-environment-maps) ·
[light strategies](#renderer-light-strategies) · [samplers](#renderer-samplers) ·
[splitting](#renderer-splitting) · [film](#film-pixel-filters-and-8-bit-output)

Plots are drawn with matplotlib %s and numpy %s from Debian (python3-matplotlib, python3-numpy), which
`scripts/report.sh` installs with apt-get when they are missing, like every other dependency of the
build (scripts/setup.sh): the same channel and the distribution's tested versions, no virtualenv and no
network access to PyPI needed.
""" % (" --quick" if args.quick else "", info["date"], info["cpu"], info["nproc"], info["cc"], info["flags"],
       info["commit"], elapsed, load[0], load_end[0], matplotlib.__version__, np.__version__)
    if args.quick:
        head += "\n**This is a --quick run** (tiny sizes, one repeat): it checks that the command works; read the numbers of the full run in docs/.\n"
    with open(os.path.join(args.out, "accuracy-vs-time.md"), "w") as f:
        f.write(head + "\n" + "\n".join(md))
    problems = check_report.check(args.out, args.quick)  # every expected file, linked, a real PNG
    if problems:
        sys.exit("report.py: " + "\nreport.py: ".join(problems))
    shutil.rmtree(tmp, ignore_errors=True)
    print("report.py: wrote %s/accuracy-vs-time.md and %d plots in %.0f s" % (args.out, len(EXPECTED_PLOTS), elapsed))


if __name__ == "__main__":
    main()
