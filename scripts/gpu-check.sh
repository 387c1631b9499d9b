#!/usr/bin/env bash
# Runs penumbra on the lent NVIDIA machine from a packed build (README, "Running on an NVIDIA GPU"). Here:
#   ../shared/gpu/pack.sh .gpu build/tests/penumbra_tests build/tools/raster_bench build/tools/stages_bench \
#       build/tools/vssm_bench [build/tools/penumbra]
# then, there: scripts/gpu-check.sh OUTDIR [tests|bench|all] (default all). Registers NVIDIA's OpenCL driver for
# this command only and selects it (PENUMBRA_DEVICE=NVIDIA); `tests` lists the devices and runs the kernel and
# technique tests on the GPU, `bench` the Google Benchmark targets (JSON + console tables under OUTDIR) and, when
# the CLI was packed, `penumbra bench` of every technique at 1920x1080. Each step has its own time limit, so one
# slow step cannot eat a session's device time. (penumbra links Embree, ~44 MB: pack it only when it fits.)
set -uo pipefail
out=${1:-out/gpu}
what=${2:-all}
mkdir -p "$out" /tmp/vendors
echo /usr/lib/libnvidia-opencl.so.1 >/tmp/vendors/nvidia.icd
export OCL_ICD_VENDORS=/tmp/vendors LD_LIBRARY_PATH=.gpu/lib PENUMBRA_DEVICE=NVIDIA
bin=.gpu/bin

run() {  # run SECONDS NAME COMMAND...: stdout+stderr into OUTDIR/NAME.txt, the tail on the console
  local limit=$1 name=$2
  shift 2
  echo "== $name"
  timeout "$limit" "$@" >"$out/$name.txt" 2>&1
  echo "   exit $? ($name)"
  tail -n 25 "$out/$name.txt"
}

if [[ $what == tests || $what == all ]]; then
  [[ -x $bin/penumbra ]] && run 30 devices "$bin/penumbra" devices
  run 240 tests "$bin/penumbra_tests" --gtest_brief=1 \
    "--gtest_filter=Runtime*:*Techniques*:LightFit*:Raster*:Sat*:Blur*:Pyramid*:Reduce*:Moments*:*Vssm*:*Lvsm*:*Pssm*:Params*"
fi

if [[ $what == bench || $what == all ]]; then
  flags=(--benchmark_counters_tabular=true --benchmark_min_time=0.2)
  run 150 stages_bench "$bin/stages_bench" "${flags[@]}" --benchmark_out="$out/stages_bench.json"
  run 150 raster_bench "$bin/raster_bench" "${flags[@]}" --benchmark_out="$out/raster_bench.json"
  run 120 vssm_bench "$bin/vssm_bench" "${flags[@]}" --benchmark_out="$out/vssm_bench.json"
  if [[ -x $bin/penumbra ]]; then
    run 180 penumbra_bench "$bin/penumbra" bench scenes/default.json --techniques all --size 1920x1080 \
      --runs 5 --no-reference -o "$out/penumbra_bench.csv" --json "$out/penumbra_bench.json"
  fi
fi
