#!/usr/bin/env bash
# End-to-end checks of the limits and messages of docs/robustness.md: one size limit everywhere, the frame memory
# plan (--memory-limit), huge but finite coordinates and overflowed counts named by file and element, and the warning
# of a frame that sees nothing. Inputs are the fuzz corpus's hostile seeds. Usage: cli_robustness_test.sh BIN SCRATCH
set -u
bin=$1
scratch=$2
rm -rf "$scratch" && mkdir -p "$scratch"
source "$(dirname "$0")/expect.sh"
corpus="$(dirname "$0")/fuzz/corpus"
cp "$corpus/gltf/hostile-triangle.gltf" "$scratch/triangle.gltf"
for f in ground-minus-1e38 eye-1e308 size-too-big; do cp "$corpus/scene_file/hostile-$f.json" "$scratch/$f.json"; done

expect size-above-raster 2 'width 8193 is outside 1..8192' -- "$bin" render builtin:box --size 8193x16 -o "$scratch/x.exr"
expect scene-file-size 1 'size-too-big.json: /camera/size: expected \[width, height\], integers in 1..8192' -- \
  "$bin" render "$scratch/size-too-big.json" -o "$scratch/x.exr"
expect memory-limit-refuses 1 'needs [0-9.]+ GiB of device memory, more than 1.0 GiB \(--memory-limit\); the most: G-buffer' -- \
  "$bin" render builtin:box -t evsm4 --moment-filtering trilinear --size 4096x4096 --memory-limit 1GiB -o "$scratch/x.exr"
expect memory-limit-fits 0 'wrote' -- "$bin" render builtin:box -t sm --size 64x48 --map-size 256 --memory-limit 1GiB \
  -o "$scratch/fits.exr"
# izb's bounded memory at the issue's scale: a million triangles (builtin:poles, 84 000 poles) at 3840x2160, 8
# samples a pixel in 4 passes of 2^24 samples, inside a 1.5 GiB plan (docs/techniques/izb.md: 32 samples peak at
# 991 MB on PoCL). The scene's sun made a point direction: the hard path (the soft one's scale is in that doc).
expect izb-1m-triangles-4k 0 'izb/izb_test +[0-9.]+ +4$' -- "$bin" render 'builtin:poles:rows=300,columns=280' -t izb \
  --light dir:0.49827287,-0.83045477,-0.24913643 --izb-samples 8 --size 3840x2160 --memory-limit 1536MiB \
  -o "$scratch/izb-4k.png"
expect memory-limit-bad 2 '--memory-limit "lots": expected a number' -- "$bin" render builtin:box --memory-limit lots \
  -o "$scratch/x.exr"
expect bench-memory-limit 2 '--memory-limit "0"' -- "$bin" bench builtin:box --techniques sm --memory-limit 0 \
  -o "$scratch/x.csv"
expect positions-3e38 1 'hostile-positions-3e38.gltf: accessor 0: POSITION 1 \(3e\+38, 0, 0\) is outside \+-1e\+18' -- \
  "$bin" render "$corpus/gltf/hostile-positions-3e38.gltf" -o "$scratch/x.exr"
expect translation-1e300 1 'hostile-translation-1e300.gltf: node 0: world translation \(1e\+300, 0, 0\) is outside' -- \
  "$bin" render "$corpus/gltf/hostile-translation-1e300.gltf" -o "$scratch/x.exr"
expect scale-1e30 1 'hostile-scale-1e30.gltf: node 0 \(mesh 0 primitive 0\): world position' -- \
  "$bin" render "$corpus/gltf/hostile-scale-1e30.gltf" -o "$scratch/x.exr"
expect sparse-overflow 1 '/accessors/0/sparse/count: 2147483648 is larger than 2147483647' -- \
  "$bin" render "$corpus/gltf/hostile-sparse-overflow.gltf" -o "$scratch/x.exr"
expect eye-1e308 1 'eye-1e308.json: /camera/eye: \[1e\+308,0,0\] is outside \+-1e\+18' -- \
  "$bin" render "$scratch/eye-1e308.json" -o "$scratch/x.exr"
expect ground-minus-1e38 1 'ground-minus-1e38.json: /ground/y: expected a number in \+-1e\+18' -- \
  "$bin" render "$scratch/ground-minus-1e38.json" -o "$scratch/x.exr"
expect camera-1e30 2 'eye x: 1e30 is outside \+-1e\+18' -- "$bin" render builtin:box --camera 1e30,0,0:0,0,0 -o "$scratch/x.exr"
expect scale-zero-warns 0 'warning: the frame sees no surface.*no extent' -- \
  "$bin" render "$corpus/gltf/hostile-scale-zero.gltf" --size 32x18 --map-size 64 -t sm -o "$scratch/zero.exr"
# A light as large as the scene renders (the caller asked for it) but says why render and reference will disagree.
expect light-engulfs-scene 0 'warning: light point:0,5,0:1e\+17: the scene comes within 5 of its centre, inside its radius' -- \
  "$bin" render builtin:box --light point:0,5,0:1e17 --size 32x18 --map-size 64 -t sm -o "$scratch/engulf.exr"
expect light-engulfs-scene-reference 0 'warning: light point:0,5,0:1e\+17: the scene comes within 5' -- \
  "$bin" reference builtin:box --light point:0,5,0:1e17 --size 32x18 --spp 4 -o "$scratch/engulf-ref.exr"

# Outputs that are not regular files are never replaced (docs/robustness.md, Outputs): a FIFO is written in place and
# stays a FIFO, a symlink is written through and stays a link, a directory is refused, a full device is an error.
# (/dev/null itself is left alone here: tests/io_atomic_file_test.cpp checks it is written in place before writing.)
mkfifo "$scratch/preview.fifo"
cat "$scratch/preview.fifo" >"$scratch/from-fifo.png" &
reader=$!
expect png-into-fifo 0 'wrote .*preview.fifo' -- "$bin" render builtin:box -t sm --size 64x48 --map-size 256 \
  -o "$scratch/fifo.exr" --png "$scratch/preview.fifo"
wait "$reader"
expect fifo-stays-fifo 0 'fifo' -- bash -c "[ -p '$scratch/preview.fifo' ] && echo fifo"
expect fifo-carried-png 0 '^PNG$' -- bash -c "head -c 4 '$scratch/from-fifo.png' | tail -c 3"
mkdir -p "$scratch/real"
ln -sf real/linked.exr "$scratch/link.exr"
expect exr-through-symlink 0 'wrote' -- "$bin" render builtin:box -t sm --size 64x48 --map-size 256 \
  -o "$scratch/link.exr" --png none
expect symlink-kept 0 'kept' -- bash -c "[ -L '$scratch/link.exr' ] && [ -f '$scratch/real/linked.exr' ] && echo kept"
expect output-directory 1 'real: is a directory' -- "$bin" render builtin:box -t sm --size 64x48 --map-size 256 \
  -o "$scratch/out.exr" --png "$scratch/real"
expect output-directory-keeps-nothing 0 'none' -- bash -c "[ ! -e '$scratch/out.exr' ] && echo none"
if [ -c /dev/full ]; then
  expect bench-csv-full-disk 1 '/dev/full: write failed: No space left on device' -- \
    "$bin" bench builtin:box --techniques sm --size 32x24 --map-size 64 --runs 1 --warmup 0 --no-reference -o /dev/full
  expect full-device-still-device 0 'device' -- bash -c "[ -c /dev/full ] && echo device"
fi

# Inputs read with a bound (docs/robustness.md, Limits): a manifest, sweep or camera path from /dev/zero stops at its
# limit at once, a FIFO nobody writes to reads as empty instead of blocking, a directory is named; a sweep's job count
# and its template's field widths are checked before any job is made.
expect manifest-dev-zero 66 '/dev/zero: the manifest is over the limit of 268435456 bytes' -- \
  timeout 60 "$bin" run /dev/zero --out "$scratch/run"
mkfifo "$scratch/manifest.fifo"
expect manifest-fifo-without-writer 66 'manifest.fifo: the manifest holds no job' -- \
  timeout 60 "$bin" run "$scratch/manifest.fifo" --out "$scratch/run"
expect manifest-directory 66 'cannot read the manifest: is a directory' -- timeout 60 "$bin" run "$scratch" --out "$scratch/run"
expect sweep-dev-zero 1 '/dev/zero: the sweep is over the limit of 16777216 bytes' -- \
  timeout 60 "$bin" plan /dev/zero -o "$scratch/jobs.jsonl"
echo '{"scene": "builtin:box", "technique": "sm", "frames": 3, "output": "f{frame:999999999}.exr"}' >"$scratch/wide.json"
expect sweep-field-width 1 "a width or precision above 64 in '\\{frame:999999999\\}'" -- \
  timeout 60 "$bin" plan "$scratch/wide.json" -o "$scratch/jobs.jsonl"
hundred=$(seq -s, 0 99)
echo "{\"scene\": \"builtin:box\", \"technique\": [\"sm\", \"pcf\", \"pcss\", \"vsm\"], \"a\": [$hundred], \"b\": [$hundred], \
\"c\": [$hundred], \"output\": \"x{index}.exr\"}" >"$scratch/product.json"
expect sweep-product 1 'more than 1000000 jobs \(4 "technique" x 100 "a" x 100 "b" x 100 "c"\)' -- \
  timeout 60 "$bin" plan "$scratch/product.json" -o "$scratch/jobs.jsonl"
expect camera-path-dev-zero 2 '/dev/zero: the camera path is over the limit of 67108864 bytes' -- \
  timeout 60 "$bin" bench builtin:box --camera-path @/dev/zero --frames 2 --techniques sm -o "$scratch/b.csv"

# bench on SIGTERM: the frame in flight ends, the settings measured so far are written, exit 143 (it used to die from
# the signal with nothing written).
"$bin" bench builtin:box --techniques sm,pcf,pcss,vsm --size 96x64 --map-size 256 --runs 100 --no-reference \
  -o "$scratch/term.csv" >"$scratch/term.log" 2>&1 &
bench_pid=$!
for _ in $(seq 1 1200); do grep -q '(25% done)' "$scratch/term.log" && break; sleep 0.1; done
kill -TERM "$bench_pid"
wait "$bench_pid"
expect bench-sigterm-exit 0 '^143$' -- echo "$?"
expect bench-sigterm-message 0 'bench: stopped by SIGTERM: wrote the [1-3] of 4 settings measured so far' -- \
  cat "$scratch/term.log"
expect bench-sigterm-rows 0 '^builtin:box,sm,default,total,' -- cat "$scratch/term.csv"

# Values that used to be accepted and made nonsense or aborts (docs/robustness.md, Messages).
expect blend-cutoff-nan 2 '--blend-cutoff: not a number in \[0, 1\]' -- "$bin" render builtin:box --blend-cutoff nan \
  -o "$scratch/x.exr"
expect light-radius-1e30 2 'radius: 1e30 is outside \[0, 1e\+18\]' -- \
  "$bin" reference builtin:box --light spot:0,5,0:0,0,0:60:1e30 -o "$scratch/x.exr"
expect time-limit-nan 2 '--time-limit nan: use 90s, 15m, 2h or H:MM:SS' -- "$bin" run /dev/null --time-limit nan \
  --out "$scratch/run"
expect time-limit-99-minutes 2 '--time-limit 1:99:99: use' -- "$bin" run /dev/null --time-limit 1:99:99 --out "$scratch/run"
expect max-failures-negative 2 '--max-failures: Value -1 not in range' -- "$bin" run /dev/null --max-failures -1 \
  --out "$scratch/run"
"$bin" render builtin:box -t sm --size 32x24 --map-size 64 -q -o "$scratch/cov.exr" --png none
expect compare-coverage-unknown 4 '--coverage nan: neither image has that channel' -- \
  "$bin" compare "$scratch/cov.exr" "$scratch/cov.exr" --coverage nan

# Messages that name the problem (docs/robustness.md, Messages).
expect map-size-range 2 '--map-size-min 4096 is above --map-size-max 1024' -- \
  "$bin" render builtin:box --map-size-min 4096 --map-size-max 1024 -o "$scratch/x.exr"
expect eye-target-1e-30 2 'camera eye and target: \(0, 1, 0\) and \(0, 1, 1e-30\) are 1e-30 apart' -- \
  "$bin" render builtin:box --camera 0,1,0:0,1,1e-30 -o "$scratch/x.exr"
expect light-radius-1e300 2 'radius: 1e300 is beyond the largest float' -- \
  "$bin" render builtin:box --light point:0,5,0:1e300 -o "$scratch/x.exr"
ln -sf loop-b.glb "$scratch/loop-a.glb" && ln -sf loop-a.glb "$scratch/loop-b.glb"
expect symlink-loop 1 'loop-a.glb: cannot open: Too many levels of symbolic links' -- \
  "$bin" render "$scratch/loop-a.glb" -o "$scratch/x.exr"
mkdir -p "$scratch/folder.glb"
expect directory-as-scene 1 'folder.glb: is a directory, not a scene file' -- \
  "$bin" render "$scratch/folder.glb" -o "$scratch/x.exr"

echo '{"scene": "builtin:box", "technique": "sm", "frames": 4, "camera": {"orbit": {"target": [0, 0, 0],
 "radius": 1e300}}, "output": "o{frame}.exr"}' >"$scratch/orbit.json"
expect plan-orbit-1e300 1 'camera path, frame 0: camera "0,0,1e\+300:0,0,0:45": eye z: 1e\+300 is beyond the largest' -- \
  "$bin" plan "$scratch/orbit.json" -o "$scratch/jobs.jsonl"

finish
