#!/bin/sh
# callgrind_parts.sh: instructions per camera sample of bench_render's direct-lighting loop (16 spp, one
# thread, zsobol unless --sampler is given), by part (sampler, light, BSDF, film, Embree, camera, loop):
# two callgrind runs (25600 and 51200 camera samples) and bench/callgrind_parts.py on their difference.
# Run from the repository:  sh bench/callgrind_parts.sh [bench_render options, e.g. --loop one]
# Needs valgrind and a Release build in build/ (cmake --build build --target bench_render). About 5 min.
set -e
here=$(cd "$(dirname "$0")" && pwd)
bin=${BENCH_RENDER:-$here/../build/bin/bench_render}
out=$(mktemp -d)
for n in 25600 51200; do
  valgrind --tool=callgrind --callgrind-out-file="$out/cg.$n" "$bin" --callgrind samples $n --sampler zsobol "$@" > "$out/log.$n" 2>&1
  grep "camera samples" "$out/log.$n"
done
python3 "$here/callgrind_parts.py" --top 8 "$out/cg.25600" "$out/cg.51200" 25600 51200
rm -rf "$out"
