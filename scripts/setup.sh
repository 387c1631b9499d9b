#!/usr/bin/env bash
# Shared by demo.sh and test.sh: installs the Debian packages penumbra needs (only the missing ones; uses
# sudo when not root), then configures (Ninja when installed, in a new build folder) and builds penumbra (Release)
# into ./build: every target, or only those named in BUILD_TARGETS (demo.sh: the penumbra tool).
# Environment: BUILD_DIR (default build), BUILD_TYPE (default Release), JOBS (default nproc), BUILD_TARGETS.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  cmake g++ make ninja-build pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libopenexr-dev libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libcli11-dev libfmt-dev
  libpng-dev  # PNG previews, written row by row
  libgtest-dev libbenchmark-dev libboost-dev  # Boost.Compute: the scan baseline of stages_bench
  libembree-dev  # Embree 3: the ray-traced reference of `penumbra reference` (tools/reference/ only)
  libopengl-dev libgl-dev libegl-dev libgl1-mesa-dri libegl-mesa0  # raster_bench's OpenGL peer: glvnd, llvmpipe
  assimp-testmodels  # malformed glTF files the test suite feeds the loader
  oclgrind  # a second OpenCL implementation that checks every access: the oclgrind tests (tests/oclgrind_test.sh)
  python3-matplotlib  # tools/chart.py: the speed-vs-error charts (scripts/charts.sh)
  pybind11-dev python3-dev python3-numpy  # the Python module (python/, PENUMBRA_BUILD_PYTHON)
  python3-pyopencl  # the Python module's pyopencl interop, tested by api-python (the module itself never imports it)
  doxygen  # the API reference of include/penumbra/ (target penumbra_api_docs, test api-docs)
  slurm-wlm munge  # the slurm test: a real Slurm (slurmctld, slurmd) and munge started on this host
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
done
if ((${#missing[@]})); then
  echo "==> installing Debian packages: ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

BUILD_DIR=${BUILD_DIR:-build}
BUILD_TYPE=${BUILD_TYPE:-Release}
JOBS=${JOBS:-$(nproc)}
GENERATOR=()
# A build folder keeps the generator it was made with; a new one gets Ninja when it is there.
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ] && command -v ninja >/dev/null; then GENERATOR=(-G Ninja); fi
echo "==> configuring ($BUILD_TYPE) in $BUILD_DIR"
cmake -S . -B "$BUILD_DIR" "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE="$BUILD_TYPE" "$@" >/dev/null
TARGETS=()
for target in ${BUILD_TARGETS:-}; do TARGETS+=(--target "$target"); done
echo "==> building ${BUILD_TARGETS:-everything} with $JOBS jobs"
cmake --build "$BUILD_DIR" -j "$JOBS" "${TARGETS[@]}"
