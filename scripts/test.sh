#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (ctest) on PoCL, the CPU OpenCL device.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_TARGETS= ./scripts/setup.sh  # every target: the suite runs them all
BUILD_DIR=${BUILD_DIR:-build}
export PENUMBRA_DEVICE=${PENUMBRA_DEVICE:-cpu}
echo "==> running the test suite on: $("$BUILD_DIR"/tools/penumbra devices | head -n 1)"
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
