#!/usr/bin/env bash
# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer: configures and builds a separate tree
# (build-asan, RelWithDebInfo, -fsanitize=address,undefined on every target, any report fatal) and runs ctest there.
# Arguments go to ctest, e.g. `scripts/sanitize.sh -L 'unit|cli|fuzz-replay'` or `-R Scene` for a subset.
# Environment: BUILD_DIR (default build-asan), JOBS (default nproc), CXX (default g++).
# PoCL compiles kernels with its own LLVM; its allocations are not instrumented, and leak checking is off because
# the ICD loader and PoCL keep their one-time allocations to exit (not ours to free).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build-asan}
JOBS=${JOBS:-$(nproc)}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPENUMBRA_SANITIZE=address,undefined \
  -DPENUMBRA_BUILD_BENCHMARKS=OFF -DPENUMBRA_BUILD_PYTHON=OFF >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"
export PENUMBRA_DEVICE=${PENUMBRA_DEVICE:-cpu}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0:abort_on_error=1:detect_odr_violation=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$JOBS" "$@"
