#!/usr/bin/env bash
# End-to-end tests of the `penumbra` tool: exit codes and one-line messages for bad input, and a real
# render of a built-in scene. Usage: cli_test.sh PENUMBRA_BINARY SCRATCH_DIR
set -u
bin=$1
scratch=$2
rm -rf "$scratch" && mkdir -p "$scratch"
passed=0
failed=0

# expect NAME CODE PATTERN -- COMMAND...: runs COMMAND, checks the exit code and that stderr+stdout match PATTERN.
expect() {
  local name=$1 code=$2 pattern=$3
  shift 4
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if [ "$rc" -eq "$code" ] && grep -qE -- "$pattern" <<<"$out"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL $name: exit $rc (want $code), output (want /$pattern/):"
    sed 's/^/    /' <<<"$out" | head -n 20
  fi
}

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
expect render-box 0 "wrote" -- "$bin" render builtin:box --size 64x48 -t pcss --map-size 256 -o "$scratch/box.exr"
if [ ! -s "$scratch/box.exr" ] || [ ! -s "$scratch/box.png" ]; then
  failed=$((failed + 1))
  echo "FAIL render-box: $scratch/box.exr or box.png missing"
else
  passed=$((passed + 1))
fi

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
expect compare-self 0 "PASS" -- "$bin" compare "$scratch/ref.exr" "$scratch/ref.exr" --max-mae 0 --max-p95 0 --max-leak 0
expect compare-no-limits 0 "^PASS" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr"
expect compare-within 0 "PASS" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --max-mae 0.5 --max-false-shadow 0.5
expect compare-outside 1 "FAIL: mae" -- "$bin" compare "$scratch/box.exr" "$scratch/ref.exr" --max-mae 0
expect compare-json 0 '"false_shadow"' -- "$bin" compare --json "$scratch/box.exr" "$scratch/ref.exr"
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

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
