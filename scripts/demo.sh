#!/usr/bin/env bash
# Installs what is missing, builds, renders the bundled default scene (a real model on a ground plane under
# a soft-shadowing disk light), writes out/default.exr and out/default.png, and prints per-pass timings.
# Extra arguments go to `penumbra render` (e.g. --technique pcf, --device cpu).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_TARGETS=penumbra ./scripts/setup.sh  # the tool alone: the tests and benchmarks are test.sh's
BUILD_DIR=${BUILD_DIR:-build}
mkdir -p out
"$BUILD_DIR"/tools/penumbra devices | head -n 1
"$BUILD_DIR"/tools/penumbra render scenes/default.json -o out/default.exr "$@"
