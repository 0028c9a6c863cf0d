#!/usr/bin/env bash
# Installs the Debian 12 packages pensight needs (scripts/packages.txt) and builds it into
# $PENSIGHT_BUILD_DIR (default build/); only $PENSIGHT_BUILD_TARGET when set (default: all). Extra
# CMake arguments may be passed through.
# --with-ros (or PENSIGHT_WITH_ROS=1, for scripts that call this one through another): also the
# ROS 1 bag packages (scripts/packages-ros.txt), and the ROS layer on (docs/ros.md).
set -euo pipefail
cd "$(dirname "$0")/.."

with_ros="${PENSIGHT_WITH_ROS:-0}"
cmake_args=()
for arg in "$@"; do
  if [ "$arg" = "--with-ros" ]; then with_ros=1; else cmake_args+=("$arg"); fi
done
package_lists=(scripts/packages.txt)
if [ "$with_ros" = 1 ]; then
  package_lists+=(scripts/packages-ros.txt)
  # An earlier configure without the packages cached PENSIGHT_ROS=OFF.
  cmake_args+=(-DPENSIGHT_ROS=ON)
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
mapfile -t packages < <(cat "${package_lists[@]}" | grep -v '^#' | grep -v '^$')
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
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPENSIGHT_WERROR=ON \
  ${cmake_args[@]+"${cmake_args[@]}"} >/dev/null
cmake --build "$build_dir" ${PENSIGHT_BUILD_TARGET:+--target "$PENSIGHT_BUILD_TARGET"}
