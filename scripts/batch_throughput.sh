#!/usr/bin/env bash
# Throughput of `penumbra run` against `bench`'s steady frame on the same jobs (docs/batch.md#throughput): a manifest
# of FRAMES frames of a short orbit, rendered by one `run`, against `bench` over the same camera path (its median
# frame; --spp 4: its references are traced but not what is compared); ROUNDS rounds, each bench then run back to back
# so that the machine's load reaches both alike. run's time per job is its steady state: the
# span between the first and the last job's status records over FRAMES - 1 (the first job pays the context and the
# kernels' build). Environment: PENUMBRA (default build/tools/penumbra), SCENE, TECHNIQUE, SIZE, FRAMES, ROUNDS, PNG
# (none, or beside: the preview written too), EXR_COMPRESSION (zip, the default, or none, rle, zips, piz), OUT
# (scratch folder).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${PENUMBRA:-build/tools/penumbra}
scene=${SCENE:-$PWD/scenes/default.json}
technique=${TECHNIQUE:-pcss}
size=${SIZE:-640x360}
frames=${FRAMES:-12}
rounds=${ROUNDS:-2}
out=${OUT:-out/batch-throughput}
png=${PNG:-none}
compression=${EXR_COMPRESSION:-zip}
rm -rf "$out" && mkdir -p "$out"
png_member=$([ "$png" = none ] && echo '"png": "none", ' || echo '')
orbit='{"orbit": {"target": [0, 0.5, 0], "radius": 7, "height": 3, "fov": 45, "degrees": [0, 10]}}'
cat >"$out/sweep.json" <<JSON
{"scene": "$scene", "technique": "$technique", "size": "$size", $png_member"exr-compression": "$compression",
 "frames": $frames, "camera": $orbit, "output": "f{frame:03}.exr"}
JSON
"$bin" plan "$out/sweep.json" -o "$out/jobs.jsonl" -q
echo "device: $("$bin" devices | head -n 1)"
for round in $(seq 1 "$rounds"); do
  load=$(cut -d' ' -f1 /proc/loadavg)
  "$bin" bench "$scene" --techniques "$technique" --size "$size" --camera-path "$orbit" --frames "$frames" --warmup 1 \
    --spp 4 -q -o "$out/bench-$round.csv"
  bench_ms=$(/usr/bin/python3 -c "import csv,sys; print(next(csv.DictReader(open(sys.argv[1])))['ms'])" \
    "$out/bench-$round.csv")
  rm -rf "$out/run-$round"
  "$bin" run "$out/jobs.jsonl" --out "$out/run-$round" -q
  /usr/bin/python3 - "$out/run-$round/penumbra-status/shard-0-of-1.jsonl" "$bench_ms" "$round" "$load" \
    "$compression" <<'PY'
import datetime, json, sys
records = [json.loads(line) for line in open(sys.argv[1])]
stamp = lambda r: datetime.datetime.fromisoformat(r["time"].rstrip("Z"))
span = (stamp(records[-1]) - stamp(records[0])).total_seconds()
per_job = span / (len(records) - 1) * 1000
bench = float(sys.argv[2])
device = sorted(r["device_ms"] for r in records[1:])
device = device[len(device) // 2]
print(f"round {sys.argv[3]} (load {sys.argv[4]}, EXR {sys.argv[5]}): bench median frame over the path "
      f"{bench:.1f} ms (device); run: "
      f"{device:.1f} ms device per job (median) {100 * (device / bench - 1):+.1f} %, "
      f"{per_job:.1f} ms wall per job with the EXR written {100 * (per_job / bench - 1):+.1f} %")
PY
done
