#!/usr/bin/env bash
# Regenerates docs/default-front.md: whether each technique's default map size sits on its own speed-vs-error front.
# Per scene, frame size and technique, one interleaved `penumbra bench --sweep map-size=default,<fixed sizes>` run
# against an Embree reference (traced once per scene and size, cached in out/front/), then tools/default_front.py over
# the CSVs. One technique a run: an interleaved run keeps a renderer per setting, and every technique's at 8192² at once
# took 23.7 GB on `staircase`. The whole matrix (every
# technique, sizes 256..8192, three frame sizes) takes hours on a 2-core PoCL machine and minutes on a GPU; the
# environment narrows it.
# Environment: PENUMBRA (a built tool; default: build with scripts/setup.sh and use $BUILD_DIR/tools/penumbra),
# SCENES (space-separated; default: scenes/*.json and the built-in scenes), SIZES ("480x270 1280x720 1920x1080"),
# MAP_SIZES (256,512,1024,2048,4096,8192), TECHNIQUES (all), SPP (256), RUNS (3), WARMUP (1), OUT (docs/default-front.md),
# SECTION (empty: OUT is the table alone; else the table replaces or joins OUT's "## SECTION").
set -euo pipefail
cd "$(dirname "$0")/.."

SIZES=${SIZES:-480x270 1280x720 1920x1080}
MAP_SIZES=${MAP_SIZES:-256,512,1024,2048,4096,8192}
TECHNIQUES=${TECHNIQUES:-all}
SPP=${SPP:-256}
RUNS=${RUNS:-3}
WARMUP=${WARMUP:-1}
OUT=${OUT:-docs/default-front.md}
read -r -a SCENE_LIST <<<"${SCENES:-$(echo scenes/*.json) builtin:box builtin:staircase builtin:stacked-planes builtin:poles builtin:cards}"
PYTHON=${PYTHON:-$([ -x /usr/bin/python3 ] && echo /usr/bin/python3 || echo python3)}

if [ -z "${PENUMBRA:-}" ]; then
  ./scripts/setup.sh -DPENUMBRA_BUILD_BENCHMARKS=OFF
  PENUMBRA=${BUILD_DIR:-build}/tools/penumbra
fi
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$(dirname "$PENUMBRA")/../pocl-cache}

TECH_LIST=$TECHNIQUES
[ "$TECHNIQUES" = all ] && TECH_LIST=$("$PENUMBRA" render --help | sed -n 's/.*Shadow technique: //p' | tr -d ' ')
[ -n "$TECH_LIST" ] || { echo "default_front: no technique list" >&2; exit 1; }

mkdir -p out/front
csvs=()
for scene in "${SCENE_LIST[@]}"; do
  for size in $SIZES; do
    name=$(basename "$scene" .json | tr ':' '-')-$size
    for technique in ${TECH_LIST//,/ }; do
      echo "default_front: $scene at $size, $technique"
      # The scene's reference, shared by name: bench reuses a cached trace beside its CSV when its key (scene, camera,
      # size, lights, spp) matches, and traces a new one otherwise.
      stem=out/front/$name-$technique
      [ -f "out/front/$name.reference.exr" ] && ln -f "out/front/$name.reference.exr" "$stem.reference.exr"
      # Exit 1: some settings failed (a fixed size the device cannot hold, named on stderr); the others' rows stand.
      status=0
      "$PENUMBRA" bench "$scene" --size "$size" --techniques "$technique" --sweep "map-size=default,$MAP_SIZES" \
        --interleave --runs "$RUNS" --warmup "$WARMUP" --spp "$SPP" --quiet -o "$stem.csv" >/dev/null || status=$?
      [ "$status" -le 1 ] || exit "$status"
      ln -f "$stem.reference.exr" "out/front/$name.reference.exr"
      csvs+=("$stem.csv")
    done
  done
done
command="SCENES=\"${SCENE_LIST[*]}\" SIZES=\"$SIZES\" MAP_SIZES=$MAP_SIZES TECHNIQUES=$TECHNIQUES SPP=$SPP RUNS=$RUNS"
command="$command ./scripts/default_front.sh"
section_args=()
[ -n "${SECTION:-}" ] && section_args=(--section "$SECTION") && command="SECTION=\"$SECTION\" $command"
"$PYTHON" tools/default_front.py "$OUT" "${csvs[@]}" --command "$command" "${section_args[@]}"
