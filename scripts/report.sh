#!/bin/sh
# "What accuracy costs in time": regenerates docs/accuracy-vs-time.md and its plots (docs/img/*.png).
#
#   sh scripts/report.sh           the full run (a few minutes on 2 cores): writes docs/
#   sh scripts/report.sh --quick   tiny sizes, one repeat (CI, under a minute or two): writes build/report-quick/
#   sh scripts/report.sh [--quick] --out DIR   writes DIR instead
#
# Installs what is missing (scripts/setup.sh's packages, and Debian's python3-matplotlib and
# python3-numpy: the same apt channel as every other dependency, no virtualenv or network access to PyPI
# needed), configures build/ (Release), builds only the programs the report runs, then runs
# bench/report.py.
set -eu
cd "$(dirname "$0")/.."
sh scripts/setup.sh
# Debian's packages go to Debian's python (/usr/bin/python3), which may not be the first python3 on the PATH.
PY=python3
if ! "$PY" -c "import matplotlib, numpy" 2>/dev/null; then PY=/usr/bin/python3; fi
if ! "$PY" -c "import matplotlib, numpy" 2>/dev/null; then
  echo "envlight: installing Debian packages: python3-matplotlib python3-numpy" >&2
  if [ "$(id -u)" -eq 0 ]; then SUDO=""; else SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq python3-matplotlib python3-numpy >/dev/null
fi
JOBS=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$JOBS" --target bench_mipmap bench_envlight bench_bigmaps bench_film render
exec "$PY" bench/report.py --build build "$@"
