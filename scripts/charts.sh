#!/usr/bin/env bash
# Regenerates the speed-vs-error charts (docs/charts/SCENE.{png,svg}) and docs/accuracy.md: `penumbra bench` on the
# bundled scenes (scenes/*.json and two built-in ones) against Embree references, then tools/chart.py and
# tools/accuracy_table.py over the CSVs (kept in out/charts/). Sized to finish in minutes on a 2-core PoCL machine.
# Environment: PENUMBRA (a built tool; default: build with scripts/setup.sh and use $BUILD_DIR/tools/penumbra),
# SIZE (640x360), MAP_SIZE (empty: each technique's own default, --map-size auto where it has one; or a size for
# every technique), SPP (256), RUNS (3), WARMUP (1), TECHNIQUES (all,reference: every technique and
# the Embree tracer as their peer), SCENES (space-separated), SWEEPS (space-separated PARAM=a,b,c for more points per
# technique; default "lvsm-layers=1,2,4,8 pssm-splits+map-size=default+default,1+2048,2+1448,4+1024,8+724
# spp=4,16,64": LVSM-N, the split techniques' defaults and 1-8 parallel splits with the same total texels as one 2048²
# map, and the tracer at 4, 16 and 64 samples per pixel
# against the SPP ground truth; "" for defaults only).
set -euo pipefail
cd "$(dirname "$0")/.."

SIZE=${SIZE:-640x360}
MAP_SIZE=${MAP_SIZE-}
map_args=()
[ -n "$MAP_SIZE" ] && map_args=(--map-size "$MAP_SIZE")
SPP=${SPP:-256}
RUNS=${RUNS:-3}
WARMUP=${WARMUP:-1}
TECHNIQUES=${TECHNIQUES:-all,reference}
sweep_args=()
for sweep in ${SWEEPS-lvsm-layers=1,2,4,8 pssm-splits+map-size=default+default,1+2048,2+1448,4+1024,8+724 spp=4,16,64}; do sweep_args+=(--sweep "$sweep"); done
read -r -a SCENE_LIST <<<"${SCENES:-$(echo scenes/*.json) builtin:stacked-planes builtin:staircase}"
PYTHON=${PYTHON:-$([ -x /usr/bin/python3 ] && echo /usr/bin/python3 || echo python3)}  # Debian's, with matplotlib

if [ -z "${PENUMBRA:-}" ]; then
  ./scripts/setup.sh -DPENUMBRA_BUILD_BENCHMARKS=OFF
  PENUMBRA=${BUILD_DIR:-build}/tools/penumbra
fi
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$(dirname "$PENUMBRA")/../pocl-cache}

start=$(date +%s)
mkdir -p out/charts docs/charts
csvs=()
for scene in "${SCENE_LIST[@]}"; do
  name=$(basename "${scene#builtin:}" .json)
  echo "==> bench $scene"
  "$PENUMBRA" bench "$scene" --techniques "$TECHNIQUES" --size "$SIZE" "${map_args[@]}" --spp "$SPP" \
    --runs "$RUNS" --warmup "$WARMUP" "${sweep_args[@]}" -o "out/charts/$name.csv" --json "out/charts/$name.json"
  csvs+=("out/charts/$name.csv")
done
"$PYTHON" tools/chart.py docs/charts "${csvs[@]}"
elapsed=$(($(date +%s) - start))
"$PYTHON" tools/accuracy_table.py docs/accuracy.md "${csvs[@]}" --command "./scripts/charts.sh" \
  --note "Settings: ${SIZE} frames, ${MAP_SIZE:+${MAP_SIZE}² shadow maps (--map-size; other parameters at their defaults)}${MAP_SIZE:-every parameter at its default (map sizes: auto where a technique has it)}, \
reference ${SPP} spp for soft lights, median of ${RUNS} runs after ${WARMUP} warm-up; the whole run took \
${elapsed} s. Charts: [docs/charts/](charts/)."
echo "==> done in ${elapsed} s"
