#!/bin/sh
# Builds one lab of the course against your files in tutorials/labs/ and runs its test:
#   sh scripts/lab.sh 1      (2, 3 or 4; 5: appendix A3.15's patch density; from the repository root; `all` for all five)
# It configures build-lab/ with EL_LAB_STUDENT=ON (only the labs are built, in a few seconds), then
# runs `ctest -R lab_0N`: the test prints, part by part, what differs from pbrt's code and what the
# chapter says about it, and ends with "all M checks passed" once your lab is done. Run it again after
# each change.
set -eu
cd "$(dirname "$0")/.."
case "${1:-}" in
  1) t=lab_01_mipmap ;;
  2) t=lab_02_lookups ;;
  3) t=lab_03_light ;;
  4) t=lab_04_film ;;
  5) t=lab_05_patch ;;
  all) t="lab_01_mipmap lab_02_lookups lab_03_light lab_04_film lab_05_patch" ;;
  *) echo "usage: sh scripts/lab.sh N   (N = 1, 2, 3 or 4: the chapter's lab in tutorials/labs/; 5: the appendix's patch density; or all)" >&2; exit 2 ;;
esac
sh scripts/setup.sh
cmake -S . -B build-lab -DCMAKE_BUILD_TYPE=Debug -DEL_LAB_STUDENT=ON -DEL_BUILD_EXAMPLES=OFF -DEL_BUILD_BENCH=OFF >/dev/null
cmake --build build-lab --target $t
if [ "$1" = all ]; then r=lab_; else r=$t; fi
ctest --test-dir build-lab -R "$r" --output-on-failure
