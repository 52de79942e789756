#!/bin/sh
# The whole test suite: installs what is missing, then builds and runs ctest three times: on a normal
# (Release) gcc build in build/, on an AddressSanitizer + UndefinedBehaviorSanitizer build in
# build-asan/, and on a Release clang build in build-clang/ (clang warns where gcc does not, and the
# compile tests use -Werror).
set -eu
cd "$(dirname "$0")/.."
sh scripts/setup.sh
JOBS=$(nproc 2>/dev/null || echo 2)

echo "== normal build (build/) =="
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$JOBS"
(cd build && ctest --output-on-failure -j "$JOBS")

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/) =="
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEL_SANITIZE=ON -DEL_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j "$JOBS"
(cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --output-on-failure -j "$JOBS")

echo "== clang build (build-clang/) =="
cmake -S . -B build-clang -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ >/dev/null
cmake --build build-clang -j "$JOBS"
(cd build-clang && ctest --output-on-failure -j "$JOBS")
