#!/usr/bin/env python3
"""lobes.py: issue 20's "every lobe" measurement: the renderer's default environment sampling against
the map alone, per material and over the image. Two map-alone baselines: "map" (--env-sampling map with
render's default density: le()'s patch density, importance bilinear, under a sun map with a low-discrepancy
sampler since issue 22, so on lobes_city; pbrt-v3's elsewhere) and "map3" (--env-sampling map --importance
pbrt-v3, pbrt-v3's own strategy); every other strategy's ratio is printed against both.
Last run (2026-12-02, 8 seeds, 16 spp; examples/render/README.md "Sampling the environment"), default
against map / map3: city image 1.38 / 1.19, metal 1.03 / 0.88, glossy 2.70 / 2.29, rough 3.93 / 3.56, plane
1.14 / 1.06, shadows 1.14 / 0.91; studio image 5.01 / 5.02, every region 4.2-23x.

Scenes: scenes/lobes_city.pbrt and scenes/lobes_studio.pbrt (a near-specular metal, alpha 0.02; a glossy
plastic, pbrt-v3 roughness 0.1 remapped, alpha 0.46; a rough plastic, roughness 0.5, alpha 1.13; on a
diffuse plane; directlighting, stratified 4x4, one light + one BSDF sample). Regions: the whole image and
one crop window per material (Film "cropwindow", written to a temporary copy of the scene: the crop's time
is the time of its pixels alone): a square inside each sphere's disk, the plane's strip in front of them, and
the strip with the spheres' shadows (city's sun is behind them).
Error: the RELATIVE VARIANCE ACROSS SEEDS, the mean over pixels and channels of the variance of the
seeds' images over (mean^2 + 1e-2), as bench/mitsuba_compare.py. Time: the render loop's CPU seconds
(render --stats, one thread), the mean over seeds. Time to unit variance (TTUV) = relvar x CPU s; the
ratio printed is TTUV(map alone) / TTUV(default): above 1 the default wins.
Runs are interleaved (every strategy once per seed, the order rotating), as the machine is shared.
  python3 bench/lobes.py [--seeds 8] [--spp 16] [--render build/bin/render] [--maps city,studio]
                         [--regions full,metal,glossy,rough,plane,shadows] [--extra "--env-lobe-alpha 0"] [--metal-alpha 0.2]
                         [--variants "s2=--split 2;sc=--env-sun-diffuse suncos"]
--extra: options added to the default's command line (e.g. render's --env-lobe-alpha and --env-light-alpha, the
per-lobe thresholds); --variants: more strategies (name=options, ';'-separated: levers), each against both
baselines; --metal-alpha, --glossy-alpha: the metal's and the glossy plastic's Trowbridge-Reitz alpha
(sweeps for the thresholds).
"""
import argparse, os, re, struct, subprocess, sys, tempfile, array

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CROPS = {  # NDC crop windows (x0 x1 y0 y1): squares inside each sphere's disk, the plane in front of them
    'full': None,
    'metal': (0.19, 0.31, 0.27, 0.57),
    'glossy': (0.44, 0.56, 0.27, 0.57),
    'rough': (0.69, 0.81, 0.27, 0.57),
    'plane': (0.0, 1.0, 0.85, 1.0),
    'shadows': (0.0, 1.0, 0.71, 0.84),  # the plane in the spheres' shadows from city's sun (and below them)
}


def read_pfm(path):
    with open(path, 'rb') as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = array.array('f')
        data.frombytes(f.read())
        if scale > 0: data.byteswap()
    nc = 3 if kind == b'PF' else 1
    assert len(data) == w * h * nc, path
    return data


def run(render, scene, seed, spp, extra):
    out = tempfile.mktemp(suffix='.pfm', dir=TMP)
    cmd = [render, scene, '--outfile', out, '--seed', str(seed), '--spp', str(spp), '--nthreads', '1', '--quiet',
           '--stats'] + extra
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0: sys.exit('render failed: %s\n%s' % (' '.join(cmd), p.stderr))
    m = re.search(r'render\s+[\d.]+ s\s+\(CPU ([\d.]+) s\)', p.stdout + p.stderr)
    img = read_pfm(out)
    os.unlink(out)
    return img, float(m.group(1)), p.stdout + p.stderr


def relvar(imgs):
    n = len(imgs)
    tot = 0.0
    for i in range(len(imgs[0])):
        vals = [im[i] for im in imgs]
        m = sum(vals) / n
        v = sum((x - m) ** 2 for x in vals) / (n - 1)
        tot += v / (m * m + 1e-2)
    return tot / len(imgs[0])


def main():
    global TMP
    ap = argparse.ArgumentParser()
    ap.add_argument('--seeds', type=int, default=8)
    ap.add_argument('--spp', type=int, default=16)
    ap.add_argument('--render', default=os.path.join(ROOT, 'build', 'bin', 'render'))
    ap.add_argument('--maps', default='city,studio')
    ap.add_argument('--regions', default='full,metal,glossy,rough,plane,shadows')
    ap.add_argument('--extra', default='')
    ap.add_argument('--variants', default='', help='more default-like strategies, "name=options;name2=options" (levers), each against both baselines')
    ap.add_argument('--metal-alpha', type=float, default=None, help="the metal sphere's alpha instead of 0.02 (threshold sweeps)")
    ap.add_argument('--glossy-alpha', type=float, default=None, help="the glossy plastic's alpha instead of 0.46")
    a = ap.parse_args()
    TMP = tempfile.mkdtemp(prefix='lobes')
    # the baselines: the map alone with render's default density ("map": le()'s patch density under a sun
    # map with a low-discrepancy sampler since issue 22, pbrt-v3's elsewhere) and with pbrt-v3's ("map3")
    strategies = [('default', a.extra.split()), ('map', ['--env-sampling', 'map']),
                  ('map3', ['--env-sampling', 'map', '--importance', 'pbrt-v3'])]
    for v in filter(None, a.variants.split(';')):
        k, _, ex = v.partition('=')
        strategies.append((k.strip(), ex.split()))
    others = [k for k, _ in strategies if k not in ('map', 'map3')]
    print('relvar across %d seeds, %d spp, CPU s of the render loop (1 thread; machine shared); TTUV ratios against'
          ' the map alone with the default density (map) and with pbrt-v3\'s (map3)' % (a.seeds, a.spp))
    print('| map | region | ' + ' | '.join('%s relvar | %s CPU s' % (k, k) for k, _ in strategies) + ' | ' +
          ' | '.join('%s: map/x, map3/x' % k for k in others) + ' |')
    print('|---|---|' + '---|---|' * len(strategies) + '---|' * len(others))
    for mp in a.maps.split(','):
        src = open(os.path.join(ROOT, 'scenes', 'lobes_%s.pbrt' % mp)).read()
        src = src.replace('"../data/', '"%s/data/' % ROOT)
        if a.metal_alpha is not None:
            src = src.replace('"float roughness" [ 0.02 ]', '"float roughness" [ %g ]' % a.metal_alpha)
        if a.glossy_alpha is not None:
            src = src.replace('"float roughness" [ 0.1 ]', '"float roughness" [ %g ] "bool remaproughness" "false"' % a.glossy_alpha)
        for reg in a.regions.split(','):
            text = src
            if CROPS[reg]:
                text = text.replace('"string filename"', '"float cropwindow" [ %g %g %g %g ] "string filename"' % CROPS[reg])
            scene = os.path.join(TMP, 'lobes_%s_%s.pbrt' % (mp, reg))
            open(scene, 'w').write(text)
            imgs = {k: [] for k, _ in strategies}
            cpu = {k: [] for k, _ in strategies}
            for s in range(a.seeds):
                rot = s % len(strategies)  # the order rotating per seed (the machine is shared)
                order = strategies[rot:] + strategies[:rot]
                for k, ex in order:
                    img, t, _ = run(a.render, scene, s + 1, a.spp, ex)
                    imgs[k].append(img)
                    cpu[k].append(t)
            r = {}
            for k, _ in strategies:
                v = relvar(imgs[k])
                t = sum(cpu[k]) / len(cpu[k])
                r[k] = (v, t, min(cpu[k]), max(cpu[k]))
            ttuv = {k: r[k][0] * r[k][1] for k in r}
            print('| %s | %s | ' % (mp, reg) + ' | '.join('%.4g | %.3f' % (r[k][0], r[k][1]) for k, _ in strategies) + ' | ' +
                  ' | '.join('%.2f, %.2f' % (ttuv['map'] / ttuv[k], ttuv['map3'] / ttuv[k]) for k in others) + ' |')
            sys.stdout.flush()


if __name__ == '__main__':
    main()
