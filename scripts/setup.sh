#!/bin/sh
# Installs what envlight's build needs on Debian, only what is missing: apt-get as root, sudo otherwise.
set -eu
PKGS="cmake make gcc g++ clang pkg-config libembree-dev libstb-dev libopenexr-dev zlib1g-dev"
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "envlight: installing Debian packages:$missing" >&2
  if [ "$(id -u)" -eq 0 ]; then SUDO=""; else SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $missing >/dev/null
fi
