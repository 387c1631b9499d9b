#!/usr/bin/env bash
# Runs the libFuzzer harnesses of tests/fuzz: builds them with clang-14 (ASan + UBSan, coverage on the whole
# library) into build-fuzz, then fuzzes each for SECONDS (default 120) from a copy of the committed corpus.
# New inputs land in build-fuzz/corpus/HARNESS; crashes as build-fuzz/crash-*. Usage: scripts/fuzz.sh [SECONDS]
# [HARNESS...] (harnesses: gltf scene_file cli_values). Needs clang-14 and libclang-rt-14-dev (Debian 12).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_EACH=${1:-120}
shift || true
HARNESSES=("${@:-gltf scene_file cli_values}")
read -r -a HARNESSES <<<"${HARNESSES[*]}"
BUILD_DIR=${BUILD_DIR:-build-fuzz}
CC=clang-14 CXX=clang++-14 cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPENUMBRA_FUZZ=ON \
  -DPENUMBRA_SANITIZE=address,undefined -DPENUMBRA_BUILD_BENCHMARKS=OFF -DPENUMBRA_BUILD_PYTHON=OFF >/dev/null
cmake --build "$BUILD_DIR" -j "${JOBS:-$(nproc)}" --target "${HARNESSES[@]/#/fuzz_}"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
for h in "${HARNESSES[@]}"; do
  mkdir -p "$BUILD_DIR/corpus/$h"
  cp -n tests/fuzz/corpus/"$h"/* "$BUILD_DIR/corpus/$h/" 2>/dev/null || true
  echo "==> fuzz_$h for ${SECONDS_EACH}s"
  (cd "$BUILD_DIR" && ./tests/fuzz/fuzz_"$h" -max_total_time="$SECONDS_EACH" -max_len=65536 -rss_limit_mb=2048 \
    -timeout=10 -print_final_stats=1 "corpus/$h")
done
