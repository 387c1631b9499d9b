#!/usr/bin/env bash
# Every technique and the small kernel tests on Oclgrind, a simulated OpenCL device that checks each access: data
# races, API misuse and uninitialised values on, any report fails. Oclgrind reports every device type at once (so
# Auto would take the CPU layouts) and 32 KiB of local memory: the GPU layouts are forced (PENUMBRA_LAYOUTS=gpu;
# NVIDIA's and the CPU ones in `layouts`), and the local-memory plans meet a small device (16 KiB as well).
# Defects of Oclgrind 21.10 worked around: docs/portability.md.
# Usage: oclgrind_test.sh SUITE PENUMBRA PENUMBRA_TESTS OCLGRIND_ICD_LIBRARY SCRATCH_DIR
#   SUITE: techniques-1 | techniques-2 (every other technique each) | layouts | kernels | selftest
set -u
suite=$1 bin=$2 tests=$3 icd=$4 scratch=$5
rm -rf "$scratch" && mkdir -p "$scratch/vendors"
echo "$icd" >"$scratch/vendors/oclgrind.icd"
export OCL_ICD_VENDORS="$scratch/vendors" PENUMBRA_DEVICE=oclgrind PENUMBRA_LAYOUTS=gpu
# Oclgrind's LLVM rejects the llvm.experimental.noalias.scope.decl intrinsic its own optimiser emits.
export OCLGRIND_BUILD_OPTIONS=-cl-opt-disable
export OCLGRIND_CHECK_API=1 OCLGRIND_DATA_RACES=1 OCLGRIND_UNINITIALIZED=1 OCLGRIND_MAX_ERRORS=5
# One simulator thread per entry: ctest runs the entries side by side (-j), one per core.
export OCLGRIND_NUM_THREADS=1
# What Oclgrind prints for a report (plugins' headers, the per-report Kernel:/Entity: lines, the API checker).
reports='Oclgrind - |Oclgrind: |^[[:space:]]+(Kernel|Entity): |[Dd]ata race|Invalid (read|write)|Uninitiali[sz]ed'
passed=0
failed=0

# check NAME COMMAND...: runs COMMAND; fails on a non-zero exit or any Oclgrind report on stderr.
check() {
  local name=$1 log="$scratch/$1.log" start=$SECONDS rc
  shift
  "$@" >"$log.out" 2>"$log"
  rc=$?
  if [ "$rc" -eq 0 ] && ! grep -qE -- "$reports" "$log"; then
    passed=$((passed + 1))
    echo "ok   $name ($((SECONDS - start)) s)"
  else
    failed=$((failed + 1))
    echo "FAIL $name: exit $rc ($((SECONDS - start)) s), stderr:"
    head -n 40 "$log" | sed 's/^/    /'
    tail -n 20 "$log.out" | sed 's/^/    out: /'
  fi
}

render() {  # render NAME [ENV=VALUE...] -- ARGS...: a 48x32 frame of the box scene on a 64^2 map
  local name=$1 envs=()
  shift
  while [ "$1" != "--" ]; do envs+=("$1") && shift; done
  shift
  check "$name" env "${envs[@]}" "$bin" render builtin:box --size 48x32 --map-size 64 -q -o "$scratch/$name.exr" "$@"
}

techniques=$("$bin" render --help | grep -oE 'Shadow technique: [a-z0-9, ]+' | sed 's/.*: //; s/,/ /g')
case "$suite" in
  techniques-1 | techniques-2)
    i=0
    for t in $techniques; do
      if [ $((i % 2 + 1)) -eq "${suite#techniques-}" ]; then render "$t" -- -t "$t"; fi
      i=$((i + 1))
    done
    ;;
  layouts)
    # NVIDIA's raster row (128-item groups); the CPU layouts (blur runs, SAT lines, one-item pyramid groups, as
    # Oclgrind's device type picks them); the GPU paths at 32 KiB (Oclgrind's) and 16 KiB of local memory: the
    # issue's failures there (blur radius 17 of EVSM4 and MSM, box radius 31 and 32).
    for t in sm evsm4 savsm vssm; do render "nvidia-$t" PENUMBRA_LAYOUTS=nvidia -- -t "$t"; done
    for t in evsm4 savsm psvsm lvsm; do render "cpu-$t" PENUMBRA_LAYOUTS= -- -t "$t"; done
    # esm's log-space filters (exponents outside [1, 80]): its blur, mips and lookups, in fp32 and half.
    render "esm-log-space" -- -t esm --esm-exponent 400 --blur-radius 2 --moment-filtering trilinear
    render "esm-log-space-half" -- -t esm --esm-exponent 0.5 --blur-radius 2 --moment-storage fp16
    # izb's conservative draw in the CPU coarse layout, its sub-pixel samples and its passes (chunks) over the cells.
    render "cpu-izb-samples-chunks" PENUMBRA_LAYOUTS= -- -t izb --izb-samples 8 --izb-chunk 4096 \
      --light spot:-2,5,-1:0,0,0:60
    # vssm's moments and SAT over 3 x 3 blocks, which do not tile the 64^2 map (the last blocks reach past it).
    render "vssm-sat-reduce3" -- -t vssm --vssm-sat-reduce 3
    # izb under the box's disk light: caster lists, bitmask lookups and exact rays, over two passes.
    render "izb-soft" -- -t izb --izb-light-samples 16 --izb-chunk 1024
    for kib in 32 16; do
      local_env=OCLGRIND_LOCAL_MEM_SIZE=$((kib * 1024))
      render "local${kib}k-evsm4-r17" "$local_env" -- -t evsm4 --blur-radius 17
      render "local${kib}k-msm-r17" "$local_env" -- -t msm --blur-radius 17
      render "local${kib}k-msm-box31" "$local_env" -- -t msm --blur-filter box --blur-radius 31
      render "local${kib}k-evsm4-box32" "$local_env" -- -t evsm4 --blur-filter box --blur-radius 32
    done
    ;;
  selftest)
    # `penumbra selftest --quick` with every access checked: a case or two of every stage, the rasterizer and VSSM's
    # kernel against the references (about 3 min; its techniques, minutes each here, are what techniques-1/-2 render).
    check selftest "$bin" selftest --quick --filter moments/,blur/,sat/,pyramid/,reduce/,raster/,vssm/ \
      --json "$scratch/selftest.json"
    ;;
  kernels)
    check kernels "$tests" --gtest_brief=1 "--gtest_filter=${PENUMBRA_OCLGRIND_FILTER:?}"
    ;;
  *)
    echo "unknown suite '$suite'" && exit 2
    ;;
esac
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
