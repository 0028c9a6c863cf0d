#!/usr/bin/env bash
# Installs the Debian 12 packages pensight needs (scripts/packages.txt) and builds it into
# $PENSIGHT_BUILD_DIR (default build/); only $PENSIGHT_BUILD_TARGET when set (default: all). Extra
# CMake arguments may be passed through.
set -euo pipefail
cd "$(dirname "$0")/.."

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
mapfile -t packages < <(grep -v '^#' scripts/packages.txt | grep -v '^$')
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
fi

build_dir="${PENSIGHT_BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPENSIGHT_WERROR=ON "$@" >/dev/null
cmake --build "$build_dir" ${PENSIGHT_BUILD_TARGET:+--target "$PENSIGHT_BUILD_TARGET"}
