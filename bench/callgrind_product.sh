#!/bin/sh
# callgrind_product.sh: instructions per call of product sampling against plain light sampling (issue 20).
#
#   sh bench/callgrind_product.sh [BENCH [MAP [N]]]
#     BENCH  the bench_envlight binary (default build/bin/bench_envlight)
#     MAP    an RGB map file (default data/envmaps/city.hdr), default options (guide sampler, identity matrix)
#     N      calls per operation (default 100000)
#
# For each operation OP it runs `valgrind --tool=callgrind bench_envlight --callgrind OP N MAP` and the
# same with 0 calls, and prints (Ir(N) - Ir(0)) / N minus the "loop" operation's own count (reading the
# precomputed random numbers and summing the results). Product sampling draws a new random normal on every
# call (the random directions, as a renderer's shading points); sample_li and sample_li_cos with _rgb
# also return the radiance; the _n operations are the same calls n at once (el_envlight_sample_li_cos_n,
# el_envlight_pdf_li_cos_n) in batches of 64, per sample. Instruction counts do not depend on the machine's load. build_product: one
# build of the product tables with the light's init (2 builds counted, per build). Table bytes, build
# milliseconds, variance and time per sample (time-to-unit-variance): build/bin/bench_product --library.
# Importance BILINEAR's patch density (issue 22), the same way:
#   OPS="sample_guide pdf sample_bilinear sample_bilinear_rgb pdf_bilinear sample_bilinear_rotated pdf_bilinear_rotated" \
#     sh bench/callgrind_product.sh build/bin/bench_envlight data/envmaps/city.hdr
set -e
BENCH=${1:-build/bin/bench_envlight}
MAP=${2:-data/envmaps/city.hdr}
N=${3:-100000}
ir() { # OP CALLS -> the "Collected" count
  valgrind --tool=callgrind --callgrind-out-file=/dev/null "$BENCH" --callgrind "$1" "$2" "$MAP" 2>&1 |
    sed -n 's/.*Collected : *\([0-9]*\).*/\1/p'
}
per_call() { a=$(ir "$1" 0); b=$(ir "$1" "$N"); echo "($b - $a) / $N" | bc -l; }
LOOP=$(per_call loop)
printf '%-22s %10s   (map %s, %s calls, the loop'"'"'s %.1f subtracted)\n' operation instr/call "$MAP" "$N" "$LOOP"
for op in ${OPS:-sample_guide sample_guide_rgb pdf sample_cos sample_cos_rgb pdf_cos sample_cos_rotated pdf_cos_rotated \
             sample_cos_n sample_cos_n_rgb pdf_cos_n sample_cos_n_rotated pdf_cos_n_rotated}; do
  c=$(per_call "$op")
  printf '%-22s %10.1f\n' "$op" "$(echo "$c - $LOOP" | bc -l)"
done
if [ -z "$OPS" ]; then
  a=$(ir build_product 0); b=$(ir build_product 2)
  printf '%-22s %10.1f M (per build, with the light'"'"'s init)\n' build_product "$(echo "($b - $a) / 2000000" | bc -l)"
fi
