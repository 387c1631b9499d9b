#!/usr/bin/env bash
# Runs penumbra on the lent NVIDIA machine from a packed build (docs/gpu.md). Here:
#   ../shared/gpu/pack.sh .gpu build/tools/raster_bench build/tools/stages_bench build/tools/vssm_bench   (bench)
#   ../shared/gpu/pack.sh .gpu build/tools/penumbra                                       (the selftest alone, ~9 MB)
#   ../shared/gpu/pack.sh .gpu build/tests/penumbra_tests build/tools/penumbra \
#     /usr/lib/x86_64-linux-gnu/libembree3.so.3                                                               (tests)
# then, there: scripts/gpu-check.sh OUTDIR [tests|bench|all] (default all). Registers NVIDIA's OpenCL driver for
# this command only and selects it (PENUMBRA_DEVICE=NVIDIA); `tests` lists the devices and runs the kernel and
# technique tests on the GPU (after `penumbra selftest --full` when the CLI was packed), `bench` the Google Benchmark
# targets (JSON + console tables under OUTDIR) and, when the CLI was packed, `penumbra bench` of every technique at
# 1920x1080. Each step has its own time limit, so one slow step cannot eat a session's device time. (penumbra_tests
# and penumbra load Embree, ~42 MB, only to trace references: penumbra alone packs into ~9 MB.)
set -uo pipefail
out=${1:-out/gpu}
what=${2:-all}
mkdir -p "$out" /tmp/vendors
echo /usr/lib/libnvidia-opencl.so.1 >/tmp/vendors/nvidia.icd
export OCL_ICD_VENDORS=/tmp/vendors LD_LIBRARY_PATH=.gpu/lib PENUMBRA_DEVICE=NVIDIA
bin=.gpu/bin
# Embree, where it was packed beside the tests (docs/gpu.md): the reference tracer loads it at run time.
if [[ -f $bin/libembree3.so.3 ]]; then export PENUMBRA_EMBREE_LIBRARY=$PWD/$bin/libembree3.so.3; fi

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
  # The installed tool's own checks first (docs/portability.md): every stage, the rasterizer and every technique
  # against the references, with the device report (driver, layouts chosen) in selftest.json.
  [[ -x $bin/penumbra ]] && run 120 selftest "$bin/penumbra" selftest --full --json "$out/selftest.json"
  [[ -x $bin/penumbra_tests ]] && run 240 tests "$bin/penumbra_tests" --gtest_brief=1 \
    "--gtest_filter=Runtime*:*Techniques*:LightFit*:Raster*:Sat*:Blur*:Pyramid*:Reduce*:Moments*:*Vssm*:*Lvsm*:*Pssm*:Params*"
fi

if [[ $what == bench || $what == all ]]; then
  flags=(--benchmark_counters_tabular=true --benchmark_min_time=0.2)
  limits=(stages_bench 150 raster_bench 150 vssm_bench 120)
  for ((i = 0; i < ${#limits[@]}; i += 2)); do
    name=${limits[i]}
    [[ -x $bin/$name ]] && run "${limits[i + 1]}" "$name" "$bin/$name" "${flags[@]}" --benchmark_out="$out/$name.json"
  done
  if [[ -x $bin/penumbra ]]; then
    run 180 penumbra_bench "$bin/penumbra" bench scenes/default.json --techniques all --size 1920x1080 \
      --runs 5 --no-reference -o "$out/penumbra_bench.csv" --json "$out/penumbra_bench.json"
  fi
fi
exit 0
