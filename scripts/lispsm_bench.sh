#!/usr/bin/env bash
# LiSPSM against the uniform map: wrong pixels (`penumbra compare`'s off: |error| > 0.1), MAE and device time of
# `sm` and hard `pssm` (4 splits) with --warp none and --warp lispsm on builtin:poles (a 40-unit field of poles),
# against the exact Embree reference of a hard sun at several angles gamma to the view direction, or (LIGHTS=spot) of
# a hard spot light from the side, overhead, behind the camera, facing it and inside the view.
#   scripts/lispsm_bench.sh [BUILD_DIR] [SIZE] [MAP] [LIGHTS]   e.g. scripts/lispsm_bench.sh build 640x360 1024 spot
set -euo pipefail
build=${1:-build}
size=${2:-640x360}
map=${3:-1024}
case ${4:-sun} in
  sun) lights=(dir:0.3,-1,-0.6 dir:1,-1,0 dir:0,-0.5,-1 dir:0,-0.5,1) ;;
  spot) lights=(spot:30,25,-18:0,0,-18:110 spot:0,30,-18:0,0,-18:110 spot:1,6,10:0,0,-20:60 spot:0,8,-45:0,0,-5:80
    spot:1,2,-11:1,0,-11:160) ;;
  *) echo "LIGHTS must be sun or spot" >&2 && exit 2 ;;
esac
tool=$build/tools/penumbra
out=$(mktemp -d)
printf '| light | technique | warp | off | MAE | device ms | n |\n| --- | --- | --- | --- | --- | --- | --- |\n'
for light in "${lights[@]}"; do
  "$tool" reference builtin:poles --size "$size" --light "$light" -q -o "$out/ref.exr"
  for technique in sm pssm; do
    for warp in none lispsm; do
      extra=()
      if [ "$technique" = pssm ]; then extra=(--pssm-filter hard --pssm-splits 4); fi
      "$tool" render builtin:poles --size "$size" --light "$light" -t "$technique" --map-size "$map" --warp "$warp" \
        "${extra[@]}" -o "$out/r.exr" > "$out/log"
      "$tool" compare "$out/r.exr" "$out/ref.exr" --json > "$out/cmp.json" || true
      n=$(strings "$out/r.exr" | grep -o 'lispsm n [0-9.e+]*' | sed 's/lispsm n //' | paste -sd/ - || true)
      python3 - "$light" "$technique" "$warp" "$(awk '$1 == "total" {print $2}' "$out/log")" "${n:--}" \
        "$out/cmp.json" <<'PY'
import json, sys
light, t, warp, ms, n, path = sys.argv[1:]
r = json.load(open(path))["metrics"]
print(f"| `{light}` | {t} | {warp} | {100 * r['off']:.2f}% | {r['mae']:.4f} | {float(ms):.0f} | {n} |")
PY
    done
  done
done
rm -rf "$out"
