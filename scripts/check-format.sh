#!/usr/bin/env bash
# Fails when a tracked C++/CUDA/source file differs from its clang-format output.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.h' '*.cpp' '*.cu' '*.cuh')
clang-format --dry-run --Werror "${files[@]}"
echo "format: ${#files[@]} files clean"
