#!/usr/bin/env bash
# Installs the build ($PENSIGHT_BUILD_DIR, default build/) into a temporary prefix, builds
# examples/embed against the installed package as a vehicle program would, renders a short
# dataset and runs the example on it; fails unless some frames get a pose.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${PENSIGHT_BUILD_DIR:-build}"

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build_dir" --prefix "$tmp/prefix" >/dev/null
cmake -S examples/embed -B "$tmp/embed" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/embed" >/dev/null

# follow.yaml starts facing the net at 0.5 m: each of its first 10 frames gives a pose today.
"$build_dir/apps/pensight" render scenarios/follow.yaml --frames 10 --out "$tmp/data" --quiet
"$tmp/embed/embed" "$tmp/data" | tee "$tmp/embed.log"
with_pose="$(tail -n 1 "$tmp/embed.log" | cut -d' ' -f1)"
if [ "$with_pose" -eq 0 ]; then
  echo "example: no frame got a pose" >&2
  exit 1
fi
echo "example: the installed package builds and runs"
