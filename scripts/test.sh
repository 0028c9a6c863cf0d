#!/usr/bin/env bash
# Builds pensight (installing its packages if needed) and runs every test on lavapipe with the
# Khronos validation layer on, then the installed-package example (scripts/example.sh).
# --sanitize: the tests with AddressSanitizer + UBSan (scripts/build-asan.sh: build-asan/, clang),
# except the accuracy tests over many frames (label `accuracy`; their code, renderer, FFT detector
# and estimators, runs under ASan in the shorter tests, and their long sequences would take a third
# of the CI budget there) and the training smoke test (label `training`, Python). The rendered
# tests render with the Vulkan renderer (PENSIGHT_TEST_RENDERER, tests/support/rendered_run.h),
# 8x faster than the CPU reference on lavapipe and not instrumented under ASan; the reference keeps
# its own tests. --tsan: the tests labelled `threads` with ThreadSanitizer (build-tsan/), rendering
# with the CPU reference, whose rows run on threads. --fuzz: the fuzz targets (same build-asan/):
# each replays its seed corpus and crash regressions, then fuzzes for 30 s.
# The default and --sanitize builds include the ROS layer (its packages installed by
# `scripts/setup.sh --with-ros`), so its tests (tests/ros/) run in CI.
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-}"
ctest_args=()

if [ "$mode" = "--sanitize" ]; then
  export PENSIGHT_BUILD_DIR=build-asan
  # Only the test binaries this run takes (tests/CMakeLists.txt: pensight_tests_sanitized).
  PENSIGHT_WITH_ROS=1 scripts/build-asan.sh pensight_tests_sanitized
  # Mesa's llvmpipe keeps JIT and thread allocations until exit; leaks are not checked here.
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  # pensight_node under ASan takes ~0.3 s a frame on 2 cores: its tests play bags at a fifth of
  # real time so that it keeps up (tests/ros/node_test.cpp).
  export PENSIGHT_ROS_PLAY_RATE=0.2
  # A test binary that was not built leaves a placeholder test, <binary>_NOT_BUILT.
  ctest_args=(-LE "accuracy|fuzz|training" -E "_NOT_BUILT$")
elif [ "$mode" = "--fuzz" ]; then
  scripts/fuzz.sh --build
  export PENSIGHT_FUZZ_BUILT=1
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
  ctest --test-dir build-asan --output-on-failure -j2 -L fuzz
  mkdir -p .cache/fuzz
  scripts/fuzz.sh --list | xargs -P 2 -I '{}' sh -c 'scripts/fuzz.sh {} 30 >.cache/fuzz/{}.log 2>&1 ||
    { tail -n 40 .cache/fuzz/{}.log; echo "fuzz: {} failed; its crash input is in .cache/fuzz/crashes/{}/"; exit 255; }'
  exit 0
elif [ "$mode" = "--tsan" ]; then
  export PENSIGHT_BUILD_DIR=build-tsan
  # A race needs threads that share data, so only the tests labelled `threads` are built and run;
  # ThreadSanitizer makes them 5-15x slower. CUDA is off as in the ASan build; -g1 (line tables)
  # as there.
  PENSIGHT_BUILD_TARGET=pensight_tests_threads scripts/setup.sh -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DPENSIGHT_TSAN=ON -DPENSIGHT_CUDA=OFF -DPENSIGHT_BUILD_BENCH=OFF
  # libgomp is not instrumented: TSan does not see its barriers (every OpenMP loop reads as a race)
  # and cannot restore its workers' stacks for a suppression. One thread per OpenMP region, so TSan
  # checks our own threads (Pipeline's workers, the renderer's rows).
  export OMP_THREAD_LIMIT=1
  export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/scripts/tsan.supp"
  ctest_args=(-L threads)
else
  export PENSIGHT_BUILD_DIR=build
  scripts/setup.sh --with-ros
fi
if [ "$mode" != "--tsan" ]; then export PENSIGHT_TEST_RENDERER=vulkan; fi

# ONNX Runtime (Node.js package, from the npm registry) is the independent runtime that exported
# models are checked against; without npm those checks are skipped and say so.
if command -v npm >/dev/null && [ ! -d .cache/ort/node_modules/onnxruntime-node ]; then
  npm install --prefix .cache/ort onnxruntime-node@1 --ignore-scripts --no-audit --no-fund \
    --loglevel=error >/dev/null || echo "test: onnxruntime-node not installed; its checks skip"
fi
# node-mavlink (npm, pure JavaScript) is the independent MAVLink implementation our frames are
# checked against (tests/mavlink/node_mavlink_test.cpp); without npm that check skips and says so.
if command -v npm >/dev/null && [ ! -d .cache/node-mavlink/node_modules/node-mavlink ]; then
  npm install --prefix .cache/node-mavlink node-mavlink@2 --ignore-scripts --no-audit --no-fund \
    --loglevel=error >/dev/null || echo "test: node-mavlink not installed; its checks skip"
fi

# Vulkan tests run on lavapipe unless the caller picks another device.
export PENSIGHT_VK_DEVICE="${PENSIGHT_VK_DEVICE:-llvmpipe}"
ctest --test-dir "$PENSIGHT_BUILD_DIR" --output-on-failure -j2 --timeout 600 "${ctest_args[@]}"
if [ -z "$mode" ]; then scripts/example.sh; fi
