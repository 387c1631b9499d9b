#!/usr/bin/env bash
# Renders the gallery (docs/gallery/TECHNIQUE.png): the bundled default scene under every technique at its
# default parameters, plus the Embree reference, as PNG previews docs/techniques/README.md (and the README) show side by side.
# Environment: PENUMBRA (a built tool; default: build with scripts/setup.sh), SCENE (scenes/default.json),
# SIZE (480x270), SPP (256).
set -euo pipefail
cd "$(dirname "$0")/.."

SCENE=${SCENE:-scenes/default.json}
SIZE=${SIZE:-480x270}
SPP=${SPP:-256}
if [ -z "${PENUMBRA:-}" ]; then
  ./scripts/setup.sh -DPENUMBRA_BUILD_BENCHMARKS=OFF
  PENUMBRA=${BUILD_DIR:-build}/tools/penumbra
fi
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$(dirname "$PENUMBRA")/../pocl-cache}

mkdir -p out/gallery docs/gallery
techniques=$("$PENUMBRA" render --help | sed -n "s/.*Shadow technique: //p" | tr -d ",")
[ -n "$techniques" ] || { echo "gallery: could not read the technique list from 'penumbra render --help'" >&2; exit 1; }
for t in $techniques; do
  echo "gallery: $t"
  "$PENUMBRA" render "$SCENE" --size "$SIZE" -t "$t" -o "out/gallery/$t.exr" --png "docs/gallery/$t.png" >/dev/null
done
echo "gallery: reference ($SPP spp)"
"$PENUMBRA" reference "$SCENE" --size "$SIZE" --spp "$SPP" -o out/gallery/reference.exr \
  --png docs/gallery/reference.png >/dev/null
echo "gallery: wrote docs/gallery/*.png"
