#!/usr/bin/env bash
# Runs one libFuzzer target (fuzz/fuzz_TARGET.cpp) for SECONDS (default 60), or for RUNS inputs
# with --runs RUNS, building it first (scripts/build-asan.sh: build-asan/). New inputs that
# reach new code collect in .cache/fuzz/TARGET/ (kept between runs); a crash is written to
# .cache/fuzz/crashes/TARGET/ and the script fails. `scripts/fuzz.sh --list` names the targets,
# `--build` only builds, `--merge TARGET` folds .cache/fuzz/TARGET/ into the committed seed corpus
# fuzz/corpus/TARGET/ (only the inputs that add coverage).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=build-asan

build() {
  scripts/build-asan.sh pensight_fuzzers
}
targets() {
  sed -n 's/^foreach(name \(.*\))$/\1/p; s/^  pensight_add_fuzzer(\([a-z_]*\))$/\1/p' fuzz/CMakeLists.txt |
    tr ' ' '\n'
}

case "${1:-}" in
  "" | -h | --help) sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  --list) targets; exit 0 ;;
  --build) build; exit 0 ;;
esac

merge=0
if [ "$1" = "--merge" ]; then merge=1; shift; fi
target="$1"
if ! targets | grep -qx "$target"; then
  echo "fuzz: no target '$target'; the targets are: $(targets | tr '\n' ' ')" >&2
  exit 2
fi
# PENSIGHT_FUZZ_BUILT=1: the caller has just built (parallel runs must not configure at once).
if [ "${PENSIGHT_FUZZ_BUILT:-}" != 1 ]; then build >/dev/null; fi
binary=$build_dir/fuzz/fuzz_$target
if [ ! -x "$binary" ]; then
  # fuzz_bag needs the ROS layer (scripts/setup.sh --with-ros); the others are always built.
  echo "fuzz: $binary was not built (its layer is off in $build_dir); skipped" >&2
  exit 0
fi
mkdir -p .cache/fuzz
corpus=.cache/fuzz/$target
seeds=fuzz/corpus/$target
mkdir -p "$corpus" ".cache/fuzz/crashes/$target"
if [ "$merge" = 1 ]; then
  "$binary" -merge=1 "$seeds" "$corpus" 2>&1 | tail -2
  exit 0
fi

limit=(-max_total_time="${2:-60}")
if [ "${2:-}" = "--runs" ]; then limit=(-runs="$3"); fi
dict=()
case "$target" in
  *yaml | map_config) dict=(-dict=fuzz/dict/yaml.dict) ;;
  onnx) dict=(-dict=fuzz/dict/onnx.dict) ;;
esac
# Leaks are not findings here: llvmpipe, OpenCV and OpenVDB keep allocations until exit.
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
"$binary" "${limit[@]}" "${dict[@]}" -rss_limit_mb=2048 -malloc_limit_mb=1024 -print_final_stats=1 \
  -artifact_prefix=".cache/fuzz/crashes/$target/" "$corpus" "$seeds"
