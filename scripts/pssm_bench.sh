#!/usr/bin/env bash
# PSSM / PSVSM with 1..8 splits against a single map of the same total texel count (2048^2): device time (sum of
# the profiled passes, `penumbra render`'s "total") and accuracy against the exact Embree reference of a hard sun
# (`penumbra compare`: MAE, RMSE, fraction of pixels off by > 0.1) on builtin:poles (a long field of poles).
#   scripts/pssm_bench.sh [BUILD_DIR] [SIZE]      e.g. scripts/pssm_bench.sh build 1280x720
set -euo pipefail
build=${1:-build}
size=${2:-640x360}
tool=$build/tools/penumbra
out=$(mktemp -d)
light=dir:0.6,-1,-0.3  # the scene's sun without its angular radius: hard shadows, an exact reference
"$tool" reference builtin:poles --size "$size" --light "$light" -o "$out/ref.exr" > /dev/null
printf '%-8s %-7s %-6s %10s %8s %8s %8s\n' technique splits map device_ms mae rmse off
row() {  # technique splits map-size [extra options]
  local t=$1 n=$2 m=$3
  shift 3
  "$tool" render builtin:poles --size "$size" --light "$light" -t "$t" --map-size "$m" "$@" -o "$out/$t.exr" \
    > "$out/log"
  local ms
  ms=$(awk '$1 == "total" {print $2}' "$out/log")
  "$tool" compare "$out/$t.exr" "$out/ref.exr" --json > "$out/cmp.json" || true
  python3 - "$t" "$n" "$m" "$ms" "$out/cmp.json" <<'PY'
import json, sys
t, n, m, ms, path = sys.argv[1:]
r = json.load(open(path))["metrics"]
print(f"{t:<8} {n:<7} {m:<6} {float(ms):10.1f} {r['mae']:8.4f} {r['rmse']:8.4f} {r['off']:8.4f}")
PY
}
# Same total texels: 2048^2 = n * m^2.
for t in pssm psvsm; do
  for n_m in 1:2048 2:1448 4:1024 8:724; do
    row "$t" "${n_m%%:*}" "${n_m##*:}" --pssm-splits "${n_m%%:*}"
  done
  row "$t" auto 1024 --pssm-splits auto
done
row pcf 1 2048
row vsm 1 2048
rm -rf "$out"
