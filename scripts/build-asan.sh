#!/usr/bin/env bash
# The AddressSanitizer + UBSan build (build-asan/: clang 14 with libFuzzer's coverage), shared by
# the sanitizer tests (scripts/test.sh --sanitize) and the fuzz targets (scripts/fuzz.sh): one
# build of the library serves both. Builds TARGET (default: all). CUDA's runtime and ASan's shadow
# memory do not mix: this build is CPU + Vulkan. Line tables only: a report needs file:line, not
# variables, and full -g makes the build a third slower.
set -euo pipefail
cd "$(dirname "$0")/.."
PENSIGHT_BUILD_DIR=build-asan PENSIGHT_BUILD_TARGET="${1:-}" CC=clang-14 CXX=clang++-14 \
  scripts/setup.sh -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" -DPENSIGHT_FUZZ=ON \
  -DPENSIGHT_CUDA=OFF -DPENSIGHT_BUILD_BENCH=OFF
