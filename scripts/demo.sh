#!/bin/sh
# The main demo: installs what is missing, builds, runs, and prints the path of the picture it wrote.
set -eu
cd "$(dirname "$0")/.."
sh scripts/setup.sh
JOBS=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$JOBS"
mkdir -p out
./build/bin/02_mipmap_lookup out/02_mipmap_lookup.png
echo "wrote $(pwd)/out/02_mipmap_lookup.png"
