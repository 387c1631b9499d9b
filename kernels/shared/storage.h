// Storage of the images a kernel reads or writes, fp32 or IEEE half (binary16). Built with -DSTORE_HALF, its
// stored images are `half` buffers read with vload_half* and written with vstore_half*_rte (round to nearest
// even). Both are core OpenCL C 1.2 and need no cl_khr_fp16: there `half` is a pointer-only type, and all
// arithmetic stays fp32. Without STORE_HALF the same code reads and writes float vectors directly (the fp32
// kernels are unchanged). Two ways in: PN_STORED(n) pointers indexed by texel (PN_LOAD, PN_STORE), for kernels
// built per channel count; PN_SCALAR pointers with vector loads (PN_VLOAD), for a channel count known at run time.
// Macros, not typedefs, name the stored types, so that `half` only ever appears as a pointee, the one use
// OpenCL C 1.2 allows it without cl_khr_fp16 (sec. 6.1.1.1).
// PN_ROUND(n, v) is v as it will read back once stored (a stage that keeps a stored level in local memory for the
// next one uses it, so that it computes from what a separate pass would read).
#ifndef PENUMBRA_KERNELS_SHARED_STORAGE_H
#define PENUMBRA_KERNELS_SHARED_STORAGE_H

#include "kernels/shared/common.h"

#define PN_VLOAD_HALF_1 vload_half
#define PN_VLOAD_HALF_2 vload_half2
#define PN_VLOAD_HALF_4 vload_half4
#define PN_VSTORE_HALF_1 vstore_half_rte
#define PN_VSTORE_HALF_2 vstore_half2_rte
#define PN_VSTORE_HALF_4 vstore_half4_rte
#define PN_VLOAD_FLOAT_1(i, p) ((p)[i])
#define PN_VLOAD_FLOAT_2 vload2
#define PN_VLOAD_FLOAT_4 vload4

#ifdef STORE_HALF
#define PN_SCALAR half
#define PN_STORED(n) half
#define PN_STRIDE(n) (n)  // PN_STORED(n) elements per texel
#define PN_LOAD(n, p, i) PN_CAT(PN_VLOAD_HALF_, n)((i), (p))
#define PN_STORE(n, p, i, v) PN_CAT(PN_VSTORE_HALF_, n)((v), (i), (p))
#define PN_VLOAD(n, i, p) PN_CAT(PN_VLOAD_HALF_, n)((i), (p))
// Rounding to half in fp32 arithmetic, as vstore_half*_rte does: normal halves keep 10 of fp32's 23 fraction
// bits (add half the dropped range, plus the kept lowest bit for ties to even, then truncate; a carry moves the
// exponent), subnormal halves (below 2^-14) are multiples of 2^-24, beyond 65504 is infinity, NaN stays NaN.
#define PN_ROUND_DEFINE(n)                                                                                      \
  inline PN_VEC(float, n) PN_CAT(pn_round_half, n)(PN_VEC(float, n) v) {                                        \
    const PN_VEC(uint, n) u = PN_CAT(as_, PN_VEC(uint, n))(v);                                                  \
    PN_VEC(float, n) r = PN_CAT(as_, PN_VEC(float, n))((u + 0x0FFFu + ((u >> 13) & 1u)) & ~0x1FFFu);            \
    r = select(r, copysign((PN_VEC(float, n))(INFINITY), v), isgreater(fabs(r), (PN_VEC(float, n))(65504.0f))); \
    return select(r, rint(v * 0x1.0p24f) * 0x1.0p-24f, isless(fabs(v), (PN_VEC(float, n))(0x1.0p-14f)));        \
  }
PN_ROUND_DEFINE(1)
PN_ROUND_DEFINE(2)
PN_ROUND_DEFINE(4)
#define PN_ROUND(n, v) PN_CAT(pn_round_half, n)(v)
#else
#define PN_SCALAR float
#define PN_STORED(n) PN_VEC(float, n)
#define PN_STRIDE(n) 1
#define PN_LOAD(n, p, i) ((p)[i])
#define PN_STORE(n, p, i, v) ((p)[i] = (v))
#define PN_VLOAD(n, i, p) PN_CAT(PN_VLOAD_FLOAT_, n)((i), (p))
#define PN_ROUND(n, v) (v)
#endif

#endif
