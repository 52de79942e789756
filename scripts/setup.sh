#!/bin/sh
# Installs what envlight's build needs on Debian, only what is missing: apt-get as root, sudo otherwise.
set -eu
# python3: the tests that read the repository (test_markdown_links, test_report_docs, test_render_layout)
# are only registered when CMake finds it; without it they would be silently missing from ctest.
PKGS="cmake make gcc g++ clang pkg-config libembree-dev libstb-dev libopenexr-dev zlib1g-dev python3"
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "envlight: installing Debian packages:$missing" >&2
  if [ "$(id -u)" -eq 0 ]; then SUDO=""
  elif command -v sudo >/dev/null 2>&1; then SUDO="sudo"
  else
    echo "envlight: these packages are missing and this is not root and there is no sudo: run as root" \
         "apt-get install$missing" >&2
    exit 1
  fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $missing >/dev/null
fi
