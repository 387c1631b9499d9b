#!/usr/bin/env bash
# Batch rendering end to end, no scheduler (docs/batch.md): plan, shards from each scheduler's environment variables
# covering every job exactly once, outputs equal to single `render`s bit for bit, a rerun rendering nothing, SIGTERM
# mid-run leaving no partial file and a rerun completing, --time-limit, --max-failures, --only-failed, status, and
# malformed manifests and lines. Usage: batch_test.sh PENUMBRA EXR_CHANNEL_EQUAL SCRATCH_DIR
set -u
bin=$1
exr_equal=$2
scratch=$3
rm -rf "$scratch" && mkdir -p "$scratch"
source "$(dirname "$0")/expect.sh"
s=$scratch

# A sweep: 2 techniques x 3 orbit frames of a tiny frame, plus a map-size list for pcf only through a second sweep.
cat >"$s/sweep.json" <<'JSON'
{"scene": "builtin:box", "technique": ["sm", "pcf"], "size": "32x24", "map-size": 64, "png": "none",
 "frames": 3, "camera": {"orbit": {"target": [0, 0, 0], "radius": 6, "height": 3, "fov": 50}},
 "output": "{technique}/frame{frame:02}.exr"}
JSON
expect plan 0 "wrote 6 jobs to $s/jobs.jsonl" -- "$bin" plan "$s/sweep.json" -o "$s/jobs.jsonl"
expect plan-lines 0 '^6$' -- bash -c "wc -l <'$s/jobs.jsonl'"
expect plan-first 0 '^\{"id":"[0-9a-f]{16}","scene":"builtin:box","technique":"sm","size":"32x24","map-size":64,"png":"none","camera":"0,3,6:0,0,0:50","output":"sm/frame00.exr"\}$' \
  -- head -n 1 "$s/jobs.jsonl"
expect plan-orbit 0 '"camera":"5.19615242,3,-3:0,0,0:50","output":"pcf/frame01.exr"' -- sed -n 5p "$s/jobs.jsonl"
"$bin" plan "$s/sweep.json" -o "$s/again.jsonl" -q
expect plan-deterministic 0 '' -- cmp "$s/jobs.jsonl" "$s/again.jsonl"
expect plan-ids-unique 0 '^6$' -- bash -c "grep -o '\"id\":\"[0-9a-f]*\"' '$s/jobs.jsonl' | sort -u | wc -l"
# Keyframes: eye, target and fov linear between keys, held after the last; a per-frame time from fps.
cat >"$s/keys.json" <<'JSON'
{"scene": "builtin:box", "frames": {"start": 0, "end": 4}, "time": {"fps": 4, "start": 1},
 "camera": {"keyframes": [{"frame": 0, "eye": [0, 2, 8], "target": [0, 0, 0], "fov": 40},
                          {"frame": 2, "eye": [4, 2, 8], "target": [0, 1, 0], "fov": 60}]},
 "output": "k{frame}.exr"}
JSON
expect plan-keyframes 0 "wrote 5 jobs" -- "$bin" plan "$s/keys.json" -o "$s/keys.jsonl"
# The docs' own usage, run in the sweep's folder: `-o` with no folder part and a scene path relative to the sweep
# (fs::absolute("") failed: "cannot make absolute path: Invalid argument").
mkdir -p "$s/bare/sub"
printf '{"procedural": [{"name": "box"}]}' >"$s/bare/box.json"
printf '{"scene": "sub/../box.json", "size": "32x24", "output": "b.exr"}' >"$s/bare/sweep.json"
expect plan-bare-output 0 '"scene":"box.json"' -- bash -c "cd '$s/bare' && '$bin' plan sweep.json -o jobs.jsonl -q && cat jobs.jsonl"
expect plan-keyframe-mid 0 '"time":1.25,"camera":"2,2,8:0,0.5,0:50","output":"k1.exr"' -- sed -n 2p "$s/keys.jsonl"
expect plan-keyframe-held 0 '"time":2.0,"camera":"4,2,8:0,1,0:60","output":"k4.exr"' -- sed -n 5p "$s/keys.jsonl"
printf '{"scene": "builtin:box", "technique": ["sm", "nope"], "output": "{technique}.exr"}' >"$s/bad-sweep.json"
expect plan-bad-technique 1 "bad-sweep.json: job 1 \(nope.exr\): unknown technique 'nope'" -- \
  "$bin" plan "$s/bad-sweep.json" -o "$s/x.jsonl"
printf '{"scene": "builtin:box", "technique": ["sm", "pcf"], "output": "same.exr"}' >"$s/dup-sweep.json"
expect plan-duplicate-output 1 "job 1 \(same.exr\): the output of job 0 too" -- "$bin" plan "$s/dup-sweep.json" -o "$s/x.jsonl"
printf '{"scene": "builtin:box", "camera": {"orbit": {"radius": 2}}, "output": "a.exr"}' >"$s/path-sweep.json"
expect plan-path-needs-frames 1 '"camera": a per-frame camera needs "frames"' -- "$bin" plan "$s/path-sweep.json" -o "$s/x.jsonl"
printf '{"scene": "builtin:box", "frames": 2, "camera": {"orbit": {"radius": 2}}, "output": "{frame}.exr"}' >"$s/path-sweep.json"
expect plan-orbit-target 1 'camera orbit: "target" is not \[x, y, z\]' -- "$bin" plan "$s/path-sweep.json" -o "$s/x.jsonl"
printf '{"scene": "builtin:box", "output": "{nope}.exr"}' >"$s/template-sweep.json"
expect plan-bad-template 1 "\"output\": '\{nope\}.exr'" -- "$bin" plan "$s/template-sweep.json" -o "$s/x.jsonl"

# Shards from each scheduler's variables: every job exactly once over the shards (dry runs: nothing rendered).
all=$(for i in 1 2 3 4 5 6; do echo "$s/jobs.jsonl:$i"; done | paste -sd' ')
for variant in slurm k8s aws; do
  lines=$(for i in 0 1 2; do
    case $variant in
      slurm) env SLURM_ARRAY_TASK_ID=$i SLURM_ARRAY_TASK_COUNT=3 "$bin" run "$s/jobs.jsonl" --out "$s/dry" --shard auto --dry-run ;;
      k8s) env JOB_COMPLETION_INDEX=$i "$bin" run "$s/jobs.jsonl" --out "$s/dry" --shard auto --shard-count 3 --dry-run ;;
      aws) env AWS_BATCH_JOB_ARRAY_INDEX=$i "$bin" run "$s/jobs.jsonl" --out "$s/dry" --shard auto --shard-count 3 --dry-run ;;
    esac
  done | cut -d' ' -f1 | sort | paste -sd' ')
  expect "shards-cover-$variant" 0 "^$all$" -- echo "$lines"
done
expect shard-slurm-one-based 0 "^$s/jobs.jsonl:2 sm/frame01.exr" -- env SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_MIN=1 \
  SLURM_ARRAY_TASK_COUNT=5 "$bin" run "$s/jobs.jsonl" --out "$s/dry" --shard auto --dry-run
# A resubmission of chosen indices (`sbatch --array=1,3` of an array 0-3): with --shard-count the task id is the shard
# index (task 3 runs shard 3 of 4, not 1 of 2); without it, the rebased index past the count says what to add.
expect shard-slurm-chosen 0 "shard 3-of-4: 1 jobs" -- env SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_MIN=1 \
  SLURM_ARRAY_TASK_STEP=2 SLURM_ARRAY_TASK_COUNT=2 "$bin" run "$s/jobs.jsonl" --out "$s/chosen" --shard auto \
  --shard-count 4
expect shard-slurm-chosen-needs-count 2 "SLURM_ARRAY_TASK_ID 3 is shard 2 of this array's 2 tasks .*--shard-count N" -- \
  env SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=2 "$bin" run "$s/jobs.jsonl" \
  --out "$s/chosen" --shard auto
expect shard-mod 0 "^$s/jobs.jsonl:2 sm/frame01.exr.$s/jobs.jsonl:5 pcf/frame01.exr$" -- bash -c \
  "'$bin' run '$s/jobs.jsonl' --out '$s/dry' --shard 1/3 --dry-run | paste -sd' '"
expect shard-none 2 "no array index in the environment" -- env -u SLURM_ARRAY_TASK_ID "$bin" run "$s/jobs.jsonl" \
  --out "$s/dry" --shard auto
expect shard-k8s-count 2 "JOB_COMPLETION_INDEX needs --shard-count" -- env JOB_COMPLETION_INDEX=0 "$bin" run \
  "$s/jobs.jsonl" --out "$s/dry" --shard auto
expect shard-range 2 "index 3 is not in 0..2" -- "$bin" run "$s/jobs.jsonl" --out "$s/dry" --shard 3/3
expect shard-text 2 "--shard x: use I/N or auto" -- "$bin" run "$s/jobs.jsonl" --out "$s/dry" --shard x

# Three shards render everything; each output equals a single `render` of its line, bit for bit.
for i in 0 1 2; do
  expect "run-shard-$i" 0 "shard $i-of-3: 2 jobs: 2 rendered, 0 skipped, 0 failed" -- env SLURM_ARRAY_TASK_ID=$i \
    SLURM_ARRAY_TASK_COUNT=3 "$bin" run "$s/jobs.jsonl" --out "$s/out" --shard auto
done
expect status-done 0 "6 jobs: 6 done, 0 stale, 0 failed, 0 missing" -- "$bin" status "$s/jobs.jsonl" --out "$s/out"
expect status-json 0 '"done": 6' -- "$bin" status "$s/jobs.jsonl" --out "$s/out" --json
expect records 0 '^6$' -- bash -c "cat '$s'/out/penumbra-status/shard-*-of-3.jsonl | grep -c '\"state\":\"done\"'"
expect record-fields 0 '"exit":0.*"host":".+".*"seconds":' -- head -n 1 "$s/out/penumbra-status/shard-0-of-3.jsonl"
expect job-id-header 0 "penumbra:job-id" -- grep -ao "penumbra:job-id" "$s/out/sm/frame00.exr"
"$bin" render builtin:box -t pcf --size 32x24 --map-size 64 --camera 5.19615242,3,-3:0,0,0:50 --png none -q \
  -o "$s/single.exr"
expect equal-to-render 0 "visibility.Y: 768 pixels bit-identical" -- "$exr_equal" "$s/single.exr" "$s/out/pcf/frame01.exr"
# --exr-compression: lossless, so the same pixels whichever; the file says which; a job's id ignores it.
"$bin" render builtin:box -t pcf --size 32x24 --map-size 64 --camera 5.19615242,3,-3:0,0,0:50 --png none -q \
  --exr-compression none -o "$s/single-none.exr"
expect compression-same-pixels 0 "visibility.Y: 768 pixels bit-identical" -- "$exr_equal" "$s/single.exr" "$s/single-none.exr"
expect compression-none-larger 0 '^larger$' -- bash -c \
  "[ \$(stat -c %s '$s/single-none.exr') -gt \$(stat -c %s '$s/single.exr') ] && echo larger"
expect compression-bad 2 "--exr-compression: EXR compression 'dwaa': use none, rle, zips, zip or piz" -- \
  "$bin" render builtin:box --size 32x24 --exr-compression dwaa -o "$s/x.exr"
sed 's/"png":"none"/"png":"none","exr-compression":"none"/' "$s/jobs.jsonl" >"$s/none.jsonl"
expect compression-keeps-id 0 "6 jobs: 0 rendered, 6 skipped" -- "$bin" run "$s/none.jsonl" --out "$s/out"
expect rerun-skips 0 "6 jobs: 0 rendered, 6 skipped" -- "$bin" run "$s/jobs.jsonl" --out "$s/out"
expect run-progress 0 'shard 0-of-1: 6/6 jobs \(0 failed\), [0-9.]+ jobs/s, about 0 s left' -- "$bin" run "$s/jobs.jsonl" --out "$s/out"
expect run-quiet-no-progress 0 '^$' -- "$bin" run "$s/jobs.jsonl" --out "$s/out" -q
expect no-skip 0 "1 jobs: 1 rendered" -- "$bin" run "$s/jobs.jsonl" --out "$s/out" --shard 5/6 --no-skip-existing
sed 's/"map-size":64/"map-size":128/' "$s/jobs.jsonl" | sed 's/"id":"[0-9a-f]*",//' >"$s/changed.jsonl"
# Another manifest (a changed copy) writes over the outputs only with --force.
expect changed-job-renders 0 "6 jobs: 6 rendered, 0 skipped" -- "$bin" run "$s/changed.jsonl" --out "$s/out" --force
sed 's/"id":"[0-9a-f]\{4\}/"id":"0000/' "$s/jobs.jsonl" | head -n 1 >"$s/stale.jsonl"
# status checks the ids as the jobs are now, not as the manifest says: a stale line (exit 65, plan again), outputs
# that another job made (the changed map size above rendered over them: exit 75, run again).
printf '{"device":"torn","exit":0,"id":"ab' >>"$s/out/penumbra-status/shard-0-of-1.jsonl"  # a crash mid-append
expect stale-id 65 "stale.jsonl:1: id 0000.* in the manifest, .* for the job now: .*plan again" -- \
  "$bin" run "$s/stale.jsonl" --out "$s/out"
expect torn-record-stands-alone 0 '^stale.jsonl:1 65$' -- python3 -c \
  "import json,sys; r=json.loads(open(sys.argv[1]).read().splitlines()[-1]); print(r['where'].split('/')[-1], r['exit'])" \
  "$s/out/penumbra-status/shard-0-of-1.jsonl"
expect status-stale-line 65 "1 jobs: 0 done, 1 stale, 0 failed, 0 missing" -- "$bin" status "$s/stale.jsonl" --out "$s/out"
expect status-stale-line-says 65 "stale +.*stale.jsonl:1: id 0000.* plan again" -- "$bin" status "$s/stale.jsonl" --out "$s/out"
expect status-stale-outputs 75 "6 jobs: 0 done, 6 stale, 0 failed, 0 missing" -- "$bin" status "$s/jobs.jsonl" --out "$s/out"
expect status-stale-output-says 75 "stale +.*jobs.jsonl:1: sm/frame00.exr was made by job [0-9a-f]{16} of another manifest" -- \
  "$bin" status "$s/jobs.jsonl" --out "$s/out"

# Overlapping runs on one --out (the same manifest started three times at once): per-output claims let each job be
# rendered once, none fails, no run deletes another's temporaries.
for i in $(seq 0 11); do
  printf '{"scene": "builtin:box", "technique": "pcss", "size": "96x72", "map-size": 512, "png": "none", "camera": "%s,3,6:0,0,0:50", "output": "c%02d.exr"}\n' "$i" "$i"
done >"$s/overlap.jsonl"
"$bin" run "$s/overlap.jsonl" --out "$s/overlap" -q & p1=$!
"$bin" run "$s/overlap.jsonl" --out "$s/overlap" -q & p2=$!
"$bin" run "$s/overlap.jsonl" --out "$s/overlap" -q
wait $p1 $p2
expect overlap-rendered-once 0 '^12$' -- bash -c "cat '$s'/overlap/penumbra-status/*.jsonl | grep -c '\"state\":\"done\"'"
expect overlap-no-failure 1 '^0$' -- bash -c "cat '$s'/overlap/penumbra-status/*.jsonl | grep -c '\"state\":\"failed\"'"
expect overlap-status 0 "12 jobs: 12 done" -- "$bin" status "$s/overlap.jsonl" --out "$s/overlap"
expect overlap-claims-released 0 '^0$' -- bash -c "ls '$s/overlap/penumbra-status/claims' | wc -l"
# Another manifest's job is not written over its output without --force (the message names both jobs).
echo '{"scene": "builtin:box", "technique": "sm", "size": "32x24", "png": "none", "output": "c03.exr"}' >"$s/other.jsonl"
expect other-manifest-refused 65 "c03.exr was made by job [0-9a-f]{16} \(.*overlap.jsonl:4\); this is job [0-9a-f]{16} \(.*other.jsonl:1\): --force replaces it" \
  -- "$bin" run "$s/other.jsonl" --out "$s/overlap"
expect other-manifest-force 0 "1 rendered" -- "$bin" run "$s/other.jsonl" --out "$s/overlap" --force
expect other-manifest-status 75 "c03.exr was made by job [0-9a-f]{16} of another manifest \(.*other.jsonl:1\)" -- \
  "$bin" status "$s/overlap.jsonl" --out "$s/overlap"
# Claims: a dead process's on this host is taken over (its temporary removed); another host's holds within the lease
# (the job left to it) and is taken over past it.
claim() {  # claim OUTPUT: the claim file of an output (64-bit FNV-1a of its path)
  python3 -c "import sys; h=0xcbf29ce484222325
for c in sys.argv[1].encode(): h=((h^c)*0x100000001b3)&0xffffffffffffffff
print('$s/overlap/penumbra-status/claims/%016x.claim' % h)" "$1"
}
mkdir -p "$s/overlap/penumbra-status/claims"
echo "{\"host\": \"$(hostname)\", \"pid\": 999999999, \"start\": 1, \"job\": \"x:1\", \"time\": \"t\"}" >"$(claim c05.exr)"
rm "$s/overlap/c05.exr" && touch "$s/overlap/c05.exr.tmp-0123abcd"
expect claim-dead-owner 0 "2 rendered" -- "$bin" run "$s/overlap.jsonl" --out "$s/overlap" --force
expect claim-dead-temporary 1 '' -- bash -c "ls '$s/overlap' | grep tmp"
echo '{"host": "elsewhere", "pid": 1, "start": 1, "job": "y:1", "time": "t"}' >"$(claim c06.exr)"
rm "$s/overlap/c06.exr"
expect claim-other-host-holds 0 "0 rendered, 11 skipped, 0 failed, 1 claimed by other runs" -- \
  "$bin" run "$s/overlap.jsonl" --out "$s/overlap" --force
expect claim-other-host-named 0 "overlap.jsonl:7: claimed by elsewhere pid 1 since t \(its job y:1\)" -- \
  "$bin" run "$s/overlap.jsonl" --out "$s/overlap" --force
expect status-running 75 "12 jobs: 11 done, 0 stale, 0 failed, 0 missing, 1 running" -- \
  "$bin" status "$s/overlap.jsonl" --out "$s/overlap"
expect status-running-says 75 "running +.*overlap.jsonl:7: being rendered by elsewhere pid 1 since t" -- \
  "$bin" status "$s/overlap.jsonl" --out "$s/overlap"
touch -d '2 hours ago' "$(claim c06.exr)"
expect claim-lease-passed 0 "1 rendered" -- "$bin" run "$s/overlap.jsonl" --out "$s/overlap" --force --claim-lease 1h

# A frame's warnings name their job and stay in its record.
echo '{"scene": "builtin:box", "size": "32x24", "png": "none", "camera": "0,50,0:0,100,0:45", "output": "w.exr"}' \
  >"$s/warn.jsonl"
expect warning-names-job 0 'penumbra: warning: .*warn.jsonl:1: the frame sees no surface' -- \
  "$bin" run "$s/warn.jsonl" --out "$s/warn-out"
expect warning-in-record 0 '"warnings":\["the frame sees no surface' -- cat "$s/warn-out/penumbra-status/shard-0-of-1.jsonl"
expect status-csv 0 '^1,w.exr,[0-9a-f]{16},done,,[0-9.]+,[0-9.]+,.*,"the frame sees no surface' -- bash -c \
  "'$bin' status '$s/warn.jsonl' --out '$s/warn-out' --csv '$s/warn.csv' >/dev/null && tail -n 1 '$s/warn.csv'"

# --dry-run checks every job as run would before rendering (scene found and parsed, id current, size, camera,
# technique) and exits 65 naming each bad line; it used to list them all as runnable and exit 0.
cat >"$s/dry.jsonl" <<'JSONL'
{"scene": "builtin:box", "size": "32x24", "output": "ok.exr"}
{"scene": "missing.json", "size": "32x24", "output": "a.exr"}
{"scene": "builtin:box", "size": "99999x24", "output": "b.exr"}
{"scene": "builtin:box", "size": "32x24", "camera": "nan,0,0:0,0,0", "output": "c.exr"}
{"scene": "builtin:nope", "size": "32x24", "output": "e.exr"}
JSONL
expect dry-run-validates 65 'dry.jsonl:1 ok.exr' -- "$bin" run "$s/dry.jsonl" --out "$s/dry-out" --dry-run
expect dry-run-names-each 65 '4 of 5 jobs would fail' -- "$bin" run "$s/dry.jsonl" --out "$s/dry-out" --dry-run
expect dry-run-size 65 'dry.jsonl:3 refused: size "99999x24": width 99999 is outside 1..8192' -- \
  "$bin" run "$s/dry.jsonl" --out "$s/dry-out" --dry-run
expect dry-run-scene 65 'dry.jsonl:2 refused: .*missing.json: file not found' -- \
  "$bin" run "$s/dry.jsonl" --out "$s/dry-out" --dry-run
expect dry-run-stale 65 'stale.jsonl:1 refused: id 0000.* plan again' -- "$bin" run "$s/stale.jsonl" --out "$s/dry-out" --dry-run

# Malformed manifests and lines: each bad line fails alone, named by its line; the good ones render.
expect manifest-missing 66 "nope.jsonl: cannot read the manifest" -- "$bin" run "$s/nope.jsonl" --out "$s/bad"
: >"$s/empty.jsonl"
expect manifest-empty 66 "empty.jsonl: the manifest holds no job" -- "$bin" run "$s/empty.jsonl" --out "$s/bad"
cat >"$s/bad.jsonl" <<'JSONL'
{"scene": "builtin:box", "technique": "sm", "size": "32x24", "map-size": 64, "png": "none", "output": "good.exr"}
{"scene": "builtin:box", "output": "x.exr"

{"scene": "builtin:box", "frobnicate": 3, "output": "x.exr"}
{"scene": "builtin:box", "technique": "nope", "output": "x.exr"}
{"scene": "builtin:box", "output": "../escape.exr"}
{"scene": "builtin:box", "output": "preview.png"}
{"scene": "builtin:box", "technique": "sm", "size": "32x24", "png": "none", "output": "./good.exr"}
{"scene": "builtin:box", "size": "big", "output": "size.exr"}
["not", "an", "object"]
{"scene": "builtin:box", "device": "gpu", "output": "d.exr"}
{"scene": "builtin:box", "map-size": true, "output": "t.exr"}
{"technique": "sm", "output": "s.exr"}
{"scene": "missing.gltf", "technique": "sm", "size": "32x24", "png": "none", "output": "missing.exr"}
{"scene": "builtin:box", "technique": "sm", "size": "32x24", "png": "good.exr", "output": "other.exr"}
{"scene": "builtin:box", "technique": "sm", "size": "32x24", "technique": "pcss", "output": "twice.exr"}
JSONL
out=$("$bin" run "$s/bad.jsonl" --out "$s/bad" 2>&1)
rc=$?
expect bad-exit 0 '^65$' -- echo "$rc"
expect bad-summary 0 "15 jobs: 1 rendered, 0 skipped, 14 failed" -- echo "$out"
expect bad-json 0 "bad.jsonl:2: not JSON: .*syntax error" -- echo "$out"
expect bad-option 0 "bad.jsonl:4: \"frobnicate\" is not an option of penumbra render" -- echo "$out"
expect bad-technique 0 "bad.jsonl:5: unknown technique 'nope'" -- echo "$out"
expect bad-escape 0 "bad.jsonl:6: \"output\": '../escape.exr' is not a relative path inside --out" -- echo "$out"
expect bad-png 0 "bad.jsonl:7: \"output\": 'preview.png' is not an .exr file" -- echo "$out"
expect bad-duplicate 0 "bad.jsonl:8: output good.exr is line 1's too" -- echo "$out"
expect bad-size 0 "bad.jsonl:9: .*size" -- echo "$out"
expect bad-array 0 "bad.jsonl:10: not a JSON object" -- echo "$out"
expect bad-device 0 "bad.jsonl:11: \"device\" is an option of penumbra run, not of a job" -- echo "$out"
expect bad-bool 0 "bad.jsonl:12: \"map-size\": true is not a string or a number" -- echo "$out"
expect bad-no-scene 0 "bad.jsonl:13: no \"scene\"" -- echo "$out"
expect bad-missing-scene 0 "bad.jsonl:14: .*missing.gltf" -- echo "$out"
# A preview named like another job's EXR would turn that EXR into a PNG: refused when the manifest is read.
expect bad-duplicate-key 0 'bad.jsonl:16: duplicate key "technique"' -- echo "$out"
expect bad-preview-over-output 0 "bad.jsonl:15: preview .*/bad/good.exr is line 1's output good.exr" -- echo "$out"
expect status-failed 65 "15 jobs: 1 done, 0 stale, 14 failed, 0 missing" -- "$bin" status "$s/bad.jsonl" --out "$s/bad"
expect max-failures 65 "2 failed, [0-9]+ left \(--max-failures 2\)" -- "$bin" run "$s/bad.jsonl" --out "$s/bad2" --max-failures 2
# --only-failed: the missing scene appears (a copy of a glTF with a camera), only its job runs again.
cp "$(dirname "$0")/data/scenes/triangle.bin" "$s/triangle.bin"
printf '{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
 "buffers": [{"uri": "triangle.bin", "byteLength": 80}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 72, "byteStride": 12}, {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
  {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"},
  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]}' >"$s/missing.gltf"
expect only-failed 65 "14 jobs: 1 rendered, 0 skipped, 13 failed" -- "$bin" run "$s/bad.jsonl" --out "$s/bad" --only-failed
expect only-failed-done 0 "wrote|" -- "$exr_equal" "$s/bad/missing.exr" "$s/bad/missing.exr"
expect status-missing 75 "6 jobs: 0 done, 0 stale, 0 failed, 6 missing" -- "$bin" status "$s/jobs.jsonl" --out "$s/empty-out"

# SIGTERM mid-run: the current job finishes, nothing partial is left under a final name, exit 75; a rerun completes.
for i in $(seq 0 23); do
  printf '{"scene": "builtin:box", "technique": "pcss", "size": "96x64", "map-size": 256, "camera": "%s,3,6:0,0,0:50", "output": "seq/%02d.exr"}\n' "$i" "$i"
done >"$s/long.jsonl"
"$bin" run "$s/long.jsonl" --out "$s/term" >"$s/term.log" 2>&1 &
pid=$!
for _ in $(seq 1 600); do [ -e "$s/term/seq/01.exr" ] && break; sleep 0.05; done
kill -TERM "$pid"
wait "$pid"
expect sigterm-exit 0 '^75$' -- echo $?
expect sigterm-summary 0 "rendered, 0 skipped, 0 failed, [0-9]+ left \(SIGTERM\)" -- cat "$s/term.log"
expect sigterm-no-temp 0 '^0$' -- bash -c "find '$s/term' -name '*.tmp-*' | wc -l"
expect sigterm-outputs-whole 0 '' -- bash -c "for f in '$s'/term/seq/*.exr; do grep -aq penumbra:job-id \"\$f\" || exit 1; \
  '$exr_equal' \"\$f\" \"\$f\" visibility.Y >/dev/null || exit 1; done"
expect sigterm-status 75 "24 jobs: [0-9]+ done, 0 stale, 0 failed, [0-9]+ missing" -- "$bin" status "$s/long.jsonl" --out "$s/term"
: >"$s/term/seq/23.exr.tmp-0123456789abcdef"  # what a SIGKILL while writing leaves; a stranger's file stays
: >"$s/term/seq/notes.tmp-1"
expect sigterm-rerun 0 "24 jobs: [0-9]+ rendered, [1-9][0-9]* skipped, 0 failed" -- "$bin" run "$s/long.jsonl" --out "$s/term"
expect stale-temporary-removed 0 '^notes.tmp-1$' -- bash -c "cd '$s/term/seq' && ls | grep tmp"
expect sigterm-complete 0 "24 jobs: 24 done" -- "$bin" status "$s/long.jsonl" --out "$s/term"
expect time-limit 75 "left \(--time-limit 0.01s\)" -- "$bin" run "$s/long.jsonl" --out "$s/limit" --time-limit 0.01s
expect time-limit-bad 2 "--time-limit soon: use 90s, 15m, 2h or H:MM:SS" -- "$bin" run "$s/long.jsonl" --out "$s/limit" \
  --time-limit soon

# Temporal stability: bench over a camera path reports shimmer per technique; a still path has none; chart.py charts it.
orbit='{"orbit": {"target": [0, 0, 0], "radius": 6, "height": 3, "fov": 50, "degrees": [0, 6]}}'
expect shimmer-bench 0 "wrote $s/seq.csv" -- "$bin" bench builtin:box --techniques sm,pcf --camera-path "$orbit" \
  --frames 3 --size 48x32 --map-size 64 --warmup 0 -o "$s/seq.csv"
expect shimmer-columns 0 '^scene,technique,setting,parameters,light,width,height,frames,device,ms,mae,shimmer,' -- \
  head -n 1 "$s/seq.csv"
expect shimmer-rows 0 '^2$' -- bash -c "grep -c '^builtin:box,\(sm\|pcf\),default,' '$s/seq.csv'"
still='{"orbit": {"target": [0, 0, 0], "radius": 6, "height": 3, "fov": 50, "degrees": [0, 0]}}'
"$bin" bench builtin:box --techniques pcf --camera-path "$still" --frames 2 --size 48x32 --map-size 64 --warmup 0 -q \
  -o "$s/still.csv"
expect shimmer-still 0 ',0,0,0,[1-9][0-9]*$' -- tail -n 1 "$s/still.csv"
expect shimmer-needs-frames 2 "--camera-path requires --frames" -- "$bin" bench builtin:box --camera-path "$orbit" -o "$s/x.csv"
expect shimmer-bad-path 2 "camera: a path is" -- "$bin" bench builtin:box --camera-path '{"spin": 1}' --frames 2 -o "$s/x.csv"
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  expect shimmer-chart 0 "wrote .*box-shimmer.png" -- /usr/bin/python3 "$(dirname "$0")/../tools/chart.py" "$s/charts" "$s/seq.csv"
else
  echo "shimmer-chart skipped: no matplotlib"
fi

# A full disk (an output written through a link to /dev/full): that job fails with exit 75 in its record, the shard
# stops at once with exit 75 instead of failing every job after it, and a run with space completes it.
mkdir -p "$s/full/out"
for i in 0 1 2 3 4; do
  echo "{\"scene\": \"builtin:box\", \"size\": \"32x24\", \"map-size\": 64, \"png\": \"none\", \"output\": \"j$i.exr\", \"light\": \"spot:0,5,$i:0,0,0:60\"}"
done >"$s/full/jobs.jsonl"
ln -s /dev/full "$s/full/out/j1.exr"
expect full-disk-stops 75 'jobs: 2 rendered, 0 skipped, 1 failed, 2 left \(the storage refused a write: .*j1.exr: .*No space left on device' \
  -- "$bin" run "$s/full/jobs.jsonl" --out "$s/full/out"
expect full-disk-record 0 '"exit":75' -- grep -h '"state":"failed"' "$s/full/out/penumbra-status/shard-0-of-1.jsonl"
rm "$s/full/out/j1.exr"
expect full-disk-rerun 0 'jobs: 3 rendered, 2 skipped, 0 failed' -- "$bin" run "$s/full/jobs.jsonl" --out "$s/full/out"
# The status log on a full disk: exit 75 (it used to be 1, a code the docs did not list), naming the log.
mkdir -p "$s/full/log/penumbra-status" && ln -s /dev/full "$s/full/log/penumbra-status/shard-0-of-1.jsonl"
expect full-disk-status-log 75 'shard-0-of-1.jsonl: cannot append status records: No space left on device' \
  -- "$bin" run "$s/full/jobs.jsonl" --out "$s/full/log"

finish
