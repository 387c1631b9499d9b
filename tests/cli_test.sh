#!/usr/bin/env bash
# End-to-end tests of the `penumbra` tool: exit codes and one-line messages for bad input, and a real
# render of a built-in scene. Usage: cli_test.sh PENUMBRA_BINARY SCRATCH_DIR
set -u
bin=$1
scratch=$2
rm -rf "$scratch" && mkdir -p "$scratch"
source "$(dirname "$0")/expect.sh"

empty_vendors=$(mktemp -d)
expect no-device-devices 69 "no OpenCL" -- env OCL_ICD_VENDORS="$empty_vendors" "$bin" devices
expect no-device-render 69 "no OpenCL" -- env OCL_ICD_VENDORS="$empty_vendors" "$bin" render builtin:box -o "$scratch/x.exr"
expect bad-device 69 "no OpenCL device matches 'nope-device'" -- "$bin" render builtin:box --device nope-device -o "$scratch/x.exr"
expect devices-json 0 '"opencl_c_version"' -- "$bin" devices --json
expect no-subcommand 2 "subcommand" -- "$bin"
expect bad-size 2 "size" -- "$bin" render builtin:box --size 0x10 -o "$scratch/x.exr"
expect bad-size-text 2 "size" -- "$bin" render builtin:box --size big -o "$scratch/x.exr"
expect bad-camera 2 "camera|eye" -- "$bin" render builtin:box --camera 1,2:3 -o "$scratch/x.exr"
expect nan-camera 2 "camera|finite|eye" -- "$bin" render builtin:box --camera nan,1,1:0,0,0 -o "$scratch/x.exr"
expect bad-light 2 "light|spot|dir" -- "$bin" render builtin:box --light area:1,2,3 -o "$scratch/x.exr"
expect bad-light-fov 2 "fov|FOV|180" -- "$bin" render builtin:box --light spot:0,5,0:0,0,0:190 -o "$scratch/x.exr"
expect unknown-technique 2 "unknown technique 'nope'" -- "$bin" render builtin:box -t nope -o "$scratch/x.exr"
expect param-range 2 "pcf-radius" -- "$bin" render builtin:box -t pcf --pcf-radius 99 -o "$scratch/x.exr"
expect param-not-for-technique 2 "does not apply to technique 'sm'" -- "$bin" render builtin:box -t sm --pcf-radius 2 -o "$scratch/x.exr"
expect warp-choice 2 "--warp: 'lisp' is not one of none, lispsm" -- "$bin" render builtin:box -t sm --warp lisp -o "$scratch/x.exr"
expect lispsm-n-range 2 "lispsm-n" -- "$bin" render builtin:box -t pcf --lispsm-n -3 -o "$scratch/x.exr"
expect warp-not-for-technique 2 "does not apply to technique 'vsm'" -- "$bin" render builtin:box -t vsm --warp lispsm -o "$scratch/x.exr"
expect lispsm-spot-render 0 "" -- "$bin" render builtin:box -t sm --warp lispsm --size 32x18 --map-size 64 \
  --light spot:0,5,0:0,0,0:60 -q -o "$scratch/lispsm-spot.exr"
expect lispsm-spot-warped 0 "lispsm n [0-9.]+ \\(n_opt" -- grep -ao "lispsm n [^;]*" "$scratch/lispsm-spot.exr"
expect lispsm-snap 2 "pssm-snap" -- "$bin" render builtin:box -t pssm --warp lispsm --pssm-snap on --size 32x18 \
  --light dir:0.3,-1,-0.6 -o "$scratch/x.exr"
expect lispsm-render 0 "" -- "$bin" render builtin:box -t pssm --warp lispsm --size 32x18 --map-size 64 \
  --light dir:0.3,-1,-0.6 -q -o "$scratch/lispsm.exr"
expect jitter-passes-negative 2 "jitter-passes" -- "$bin" render builtin:box -t jittered --jitter-passes -1 -o "$scratch/x.exr"
expect jitter-epsilon-range 2 "jitter-epsilon" -- "$bin" render builtin:box -t jittered --jitter-epsilon 1.5 -o "$scratch/x.exr"
expect confidence-choice 2 "--confidence: 'best' is not one of simple, adapted, optimal" -- "$bin" render builtin:box \
  -t jittered --confidence best -o "$scratch/x.exr"
expect id-buffer-choice 2 "--id-buffer: 'mesh' is not one of off, object, polygon, combined" -- "$bin" render builtin:box \
  -t sm --id-buffer mesh -o "$scratch/x.exr"
expect id-buffer-not-for-technique 2 "does not apply to technique 'vsm'" -- "$bin" render builtin:box -t vsm \
  --id-buffer object -o "$scratch/x.exr"
expect jitter-rotation-with-warp 2 "need --warp none" -- "$bin" render builtin:box -t jittered --warp lispsm \
  --jitter-rotation 5 --size 32x18 --light dir:0.3,-1,-0.6 -o "$scratch/x.exr"
expect jittered-render 0 "" -- "$bin" render builtin:box -t jittered --id-buffer combined --jitter-reduction 0.6 --warp none \
  --size 32x18 --map-size 64 -q -o "$scratch/jittered.exr"
expect izb-samples-choice 2 "--izb-samples: '3' is not one of 1, 4, 8, 32" -- "$bin" render builtin:box -t izb --izb-samples 3 -o "$scratch/x.exr"
expect izb-render 0 "izb/izb_soft_test" -- "$bin" render builtin:cards -t izb --izb-samples 4 --izb-chunk 1000 --size 48x32 \
  --map-size 256 -o "$scratch/izb.exr"
expect izb-header 0 'receivers grid 256x256 texels \(32x32 cells\), 4 samples per pixel in 7 chunks' -- \
  bash -c "LC_ALL=C grep -ao 'receivers grid [^,]*, [^,]*' '$scratch/izb.exr' | head -n 1"
expect fvsm-budget-range 2 "fvsm-budget" -- "$bin" render builtin:box -t fvsm --fvsm-budget 10 -o "$scratch/x.exr"
expect fvsm-render 0 "fvsm/fvsm_request" -- "$bin" render builtin:poles -t fvsm --map-size 64 --fvsm-max-size 1024 \
  --fvsm-budget 16384 --size 48x32 -o "$scratch/fvsm.exr"
expect fvsm-header 0 'tiles of 64x64 \(levels [0-9]\.\.[0-9] of 4, virtual 1024x1024\)' -- \
  bash -c "LC_ALL=C grep -ao 'tiles of [^)]*)' '$scratch/fvsm.exr' | head -n 1"
expect savsm-width-above-max 2 "savsm-width 80 is larger than --savsm-max-width 64" -- "$bin" render builtin:box -t savsm --savsm-width 80 -o "$scratch/x.exr"
expect bad-choice 2 "'half' is not one of float, fixed32, fixed64, double" -- "$bin" render builtin:box -t savsm --sat-precision half -o "$scratch/x.exr"
expect render-msm 0 "wrote" -- "$bin" render builtin:box --size 64x48 -t msm --map-size 256 -o "$scratch/msm.exr"
expect missing-scene 1 "does-not-exist.glb" -- "$bin" render "$scratch/does-not-exist.glb" -o "$scratch/x.exr"
expect unknown-builtin 1 "builtin" -- "$bin" render builtin:nope -o "$scratch/x.exr"
printf 'not a gltf file' >"$scratch/garbage.glb"
expect garbage-glb 1 "garbage.glb" -- "$bin" render "$scratch/garbage.glb" -o "$scratch/x.exr"
models=/usr/share/assimp/models/glTF2
expect index-out-of-range 1 "out of range" -- "$bin" render "$models/IndexOutOfRange/IndexOutOfRange.gltf" -o "$scratch/x.exr"
expect infinite-vertices 1 "BoxWithInfinites.glb" -- "$bin" render "$models/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb" -o "$scratch/x.exr"
# glTF animation: --time poses the tutorial's skinned strip (named in the summary); --animation needs --time and
# names an animation the file has.
skin="$models/simple_skin/simple_skin.gltf"
expect animation-time 0 "simple_skin.gltf --time 1 on" -- "$bin" render "$skin" --time 1 --size 32x18 --map-size 64 \
  --png none -o "$scratch/skin.exr"
expect animation-needs-time 2 "requires --time" -- "$bin" render "$skin" --animation 0 -o "$scratch/x.exr"
expect animation-unknown 1 "--animation Walk: no such animation" -- "$bin" render "$skin" --time 1 --animation Walk \
  -o "$scratch/x.exr"
expect animation-bad-time 2 "--time" -- "$bin" render "$skin" --time soon -o "$scratch/x.exr"
# glTF cameras: a generated triangle file with a perspective and an orthographic camera (triangle.bin beside it).
cp "$(dirname "$0")/data/scenes/triangle.bin" "$scratch/triangle.bin"
cat >"$scratch/cams.gltf" <<'GLTF'
{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
 "nodes": [{"mesh": 0}, {"name": "Front", "camera": 0, "translation": [0.3, 0.3, 3]},
           {"camera": 1, "translation": [0.3, 0.3, 3]}],
 "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 2.0, "znear": 0.1}},
             {"type": "orthographic", "name": "Top", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0, "zfar": 10}}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
 "buffers": [{"uri": "triangle.bin", "byteLength": 80}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72, "byteStride": 12},
                 {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
               {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"},
               {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]}
GLTF
expect gltf-camera-default 0 '^camera gltf:0 "Front" \(perspective\)' -- "$bin" render "$scratch/cams.gltf" -t sm \
  --map-size 64 -o "$scratch/cams.exr"
expect gltf-camera-size 0 "1440x720" -- "$bin" render "$scratch/cams.gltf" -t sm --map-size 64 -o "$scratch/cams.exr"
expect gltf-camera-name 0 '^camera gltf:1 "Top" \(orthographic\)' -- "$bin" render "$scratch/cams.gltf" \
  --camera gltf:Top --size 32x32 -t pcss --map-size 64 -o "$scratch/cams.exr"
expect gltf-camera-index 0 '^camera gltf:1 "Top"' -- "$bin" reference "$scratch/cams.gltf" --camera gltf:1 \
  --size 32x32 -o "$scratch/cams-ref.exr"
expect gltf-camera-bad-index 2 '^penumbra: --camera gltf:5: no glTF camera "5" \(the scene.s glTF cameras: 0 "Front" \(perspective\), 1 "Top" \(orthographic\)\)$' \
  -- "$bin" render "$scratch/cams.gltf" --camera gltf:5 -o "$scratch/x.exr"
expect gltf-camera-bad-name 2 'no glTF camera "Back".*"Front"' -- "$bin" render "$scratch/cams.gltf" --camera gltf:Back \
  -o "$scratch/x.exr"
expect gltf-camera-none 2 'no glTF camera "0" \(the scene has no glTF cameras\)' -- "$bin" render builtin:box \
  --camera gltf:0 -o "$scratch/x.exr"
expect gltf-camera-lispsm-ortho 0 "warning: --warp lispsm with an orthographic camera" -- "$bin" render \
  "$scratch/cams.gltf" --camera gltf:Top --size 32x32 -t sm --warp lispsm --map-size 64 -o "$scratch/x.exr"
sed 's/"yfov": 0.6/"yfov": 4/' "$scratch/cams.gltf" >"$scratch/badcam.gltf"
expect gltf-camera-malformed 1 "badcam.gltf: /cameras/0/perspective/yfov: 4 radians is not below pi" -- "$bin" render \
  "$scratch/badcam.gltf" -o "$scratch/x.exr"
# Alpha-tested materials: the triangle file with a MASK material whose texture's image is missing must fail with one
# line naming the file, the image and the cause, and exit 1.
sed 's/"indices": 2}]}]/"indices": 2, "material": 0}]}], "materials": [{"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], "textures": [{"source": 0}], "images": [{"uri": "missing.png"}]/' \
  "$scratch/cams.gltf" >"$scratch/masked.gltf"
out=$("$bin" render "$scratch/masked.gltf" -o "$scratch/x.exr" 2>&1)
rc=$?
if [ "$rc" -eq 1 ] && [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] &&
  grep -qE '^penumbra: .*masked.gltf: image 0 "missing.png": "missing.png": file not found' <<<"$out"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1))
  echo "FAIL alpha-missing-texture: exit $rc (want 1, one line naming masked.gltf and image 0), output:"
  sed 's/^/    /' <<<"$out" | head -n 5
fi
expect blend-cutoff-range 2 "blend-cutoff" -- "$bin" render builtin:cards --blend-cutoff 1.5 -o "$scratch/x.exr"
expect cards-render 0 "materials: 2 materials \(1 MASK, 0 BLEND as MASK, 0 single-sided\), 1 alpha texture" -- \
  "$bin" render builtin:cards --size 64x48 -t pcf --map-size 256 -o "$scratch/cards.exr"
expect cards-header 0 "penumbra:materials" -- grep -ao "penumbra:materials" "$scratch/cards.exr"
expect cards-reference 0 "materials: 2 materials" -- "$bin" reference builtin:cards --size 32x24 --spp 16 \
  -o "$scratch/cards-ref.exr"
expect render-box 0 "wrote" -- "$bin" render builtin:box --size 64x48 -t pcss --map-size 256 -o "$scratch/box.exr"
if [ ! -s "$scratch/box.exr" ] || [ ! -s "$scratch/box.png" ]; then
  failed=$((failed + 1))
  echo "FAIL render-box: $scratch/box.exr or box.png missing"
else
  passed=$((passed + 1))
fi

# Outputs: -o's extension picks the format, the preview never lands on the EXR, --png none drops it.
# check NAME CONDITION...: one pass or fail for a file check.
check() {
  local name=$1
  shift
  if "$@"; then passed=$((passed + 1)); else failed=$((failed + 1)) && echo "FAIL $name: $*"; fi
}
small=(builtin:box --size 32x24 -t sm --map-size 64)
expect output-unknown-format 2 "^penumbra: -o .*x.tif: unknown output format '.tif'" -- "$bin" render "${small[@]}" -o "$scratch/x.tif"
expect output-no-extension 2 "unknown output format '\(no extension\)'" -- "$bin" reference "${small[@]:0:3}" -o "$scratch/x"
check output-unknown-format-writes-nothing test ! -e "$scratch/x.tif"
expect output-png-only 0 "wrote [^ ]*only.png$" -- "$bin" render "${small[@]}" -o "$scratch/only.png"
check output-png-only-is-png bash -c "head -c 4 '$scratch/only.png' | grep -q PNG"
check output-png-only-no-exr test ! -e "$scratch/only.exr"
expect output-png-twice 2 "is the PNG preview already" -- "$bin" render "${small[@]}" -o "$scratch/x.png" --png "$scratch/y.png"
expect output-png-none 0 "wrote [^ ]*nopng.exr$" -- "$bin" render "${small[@]}" -o "$scratch/nopng.exr" --png none
check output-png-none-no-png test ! -e "$scratch/nopng.png"
expect output-png-is-exr 2 "--png .*same.exr: is the EXR output itself" -- "$bin" render "${small[@]}" \
  -o "$scratch/same.exr" --png "$scratch/./same.exr"
expect reference-png-is-exr 2 "is the EXR output itself" -- "$bin" reference "${small[@]:0:3}" -o "$scratch/same.exr" \
  --png "$scratch/same.exr"
check output-png-is-exr-writes-nothing test ! -e "$scratch/same.exr"
version=$("$bin" --version)
expect version 0 "^penumbra [0-9]+\.[0-9]+\.[0-9]+$" -- echo "$version"
expect exr-version 0 "string.${version#penumbra }\$" -- bash -c "LC_ALL=C grep -ao 'penumbra:version.\{12\}[0-9.]*' '$scratch/nopng.exr' | tr -d '\\000'"
expect unknown-subcommand 2 "^penumbra: unknown subcommand 'rendr' \(one of devices, render, reference" -- "$bin" rendr x
mkdir -p "$scratch/no-kernels"
expect kernel-dir-empty 1 "PENUMBRA_KERNEL_DIR=.*no-kernels: the folder has no (kernels|raster)/" -- \
  env PENUMBRA_KERNEL_DIR="$scratch/no-kernels" "$bin" render "${small[@]}" -o "$scratch/x.exr"
expect kernel-dir-missing 1 "PENUMBRA_KERNEL_DIR=.*nowhere: not a folder" -- \
  env PENUMBRA_KERNEL_DIR="$scratch/nowhere" "$bin" render "${small[@]}" -o "$scratch/x.exr"

# reference (Embree) and compare: exit codes 0 within thresholds, 1 outside, 2 usage, 4 file errors.
expect reference-box 0 "wrote .*ref.png" -- "$bin" reference builtin:box --size 64x48 --spp 16 -o "$scratch/ref.exr"
if [ ! -s "$scratch/ref.exr" ] || [ ! -s "$scratch/ref.png" ]; then
  failed=$((failed + 1))
  echo "FAIL reference-box: $scratch/ref.exr or ref.png missing"
else
  passed=$((passed + 1))
fi
expect reference-bad-spp 2 "spp 10" -- "$bin" reference builtin:box --size 64x48 --spp 10 -o "$scratch/y.exr"
expect reference-bad-light 2 "light" -- "$bin" reference builtin:box --light spot:0,5,0:0,0,0:190 -o "$scratch/y.exr"
expect reference-small 0 "wrote" -- "$bin" reference builtin:box --size 32x24 --spp 4 -o "$scratch/small.exr"
# izb under an area light traces the rays `reference --izb-light-samples N` traces: the two images are equal.
expect reference-izb-pattern 0 "wrote" -- "$bin" reference builtin:staircase --size 64x40 --izb-light-samples 25 \
  -o "$scratch/ref-izb.exr"
expect izb-soft 0 "izb/izb_soft_test" -- "$bin" render builtin:staircase --size 64x40 -t izb --izb-light-samples 25 \
  -o "$scratch/izb-soft.exr"
expect izb-soft-equals-reference 0 "max +0.000000" -- "$bin" compare "$scratch/izb-soft.exr" "$scratch/ref-izb.exr"
expect izb-light-samples-square 2 "must be k\^2 for k in 4..16" -- "$bin" render builtin:box -t izb \
  --izb-light-samples 20 -o "$scratch/x.exr"
expect reference-izb-pattern-not-spp 2 "excludes" -- "$bin" reference builtin:box --izb-light-samples 16 --spp 16 \
  -o "$scratch/x.exr"
expect compare-self 0 "PASS" -- "$bin" compare "$scratch/ref.exr" "$scratch/ref.exr" --max-mae 0 --max-p95 0 --max-leak 0
expect compare-no-limits 0 "^PASS" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr"
expect compare-within 0 "PASS" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --max-mae 0.5 --max-false-shadow 0.5
expect compare-outside 1 "FAIL: mae" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --max-mae 0
expect compare-json 0 '"false_shadow"' -- "$bin" compare --json "$scratch/box.exr" "$scratch/ref.exr"
expect compare-json-umbra 0 '"umbra_light"' -- "$bin" compare --json "$scratch/box.exr" "$scratch/ref.exr"
expect compare-umbra-limit 0 'umbra_light' -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --max-umbra-light 1
expect compare-json-penumbra 0 '"penumbra_pixels"' -- "$bin" compare --json "$scratch/box.exr" "$scratch/ref.exr" \
  --max-penumbra-mae 1
expect compare-json-fail 1 '"pass": false' -- "$bin" compare --json "$scratch/box.exr" "$scratch/ref.exr" --max-rmse 0
expect compare-error-image 0 "PASS" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --error-image "$scratch/err/err.exr"
if [ ! -s "$scratch/err/err.exr" ] || [ ! -s "$scratch/err/err.png" ]; then
  failed=$((failed + 1))
  echo "FAIL compare-error-image: $scratch/err/err.exr or err.png missing"
else
  passed=$((passed + 1))
fi
expect compare-negative-limit 2 "max-mae" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --max-mae -1
expect compare-nan-limit 2 "max-leak" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --max-leak nan
expect compare-one-file 2 "reference" -- "$bin" compare "$scratch/box.exr"
expect compare-missing 4 "nope.exr" -- "$bin" compare "$scratch/nope.exr" "$scratch/ref.exr"
expect compare-size 4 "32x24" -- "$bin" compare "$scratch/small.exr" "$scratch/ref.exr"
expect compare-channel 4 "nope.Y" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --channel nope.Y
printf 'not an exr file' >"$scratch/garbage.exr"
expect compare-garbage 4 "garbage.exr" -- "$bin" compare "$scratch/garbage.exr" "$scratch/ref.exr"

# The compare mask: the reference's lit.Y leaves out pixels facing away from the light; --no-mask counts them.
expect compare-masked 0 "covered and lit.Y pixels" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr"
expect compare-no-mask 0 "over [0-9]+ covered pixels" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --no-mask
expect compare-mask-json 0 '"mask": "lit.Y"' -- "$bin" compare --json "$scratch/box.exr" "$scratch/ref.exr"

# bench: per-pass rows and a total row with metrics (reference traced once and cached beside the CSV).
bench=("$bin" bench builtin:box --size 48x32 --map-size 64 --spp 4 --runs 2 --warmup 1)
expect bench-box 0 "wrote .*bench.csv" -- "${bench[@]}" --techniques sm,pcf --sweep pcf-radius=1,2 \
  -o "$scratch/bench/bench.csv" --json "$scratch/bench/bench.json"
columns="scene,technique,setting,pass,calls,ms,bytes,floor_ms,mae,rmse,p95,max,off,leak,false_shadow,umbra_light,mean_signed"
if head -n 1 "$scratch/bench/bench.csv" 2>/dev/null | grep -q "^$columns," &&
  [ "$(grep -c ',total,' "$scratch/bench/bench.csv")" -eq 3 ] && [ -s "$scratch/bench/bench.reference.exr" ] &&
  grep -q '"copy_bandwidth_gbps"' "$scratch/bench/bench.json"; then
  passed=$((passed + 1))
else
  failed=$((failed + 1))
  echo "FAIL bench-box-csv: columns, 3 total rows (sm, pcf x 2), cached reference or JSON missing"
  head -n 3 "$scratch/bench/bench.csv" 2>&1 | sed 's/^/    /'
fi
cp "$scratch/bench/bench.csv" "$scratch/box.csv" 2>/dev/null  # the runs below rewrite bench.csv
# --interleave (round-robin over the settings, one Renderer each): the same rows and the same images' metrics.
expect bench-interleave 0 "wrote" -- "${bench[@]}" --techniques sm,pcf --sweep pcf-radius=1,2 --interleave \
  -o "$scratch/bench/interleaved.csv"
metrics() { awk -F, '$4 == "total" { print $2, $3, $9, $13 }' "$1"; }
if [ -n "$(metrics "$scratch/box.csv")" ] &&
  [ "$(metrics "$scratch/box.csv")" = "$(metrics "$scratch/bench/interleaved.csv" 2>/dev/null)" ]; then
  passed=$((passed + 1))
else
  failed=$((failed + 1))
  echo "FAIL bench-interleave-rows: interleaved totals differ from the sequential run's"
fi
# Interleaved renderers hold their buffers between rounds and share one budget: sm's 4096² maps (128 MiB) fit 150 MiB
# alone, and alone in a sequential run, but not beside the 2048² setting's 32 MiB.
expect bench-interleave-budget 1 "sm map-size=4096 failed: .* \(beside 32 MiB of 150 MiB held by 1 other interleaved" \
  -- "${bench[@]}" --techniques sm --sweep map-size=2048,4096 --interleave --memory-limit 150MiB \
  -o "$scratch/bench/x.csv"
expect bench-sequential-budget 0 "wrote" -- "${bench[@]}" --techniques sm --sweep map-size=2048,4096 \
  --memory-limit 150MiB -o "$scratch/bench/x.csv"
expect bench-sweep-skipped 0 "pcf-radius skipped for sm" -- "${bench[@]}" --techniques sm,pcf --sweep pcf-radius=1 \
  -o "$scratch/bench/bench.csv"
expect bench-reuses-reference 0 "reusing the reference" -- "${bench[@]}" --techniques sm -o "$scratch/bench/bench.csv"
expect bench-given-reference 0 "wrote" -- "$bin" bench builtin:box --size 64x48 --map-size 64 --runs 1 --warmup 0 \
  --techniques sm --reference "$scratch/ref.exr" -o "$scratch/bench/given.csv"
expect bench-reference-size 1 "64x48" -- "${bench[@]}" --techniques sm --reference "$scratch/ref.exr" \
  -o "$scratch/bench/x.csv"
expect bench-bad-sweep 2 "sweep" -- "${bench[@]}" --techniques sm --sweep map-size -o "$scratch/bench/x.csv"
expect bench-sweep-nobody 2 "pcf-radius" -- "${bench[@]}" --techniques sm --sweep pcf-radius=1 -o "$scratch/bench/x.csv"
expect bench-bad-value 2 "map-size" -- "${bench[@]}" --techniques sm --sweep map-size=1,2 -o "$scratch/bench/x.csv"
expect bench-bad-technique 2 "unknown technique 'nope'" -- "${bench[@]}" --techniques sm,nope -o "$scratch/bench/x.csv"
expect bench-bad-runs 2 "runs" -- "${bench[@]}" --techniques sm --runs 0 -o "$scratch/bench/x.csv"

# The chart and table scripts on bench's CSV (Debian's python3-matplotlib; scripts/setup.sh installs it).
python=$([ -x /usr/bin/python3 ] && echo /usr/bin/python3 || echo python3)
tools=$(cd "$(dirname "$0")/../tools" && pwd)
if "$python" -c "import matplotlib" 2>/dev/null; then
  expect chart 0 "wrote .*box.png" -- "$python" "$tools/chart.py" "$scratch/charts" "$scratch/box.csv"
  if [ -s "$scratch/charts/box.png" ] && [ -s "$scratch/charts/box.svg" ]; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL chart-files: $scratch/charts/box.png or .svg missing"
  fi
else
  echo "SKIP chart: matplotlib is missing for $python (apt-get install python3-matplotlib)"
fi
expect accuracy-table 0 "wrote" -- "$python" "$tools/accuracy_table.py" "$scratch/accuracy.md" "$scratch/box.csv"
# The default beside fixed map sizes in one run (--sweep map-size=default,...; the cached reference), then the table of
# whether each default sits on its technique's front.
expect bench-sweep-default 0 "map-size=default" -- "$bin" bench builtin:box --size 48x32 --map-size 64 --spp 4 --runs 1 \
  --warmup 0 --techniques sm --sweep map-size=default,64,128 -o "$scratch/bench/bench.csv"
cp "$scratch/bench/bench.csv" "$scratch/front.csv" 2>/dev/null
expect default-front 0 "wrote .* of 1 defaults on their front" -- "$python" "$tools/default_front.py" \
  "$scratch/front.md" "$scratch/front.csv"
expect default-front-row 0 "^\| builtin:box \| 48x32 \| light0 \| sm \| auto \|" -- cat "$scratch/front.md"
# --section: a second table under "## Splits" joins the page, and a new head keeps it.
expect default-front-section 0 "wrote .* of 1 defaults on their front" -- "$python" "$tools/default_front.py" \
  "$scratch/front.md" "$scratch/front.csv" --section Splits
expect default-front-head 0 "wrote" -- "$python" "$tools/default_front.py" "$scratch/front.md" "$scratch/front.csv"
expect default-front-kept 0 "^## Splits" -- cat "$scratch/front.md"
expect default-front-none 1 "no technique has both" -- "$python" "$tools/default_front.py" "$scratch/x.md" \
  "$scratch/box.csv"
expect accuracy-table-row 0 "^\| pcf \| pcf-radius=1 \|" -- cat "$scratch/accuracy.md"
# The Luksch sec. 10 comparison end to end on one tiny scene: references, bench per camera and config, table.
expect luksch-eval 0 "" -- "$python" "$tools/luksch_eval.py" "$bin" "$scratch/luksch" --size 32x18 --map-size 64 \
  --scenes box-sun --configs sm,lispsm,jittered
expect luksch-eval-table 0 "^\| box-sun \| parallel \| [0-9.]+ \| [0-9]+ \| [0-9.]+ \| [0-9]+ \|" -- \
  cat "$scratch/luksch/pixel-accurate.md"

# glTF lights (KHR_lights_punctual) on the triangle model over a box (a scene file; the box brings "light2"): the
# first light by default, --light gltf:INDEX|NAME, one clear line for a bad selection, and point lights in every
# command.
cp "$(dirname "$0")/data/scenes/triangle.bin" "$scratch/"
lit_gltf() {  # lit_gltf FILE LIGHTS NODES ROOTS [MORE]: the triangle model (node 0) plus light nodes; MORE: more
  # top-level members ("cameras": [...])
  cat >"$1" <<EOF
{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
 "extensions": {"KHR_lights_punctual": {"lights": $2}},${5:+
 $5,}
 "scene": 0, "scenes": [{"nodes": [$4]}], "nodes": [{"name": "tri", "mesh": 0}, $3],
 "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
 "buffers": [{"uri": "triangle.bin", "byteLength": 80}],
 "bufferViews": [{"buffer": 0, "byteLength": 72, "byteStride": 12}, {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
               {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"},
               {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]}
EOF
}
# Key: 6 m up, turned -90 degrees about X so its -Z points down; Sun: -60 degrees about X.
lit_gltf "$scratch/lit.gltf" '[{"type": "spot", "name": "Key", "spot": {"outerConeAngle": 0.6},
  "extras": {"penumbra": {"radius": 0.2}}}, {"type": "directional", "name": "Sun"}]' \
  '{"translation": [0, 6, 0], "rotation": [-0.7071068, 0, 0, 0.7071068], "extensions": {"KHR_lights_punctual": {"light": 0}}},
   {"rotation": [-0.5, 0, 0, 0.8660254], "extensions": {"KHR_lights_punctual": {"light": 1}}}' '0, 1, 2'
lit_gltf "$scratch/bulb.gltf" '[{"type": "point", "name": "Bulb"}]' \
  '{"translation": [0, 4, 0], "extensions": {"KHR_lights_punctual": {"light": 0}}}' '0, 1'
lit_gltf "$scratch/bad-type.gltf" '[{"type": "area"}]' '{"extensions": {"KHR_lights_punctual": {"light": 0}}}' '0, 1'
lit_gltf "$scratch/bad-index.gltf" '[{"type": "point"}]' '{"extensions": {"KHR_lights_punctual": {"light": 3}}}' '0, 1'
for f in lit bulb; do
  printf '{"models": [{"path": "%s.gltf", "translation": [0, 1, 0]}], "procedural": [{"name": "box"}]}' "$f" \
    >"$scratch/$f.json"
done
lit=("$scratch/lit.json" --size 32x24 -t sm --map-size 64)
expect gltf-light-default 0 'light "Key" \(the scene.s 1 of 3\): spot:0,7,0:' -- \
  "$bin" render "${lit[@]}" -o "$scratch/lit.exr"
expect gltf-light-exr-name 0 "penumbra:light-name.*Key" -- bash -c "LC_ALL=C grep -ao 'penumbra:light-name.\{12\}Key' '$scratch/lit.exr' | tr -d '\\000'"
expect gltf-light-by-name 0 'light "Sun" \(--light gltf:Sun\): dir:' -- "$bin" render "${lit[@]}" --light gltf:Sun \
  -o "$scratch/x.exr"
expect gltf-light-by-index 0 'light "Sun" \(--light gltf:1\)' -- "$bin" render "${lit[@]}" --light gltf:1 -o "$scratch/x.exr"
expect gltf-light-overridden 0 'light \(--light\): dir:0,-1,0$' -- "$bin" render "${lit[@]}" --light dir:0,-1,0 \
  -o "$scratch/x.exr"
expect gltf-light-quiet 0 '^$' -- "$bin" render "${lit[@]}" -q -o "$scratch/x.exr"
expect gltf-light-bad-index 2 '^penumbra: --light gltf:5: no light 5 \(the scene.s lights: 0 "Key" \(spot\), 1 "Sun" \(dir\), 2 "light2" \(spot\)\)$' -- \
  "$bin" render "${lit[@]}" --light gltf:5 -o "$scratch/x.exr"
expect gltf-light-unknown-name 2 '^penumbra: --light gltf:Fill: no light named "Fill" \(the scene.s lights: 0 "Key"' -- \
  "$bin" render "${lit[@]}" --light gltf:Fill -o "$scratch/x.exr"
expect gltf-light-reference 0 'light "Sun" \(the scene.s 2 of 3\)' -- "$bin" reference "$scratch/lit.json" \
  --size 32x24 --spp 4 -o "$scratch/lit-ref.exr"
# Several lights per frame: every light in its own layer (the first also as visibility.Y), traced the same way by
# the reference; compare --light NAME picks visibility.NAME.Y and lit.NAME.Y; bench reports per light.
expect multi-light-layers 0 'visibility.Sun.Y' -- bash -c "LC_ALL=C grep -ao 'visibility.Sun.Y' '$scratch/lit.exr' | head -n 1"
expect multi-light-ref-lit 0 'lit.light2.Y' -- bash -c "LC_ALL=C grep -ao 'lit.light2.Y' '$scratch/lit-ref.exr' | head -n 1"
expect compare-light 0 'visibility.Sun.Y over [0-9]+ covered and lit.Sun.Y pixels' -- \
  "$bin" compare "$scratch/lit.exr" "$scratch/lit-ref.exr" --light Sun
expect compare-light-unknown 4 '^penumbra compare: --light Fill: .*lit.exr has no light "Fill" \(its lights: Key, Sun, light2\)$' -- \
  "$bin" compare "$scratch/lit.exr" "$scratch/lit-ref.exr" --light Fill
expect compare-light-and-channel 2 'excludes' -- \
  "$bin" compare "$scratch/lit.exr" "$scratch/lit-ref.exr" --light Sun --channel visibility.Y
expect bench-per-light 0 '' -- "$bin" bench "$scratch/lit.json" --size 32x24 --map-size 64 --techniques sm --runs 1 --warmup 0 --no-reference -q \
  -o "$scratch/lit-bench.csv"
# The light column, then penumbra_mae, penumbra_pixels, bytes_per_pixel, wall_ms, first_wall_ms.
expect bench-per-light-rows 0 '^sm,.*,total,.*,Sun(,[^,]*){5}$' -- bash -c "grep -E ',total,' '$scratch/lit-bench.csv' | sed 's/^[^,]*,//'"
# The ray tracer as bench's peer: `reference` with its own spp, wall-clock passes, error against the ground truth.
expect bench-reference-peer 0 'reference +spp=16' -- "$bin" bench builtin:box --size 48x32 --map-size 64 --spp 64 \
  --techniques sm,reference --sweep spp=4,16 --runs 1 --warmup 0 -o "$scratch/peer/peer.csv"
expect bench-reference-peer-rows 0 '^reference,spp=4,reference/trace,1,' -- cut -d, -f2- "$scratch/peer/peer.csv"
expect bench-reference-peer-metrics 0 '^reference,spp=16,total,3,[0-9.e+-]+,,,[0-9]' -- cut -d, -f2- "$scratch/peer/peer.csv"
expect bench-reference-peer-noise 0 'no fewer samples than the ground truth' -- "$bin" bench builtin:box --size 48x32 \
  --spp 4 --techniques reference --sweep spp=4 --runs 1 --warmup 0 -o "$scratch/peer/noise.csv"
expect bench-reference-bad-spp 2 'reference: spp 5: must be 4 k\^2' -- "$bin" bench builtin:box --size 48x32 \
  --techniques reference --sweep spp=5 --runs 1 -o "$scratch/peer/bad.csv"
expect bench-unknown-technique 2 "unknown technique 'nope'.*'reference'" -- "$bin" bench builtin:box --techniques nope \
  -o "$scratch/peer/bad.csv"
# Per-light techniques from a scene file: "technique" and "params" on a light entry, checked like -t and --PARAM.
printf '{"procedural": [{"name": "box"}], "lights": [%s, %s]}' \
  '{"name": "Key", "type": "spot", "position": [0, 5, 0], "target": [0, 0, 0], "radius": 0.2, "technique": "pcss", "params": {"pcss-filter-taps": 4}}' \
  '{"name": "Sun", "type": "dir", "direction": [0.3, -1, 0.2]}' >"$scratch/two-techniques.json"
expect light-own-technique 0 'light "Key" shadowed by its own technique pcss \(.*pcss-filter-taps=4' -- \
  "$bin" render "$scratch/two-techniques.json" --size 32x24 -t sm --map-size 64 -o "$scratch/two.exr"
printf '{"procedural": [{"name": "box"}], "lights": [%s]}' \
  '{"name": "Key", "type": "spot", "position": [0, 5, 0], "target": [0, 0, 0], "technique": "sm", "params": {"pcss-filter-taps": 4}}' \
  >"$scratch/bad-technique-param.json"
expect light-own-technique-bad-param 2 'bad-technique-param.json: light "Key": params: "pcss-filter-taps" is not a parameter of technique .sm.' -- \
  "$bin" render "$scratch/bad-technique-param.json" --size 32x24 -o "$scratch/x.exr"
sed 's/"technique": "sm", "params": {"pcss-filter-taps": 4}/"technique": "nope"/' "$scratch/bad-technique-param.json" >"$scratch/bad-technique.json"
expect light-own-technique-unknown 2 'bad-technique.json: light "Key": unknown technique .nope.' -- \
  "$bin" render "$scratch/bad-technique.json" --size 32x24 -o "$scratch/x.exr"
expect gltf-light-bad-type 1 'bad-type.gltf: /extensions/KHR_lights_punctual/lights/0/type: expected "spot", "directional" or "point", got "area"$' -- \
  "$bin" render "$scratch/bad-type.gltf" -o "$scratch/x.exr"
expect gltf-light-bad-node-index 1 'bad-index.gltf: /nodes/1/extensions/KHR_lights_punctual/light: no light 3 in KHR_lights_punctual \(the file has 1\)$' -- \
  "$bin" render "$scratch/bad-index.gltf" -o "$scratch/x.exr"
# Point lights (six cube faces): every technique renders one (registry.cpp; none refuses), and so do reference,
# compare and bench; the header records the faces drawn, the EXR has the face layer, --cube-guard is a parameter.
for t in sm pcf pcss vsm evsm2 evsm4 esm msm savsm vssm lvsm pssm psvsm jittered fvsm izb; do  # every technique (registry.cpp)
  expect "point-light-$t" 0 'light "Bulb" \(the scene.s 1 of 2\): point:0,5,0' -- \
    "$bin" render "$scratch/bulb.json" --size 32x24 --map-size 64 -t "$t" -o "$scratch/bulb-$t.exr"
done
expect point-light-header 0 'faces drawn: ' -- bash -c "LC_ALL=C grep -ao 'faces drawn: [^;]*' '$scratch/bulb-sm.exr' | head -n 1"
expect point-light-face-layer 0 'cubeFace.Y' -- bash -c "LC_ALL=C grep -ao 'cubeFace.Y' '$scratch/bulb-sm.exr' | head -n 1"
expect point-light-cli 0 'light \(--light\): point:0,4,0:0.1$' -- \
  "$bin" render builtin:box --light point:0,4,0:0.1 --size 32x24 --map-size 64 -o "$scratch/x.exr"
expect point-light-reference 0 'light "Bulb" \(the scene.s 1 of 2\)' -- \
  "$bin" reference "$scratch/bulb.json" --size 32x24 -o "$scratch/bulb-ref.exr"
expect point-light-compare 0 'visibility.Bulb.Y over [0-9]+ covered and lit.Bulb.Y pixels' -- \
  "$bin" compare "$scratch/bulb-sm.exr" "$scratch/bulb-ref.exr" --light Bulb --max-off 0.1
expect point-light-bench 0 '' -- "$bin" bench "$scratch/bulb.json" --size 32x24 --map-size 64 --techniques sm,pcf \
  --runs 1 --warmup 0 --reference "$scratch/bulb-ref.exr" -q -o "$scratch/bulb-bench.csv"
expect point-light-bench-rows 0 '^pcf,.*,total,.*,Bulb(,[^,]*){5}$' -- bash -c "grep -E ',total,' '$scratch/bulb-bench.csv' | sed 's/^[^,]*,//'"
expect point-light-guard-sweep 0 '' -- "$bin" bench "$scratch/bulb.json" --light gltf:Bulb --size 32x24 --map-size 64 \
  --techniques pcf --sweep cube-guard=0,8 --runs 1 --warmup 0 --no-reference -q -o "$scratch/guard.csv"
expect point-light-guard-rows 0 '^pcf,cube-guard=8,total,' -- bash -c "grep -E ',total,' '$scratch/guard.csv' | sed 's/^[^,]*,//'"
expect point-light-guard-range 2 'cube-guard' -- "$bin" render "$scratch/bulb.json" -t pcf --cube-guard -1 -o "$scratch/x.exr"
# A glTF file with a camera and a point light renders and traces with no view options (its camera, its light).
lit_gltf "$scratch/cam-bulb.gltf" '[{"type": "point", "name": "Bulb"}]' \
  '{"translation": [0.5, 0.4, 0.6], "extensions": {"KHR_lights_punctual": {"light": 0}}}, {"camera": 0, "translation": [0.4, 0.5, 2.5]}' \
  '0, 1, 2' '"cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.0, "znear": 0.05}}]'
expect point-light-gltf-camera 0 'light "Bulb" \(the scene.s 1 of 1\): point:0.5,0.4,0.6' -- \
  "$bin" render "$scratch/cam-bulb.gltf" -t sm --map-size 256 -o "$scratch/cam-bulb.exr"
expect point-light-gltf-camera-ref 0 'camera gltf:0' -- "$bin" reference "$scratch/cam-bulb.gltf" -o "$scratch/cam-bulb-ref.exr"
expect point-light-gltf-camera-compare 0 'off' -- \
  "$bin" compare "$scratch/cam-bulb.exr" "$scratch/cam-bulb-ref.exr" --max-off 0.01
expect point-light-bad-radius 2 "radius: -1 is negative" -- "$bin" render builtin:box --light point:0,4,0:-1 -o "$scratch/x.exr"

# selftest (docs/portability.md): the lists, a run with its JSON report, bad arguments, and no device.
expect selftest-list 0 'technique/izb_square_disk' -- "$bin" selftest --list
expect selftest-list-full 0 'sat/Fp32_Hensley_50x40_c2_nonfinite' -- "$bin" selftest --full --list
expect selftest-run 0 '4 of 4 checks passed' -- "$bin" selftest \
  --filter 'sat/Fixed32_Lines,raster/cube_classify,moments/Msm_97x61' --json "$scratch/selftest/report.json"
expect selftest-json 0 'ok' -- python3 -c "
import json, sys
r = json.load(open('$scratch/selftest/report.json'))
assert r['passed'] == 4 and r['failed'] == 0 and len(r['checks']) == 4, r
assert all(c['status'] == 'pass' and c['tolerance'] is not None for c in r['checks']), r['checks']
d = r['device']
assert d['name'] and d['driver_version'] and d['opencl_c_version'] and 'sat' in d['work_group_layouts'], d
print('ok')"
expect selftest-no-match 2 "no check matches 'nothing-like-this'" -- "$bin" selftest --filter nothing-like-this
expect selftest-quick-and-full 2 'excludes' -- "$bin" selftest --quick --full
expect selftest-json-directory 1 "$scratch" -- "$bin" selftest --filter raster/cube_classify --json "$scratch"
expect selftest-no-device 69 "no OpenCL" -- env OCL_ICD_VENDORS="$empty_vendors" "$bin" selftest
# A kernel that does not build is an error row with its compiler's log, never a crash (PENUMBRA_KERNEL_DIR: a copy of
# the kernel sources with sat.cl broken); the other checks still run.
src=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$scratch/broken/tools/selftest"
cp -r "$src/kernels" "$src/raster" "$scratch/broken/" && cp -r "$src/tools/selftest/kernels" "$scratch/broken/tools/selftest/"
echo "this is not OpenCL C;" >>"$scratch/broken/kernels/sat.cl"
expect selftest-build-error 1 '2 of 3 checks passed, 0 skipped, 1 failed \(1 of them errors\)' -- \
  env PENUMBRA_KERNEL_DIR="$scratch/broken" "$bin" selftest --filter sat/Fp32_Lines_97x61,moments/Vsm_97x61 \
  --json "$scratch/broken.json"
expect selftest-build-log 0 'ok' -- python3 -c "
import json
rows = {c['case']: c for c in json.load(open('$scratch/broken.json'))['checks']}
sat = rows['Fp32_Lines_97x61_c2']
assert sat['status'] == 'error' and 'sat.cl' in sat['build_log'] and 'kernels/sat.cl' in sat['message'], sat
assert rows['Vsm_97x61']['status'] == 'pass', rows
print('ok')"
# Embree is loaded only by the tracer: without it `reference` says so, and the selftest and renders run.
expect no-embree-reference 1 "Embree 3 is not installed.*libembree3-3" -- \
  env PENUMBRA_EMBREE_LIBRARY=/nonexistent/libembree3.so "$bin" reference builtin:box --size 32x24 --spp 4 -o "$scratch/no-embree.exr"
expect no-embree-selftest 0 "2 of 2 checks passed" -- env PENUMBRA_EMBREE_LIBRARY=/nonexistent/libembree3.so \
  "$bin" selftest --filter technique/izb_square

finish
