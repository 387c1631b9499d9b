#!/usr/bin/env bash
# Runs penumbra on the lent NVIDIA machine from a packed build (see README, "Running on an NVIDIA GPU"):
#   ../shared/gpu/pack.sh .gpu build/tools/penumbra build/tests/penumbra_tests
# then, there: scripts/gpu-check.sh OUTDIR. Registers NVIDIA's OpenCL driver for this command only, lists the
# devices, runs the kernel tests on the GPU and renders the default scene with each technique.
set -uo pipefail
out=${1:-out/gpu}
mkdir -p "$out" /tmp/vendors
echo /usr/lib/libnvidia-opencl.so.1 >/tmp/vendors/nvidia.icd
export OCL_ICD_VENDORS=/tmp/vendors LD_LIBRARY_PATH=.gpu/lib PENUMBRA_DEVICE=NVIDIA
.gpu/bin/penumbra devices | tee "$out/devices.txt"
.gpu/bin/penumbra devices --json >"$out/devices.json"
.gpu/bin/penumbra_tests --gtest_brief=1 \
  "--gtest_filter=Runtime*:*Techniques*:Raster*:Sat*:Blur*:Pyramid*:Reduce*:Moments*:Params*" 2>&1 |
  tee "$out/tests.txt" | tail -n 40
for technique in sm pcf pcss; do
  for run in 1 2 3; do  # the first run builds the kernels; report the last
    .gpu/bin/penumbra render scenes/default.json -t "$technique" -o "$out/default-$technique.exr" >"$out/render-$technique.txt"
  done
  cat "$out/render-$technique.txt"
done
rm -f "$out"/*.exr
