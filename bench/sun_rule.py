#!/usr/bin/env python3
"""sun_rule.py: issue 20's sun rule measured: how diffuse-only vertices under a sun map (render.c's
elr__sun_share > ELR_ENV_SUN_SHARE: city.hdr, sunrise.hdr) sample it, render's --env-sun-diffuse
map (the map alone with MIS), product (the product light sample with MIS) or alone (the product light
sample alone), against the map alone everywhere (--env-sampling map, pbrt-v3's).

For each scene, strategy and seed (runs interleaved, the order rotating per seed, as the machine is shared)
one render at --nthreads 1; regions: the whole image, and the pixels the choice changes (those where the
map-with-MIS rule's (mapmis, else default) and product's images differ for seed 1) split into LIT and SHADOWED at 0.3x the 90th percentile of
their mean luminance (the sun seen or not), or a crop window (lobes_city's plane strip and shadow strip, as
bench/lobes.py: the crop's own CPU time). Error: relative variance across seeds (bench/lobes.py's); time:
the render loop's CPU seconds (render --stats), the mean over seeds; the ratio printed is
TTUV(map alone) / TTUV(strategy) (relvar x CPU s; above 1 the strategy beats the map alone), and the
relvar ratio alone (per sample) in brackets.
  python3 bench/sun_rule.py [--seeds 6] [--spp 16] [--scenes bench_city,lobes_city,sun_shadow_object,sun_porch]
                            [--sampler zsobol] [--strategies map,default,product,alone]
  (--strategies pbrtv3,default: the map alone's density before issue 22 (pbrt-v3's) against the default,
  which is le()'s patch density under a sun (--importance bilinear); without product the lit / shadowed
  split is over the pixels where those two images differ; the ratios are against the first strategy)
"""
import argparse, os, re, subprocess, sys, tempfile
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lobes

ROOT = lobes.ROOT
STRATS = {'map': ['--env-sampling', 'map'], 'default': [], 'product': ['--env-sun-diffuse', 'product'],
          'alone': ['--env-sun-diffuse', 'alone'], 'mapmis': ['--env-sun-diffuse', 'map'],
          'suncos': ['--env-sun-diffuse', 'suncos'], 'suncos.3': ['--env-sun-diffuse', 'suncos', '--env-sun-cos', '0.3'],
          'suncos.7': ['--env-sun-diffuse', 'suncos', '--env-sun-cos', '0.7'],
          'suncos.87': ['--env-sun-diffuse', 'suncos', '--env-sun-cos', '0.866'],  # the sun rule at 30 degrees
          'suncos1': ['--env-sun-diffuse', 'suncos', '--env-sun-cos', '1'],  # the rule never true (product everywhere)
          'bilinear': ['--importance', 'bilinear'],  # issue 22's patch density for the map alone
          'pbrtv3': ['--importance', 'pbrt-v3'],  # the map alone's density before issue 22 made bilinear the default under a sun
          'split': ['--sun', 'split']}  # issue 22's splitting by component: one spot and one sky sample (examples/render/sun.c)


def lum(img, i):
    return 0.2126 * img[3 * i] + 0.7152 * img[3 * i + 1] + 0.0722 * img[3 * i + 2]


def relvar_px(imgs, pix):
    n = len(imgs)
    tot = 0.0
    for p in pix:
        for c in range(3):
            i = 3 * p + c
            vals = [im[i] for im in imgs]
            m = sum(vals) / n
            v = sum((x - m) ** 2 for x in vals) / (n - 1)
            tot += v / (m * m + 1e-2)
    return tot / max(1, 3 * len(pix))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--seeds', type=int, default=6)
    ap.add_argument('--spp', type=int, default=16)
    ap.add_argument('--render', default=os.path.join(ROOT, 'build', 'bin', 'render'))
    ap.add_argument('--scenes', default='bench_city,lobes_city,sun_shadow_object,sun_porch')
    ap.add_argument('--sampler', default=None)
    ap.add_argument('--strategies', default='map,default,product,alone')
    ap.add_argument('--crop', default=None, help='x0,x1,y0,y1: an NDC crop window for every scene instead of its regions')
    a = ap.parse_args()
    lobes.TMP = tempfile.mkdtemp(prefix='sunrule')
    strats = a.strategies.split(',')
    extra0 = ['--sampler', a.sampler] if a.sampler else []
    print('relvar across %d seeds, %d spp, sampler %s, CPU s of the render loop (1 thread; machine shared)' %
          (a.seeds, a.spp, a.sampler or "the scene's"))
    print('| scene | region | pixels | ' + ' | '.join('%s TTUV map/x (relvar ratio) CPU s' % k for k in strats) + ' |')
    print('|---|---|---|' + '---|' * len(strats))
    for sc in a.scenes.split(','):
        src = open(os.path.join(ROOT, 'scenes', sc + '.pbrt')).read().replace('"../data/', '"%s/data/' % ROOT)
        jobs = [('full', src)]
        if a.crop:
            jobs = [('crop ' + a.crop, src.replace('"string filename"', '"float cropwindow" [ %s ] "string filename"' % a.crop.replace(',', ' ')))]
        elif sc.startswith('lobes_'):
            for reg in ('plane', 'shadows'):
                jobs.append((reg, src.replace('"string filename"', '"float cropwindow" [ %g %g %g %g ] "string filename"' % lobes.CROPS[reg])))
        for reg, text in jobs:
            scene = os.path.join(lobes.TMP, '%s_%s.pbrt' % (sc, reg))
            open(scene, 'w').write(text)
            imgs = {k: [] for k in strats}
            cpu = {k: [] for k in strats}
            for s in range(a.seeds):
                order = strats[s % len(strats):] + strats[:s % len(strats)]
                if s % 2: order = order[::-1]
                for k in order:
                    img, t, _ = lobes.run(a.render, scene, s + 1, a.spp, extra0 + STRATS[k])
                    imgs[k].append(img)
                    cpu[k].append(t)
            npx = len(imgs[strats[0]][0]) // 3
            regions = [(reg, list(range(npx)))]
            others = [k for k in ('product', 'bilinear', 'pbrtv3') if k in imgs]
            if reg in ('full',) + (('crop ' + a.crop,) if a.crop else ()) and others and ('mapmis' in imgs or 'default' in imgs):
                base = imgs['mapmis' if 'mapmis' in imgs else 'default'][0]
                other = imgs[others[0]][0]
                ch = [p for p in range(npx) if any(base[3 * p + c] != other[3 * p + c] for c in range(3))]
                allimgs = [im for k in strats for im in imgs[k]]
                ml = {p: sum(lum(im, p) for im in allimgs) / len(allimgs) for p in ch}
                if ch:
                    srt = sorted(ml.values())
                    thr = 0.3 * srt[int(0.9 * (len(srt) - 1))]
                    regions.append(('changed', ch))
                    regions.append(('changed lit', [p for p in ch if ml[p] >= thr]))
                    regions.append(('changed shadowed', [p for p in ch if ml[p] < thr]))
            for rname, pix in regions:
                if not pix: continue
                r = {k: (relvar_px(imgs[k], pix), sum(cpu[k]) / len(cpu[k])) for k in strats}
                m = r.get('map', r[strats[0]])
                cells = []
                for k in strats:
                    v, t = r[k]
                    cells.append('%.2f (%.2f) %.3f' % ((m[0] * m[1]) / (v * t) if v * t > 0 else float('nan'),
                                                       m[0] / v if v > 0 else float('nan'), t))
                print('| %s | %s | %d | %s |' % (sc, rname, len(pix), ' | '.join(cells)))
                sys.stdout.flush()


if __name__ == '__main__':
    main()
