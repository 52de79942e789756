#!/bin/sh
# compare.sh: our `render` against pbrt-v3 itself on pbrt-v3's scenes/killeroo-simple.pbrt (issue 24).
#
#   sh bench/pbrt_v3/compare.sh [render|bsdf|sphere|farlight]   (from the repository root, after building `render`)
#
# 1. Gets pbrt-v3's source (PBRT_V3_SRC=an unpacked tree, else a shallow git clone of
#    github.com/mmp/pbrt-v3 into $WORK) and builds it with bench/pbrt_v3/Makefile: Release (-O2,
#    NDEBUG), float, RGBSpectrum, without its git submodules: the system's OpenEXR 3 and zlib
#    (Debian: libopenexr-dev zlib1g-dev), a small glog stand-in (stub/glog/logging.h: CHECKs abort,
#    LOG(WARNING) and up print, VLOG is off) and a Ptex stub (a "ptex" texture is an error). About 15
#    CPU minutes; nice -n 10, make -j2.
# 2. render (default): renders killeroo-simple.pbrt at 64 spp with pbrt-v3 (its Halton sampler, as the
#    scene says, and Sobol: pbrt-v3 has no seed option, so its own noise floor is Halton against Sobol)
#    and with ours (the scene's Halton, seeds 1 and 2), 2 threads, PFM; a material-ID render (the scene
#    under a constant sky, killeroos red and green, the light yellow) splits the image into the two
#    killeroos, the light (with its edge pixels) and the rest;
#    prints relMSE (mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01)) and the mean per region
#    for: ours vs pbrt-v3, ours vs ours (seeds), pbrt-v3 Halton vs pbrt-v3 Sobol.
#    OLD_RENDER=path/to/an/older/render adds that binary's image against pbrt-v3's.
# 3. bsdf: prints pbrt-v3's BSDF::f and Pdf table (bench/pbrt_v3/bsdf_values.cpp) that
#    examples/render/tests/test_render_pbrtv3_bsdf.c pins our materials to.
# 4. sphere: renders bench/pbrt_v3/plastic_spheres.pbrt with pbrt-v3 at 4096 spp and prints its 6x6 block
#    means, the reference table of examples/render/tests/test_render_pbrtv3_scene.c.
# 5. farlight: a matte plane under a sphere light (r 3, L 2000) at d = 250, 550, 800, both renderers at
#    4096 spp against the closed form Kd L (r/d)^2 (pbrt-v3 loses light from a small, far sphere).
# Measured numbers: examples/render/README.md, "Against pbrt-v3 itself".
set -e
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE=$ROOT/bench/pbrt_v3
WORK=${WORK:-/tmp/pbrt_v3_compare}
MODE=${1:-render}
SPP=${SPP:-64}
RENDER=${RENDER:-$ROOT/build/bin/render}
mkdir -p "$WORK/img"
if [ -z "$PBRT_V3_SRC" ]; then
  PBRT_V3_SRC=$WORK/pbrt-v3src
  [ -d "$PBRT_V3_SRC/src" ] || git clone --depth 1 https://github.com/mmp/pbrt-v3 "$PBRT_V3_SRC"
fi
COMMIT=${PBRT_V3_COMMIT:-$(git -C "$PBRT_V3_SRC" rev-parse --short HEAD 2>/dev/null || echo unknown)}
echo "pbrt-v3 source: $PBRT_V3_SRC ($COMMIT); building into $WORK/obj" >&2
nice -n 10 make -s -f "$HERE/Makefile" -j2 SRC="$PBRT_V3_SRC" STUB="$HERE/stub" OUT="$WORK/obj" "$WORK/obj/pbrt" >&2
PBRT=$WORK/obj/pbrt
SCENES=$PBRT_V3_SRC/scenes

if [ "$MODE" = bsdf ]; then
  nice -n 10 make -s -f "$HERE/Makefile" SRC="$PBRT_V3_SRC" STUB="$HERE/stub" OUT="$WORK/obj" \
    BSDF_VALUES="$HERE/bsdf_values.cpp" COMMIT="$COMMIT" "$WORK/obj/bsdf_values" >&2
  "$WORK/obj/bsdf_values"
  exit 0
fi

if [ "$MODE" = sphere ]; then
  nice -n 10 "$PBRT" --nthreads 2 --quiet --outfile "$WORK/img/spheres_pbrt.pfm" "$HERE/plastic_spheres.pbrt"
  python3 "$HERE/compare_pfm.py" --blocks 6 "$WORK/img/spheres_pbrt.pfm"
  exit 0
fi

if [ "$MODE" = farlight ]; then
  for D in 250 550 800; do
    cat > "$WORK/far$D.pbrt" <<EOF
LookAt 0 0 10  0 0 0  0 1 0
Camera "orthographic" "float screenwindow" [-0.5 0.5 -0.5 0.5]
Film "image" "integer xresolution" [8] "integer yresolution" [8] "string filename" "far.pfm"
Sampler "halton" "integer pixelsamples" [4096]
Integrator "path" "integer maxdepth" [1]
WorldBegin
AttributeBegin
Material "matte" "color Kd" [0 0 0]
Translate 0 0 $D
AreaLightSource "area" "color L" [2000 2000 2000]
Shape "sphere" "float radius" [3]
AttributeEnd
Material "matte" "color Kd" [.5 .5 .5]
Shape "trianglemesh" "point P" [ -10 -10 0 10 -10 0 10 10 0 -10 10 0 ] "integer indices" [0 1 2 2 3 0]
WorldEnd
EOF
    nice -n 10 "$PBRT" --quiet --nthreads 2 --outfile "$WORK/img/far_pbrt$D.pfm" "$WORK/far$D.pbrt"
    nice -n 10 "$RENDER" "$WORK/far$D.pbrt" --quiet --nthreads 2 --outfile "$WORK/img/far_ours$D.pfm" > /dev/null
    python3 - "$HERE" "$WORK/img" $D <<'EOF'
import sys
sys.path.insert(0, sys.argv[1])
from compare_pfm import read_pfm
d = float(sys.argv[3])
exact = 0.5 * 2000 * (3.0 / d) ** 2
for n in ("pbrt", "ours"):
    w, h, a = read_pfm("%s/far_%s%d.pfm" % (sys.argv[2], n, d))
    print("d %4d  %-5s %.7f  closed form %.7f  ratio %.5f" % (d, n, sum(a) / len(a), exact, sum(a) / len(a) / exact))
EOF
  done
  exit 0
fi

# the scene at $SPP spp, once per sampler, and the material-ID scene (ours, 4 spp)
python3 - "$SCENES" "$SPP" <<'EOF'
import sys
d, spp = sys.argv[1], sys.argv[2]
s = open(d + "/killeroo-simple.pbrt").read()
assert 'Sampler "halton" "integer pixelsamples" [8]' in s
open(d + "/killeroo-cmp-halton.pbrt", "w").write(s.replace('"integer pixelsamples" [8]', '"integer pixelsamples" [%s]' % spp))
open(d + "/killeroo-cmp-sobol.pbrt", "w").write(s.replace('Sampler "halton" "integer pixelsamples" [8]', 'Sampler "sobol" "integer pixelsamples" [%s]' % spp))
m = s.replace('Integrator "path"', 'Integrator "directlighting" "integer maxdepth" [1]')
m = m.replace('WorldBegin', 'WorldBegin\nLightSource "infinite" "rgb L" [1 1 1]')
m = m.replace('AreaLightSource "area"  "color L" [2000 2000 2000] "integer nsamples" [8]', '')
m = m.replace('Material "matte" "color Kd" [.5 .5 .8]', 'Material "matte" "color Kd" [0 0 1]')
m = m.replace('Material "matte" "color Kd" [0 0 0]', 'Material "matte" "color Kd" [1 1 0]')
m = m.replace('Material "plastic" "color Kd" [.4 .2 .2] "color Ks" [.5 .5 .5]\n        "float roughness" [.025]', 'Material "matte" "color Kd" [1 0 0]')
m = m.replace('Material "plastic" "color Ks" [.3 .3 .3] "color Kd" [.4 .5 .4]\n        "float roughness" [.15] ', 'Material "matte" "color Kd" [0 1 0]')
assert "plastic" not in m and "AreaLightSource" not in m
open(d + "/killeroo-cmp-mask.pbrt", "w").write(m)
EOF
cd "$SCENES"
nice -n 10 "$RENDER" killeroo-cmp-mask.pbrt --spp 4 --nthreads 2 --quiet --outfile "$WORK/img/mask.pfm"
for s in 1 2; do
  echo "ours, seed $s" >&2; nice -n 10 "$RENDER" killeroo-cmp-halton.pbrt --nthreads 2 --seed $s --quiet --outfile "$WORK/img/ours_s$s.pfm"
done
if [ -n "$OLD_RENDER" ]; then
  echo "old ours, seed 1" >&2; nice -n 10 "$OLD_RENDER" killeroo-cmp-halton.pbrt --nthreads 2 --seed 1 --quiet --outfile "$WORK/img/old_s1.pfm"
fi
for smp in halton sobol; do
  echo "pbrt-v3, $smp" >&2; nice -n 10 "$PBRT" --nthreads 2 --quiet --outfile "$WORK/img/pbrt_$smp.pfm" killeroo-cmp-$smp.pbrt
done
C="python3 $HERE/compare_pfm.py --mask-from $WORK/img/mask.pfm"
echo "== ours (seed 1) vs pbrt-v3 (halton), $SPP spp"; $C "$WORK/img/ours_s1.pfm" "$WORK/img/pbrt_halton.pfm"
echo "== ours (seed 2) vs pbrt-v3 (halton)"; $C "$WORK/img/ours_s2.pfm" "$WORK/img/pbrt_halton.pfm"
echo "== noise floor: ours seed 1 vs ours seed 2"; $C "$WORK/img/ours_s1.pfm" "$WORK/img/ours_s2.pfm"
echo "== noise floor: pbrt-v3 sobol vs pbrt-v3 halton"; $C "$WORK/img/pbrt_sobol.pfm" "$WORK/img/pbrt_halton.pfm"
echo "== ours (seed 1) vs pbrt-v3 (sobol)"; $C "$WORK/img/ours_s1.pfm" "$WORK/img/pbrt_sobol.pfm"
if [ -n "$OLD_RENDER" ]; then
  echo "== old ours (seed 1) vs pbrt-v3 (halton)"; $C "$WORK/img/old_s1.pfm" "$WORK/img/pbrt_halton.pfm"
fi
