// Oclgrind 21.10's uninitialised-value check (OCLGRIND_UNINITIALIZED=1) dies (SIGSEGV) on a vector literal made of
// vectors, (int4)(lo, hi) with int2 halves, built unoptimised (-cl-opt-disable, as penumbra's tests build for it):
// clang emits it as shufflevectors whose masks hold undef lanes (<0, 1, undef, undef>), getMaskValue() is -1 there,
// and Uninitialized::instructionExecuted's ShuffleVector case tests the lane against llvm::Value::UndefValueVal (a
// Value subclass id, not -1), so it takes -1 as a lane of the second operand and copies shadow from about 4 GiB past
// it. Lane by lane literals, (int4)(lo.x, lo.y, hi.x, hi.y), are element inserts: no shuffle, no crash; a vector
// mixed with scalars, (float4)(xy, 2.0f, 0.0f), is built so as well.
//   mode 0: out = (int4)(lo, hi)                -> SIGSEGV (exit status 139)
//   mode 1: out = (int4)(lo.x, lo.y, hi.x, hi.y) -> runs, no report (kernels/jittered.cl's form)
// Build and run: gcc shuffle_undef.c -o shuffle_undef -lOpenCL
//   OCL_ICD_VENDORS=DIR_WITH_OCLGRIND_ICD OCLGRIND_UNINITIALIZED=1 ./shuffle_undef MODE
#include "repro.h"

static const char* kSource =
    "__kernel void widen(__global const int2* in, __global int4* out) {\n"
    "  size_t i = get_global_id(0);\n"
    "  int2 lo = in[i], hi = in[i] + 1;\n"
    "  out[i] = (int4)(lo, hi);\n"
    "}\n"
    "__kernel void widen_lanes(__global const int2* in, __global int4* out) {\n"
    "  size_t i = get_global_id(0);\n"
    "  int2 lo = in[i], hi = in[i] + 1;\n"
    "  out[i] = (int4)(lo.x, lo.y, hi.x, hi.y);\n"
    "}\n";

int main(int argc, char** argv) {
  int mode = argc > 1 ? atoi(argv[1]) : 0;
  if (mode != 0 && mode != 1) {
    fprintf(stderr, "mode 0 or 1\n");
    return 2;
  }
  Repro r = repro_open(kSource, "-cl-opt-disable");
  cl_context ctx = r.ctx;
  cl_command_queue q = r.q;
  cl_program prog = r.prog;
  cl_int err;
  cl_kernel kernel = clCreateKernel(prog, mode == 0 ? "widen" : "widen_lanes", &err);
  CHECK(err);

  enum { kItems = 4 };
  cl_int host[2 * kItems] = {1, 2, 3, 4, 5, 6, 7, 8}, result[4 * kItems];
  cl_mem in = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof host, host, &err);
  CHECK(err);
  cl_mem out = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, sizeof result, NULL, &err);
  CHECK(err);
  CHECK(clSetKernelArg(kernel, 0, sizeof in, &in));
  CHECK(clSetKernelArg(kernel, 1, sizeof out, &out));
  size_t items = kItems;
  CHECK(clEnqueueNDRangeKernel(q, kernel, 1, NULL, &items, NULL, 0, NULL, NULL));
  CHECK(clEnqueueReadBuffer(q, out, CL_TRUE, 0, sizeof result, result, 0, NULL, NULL));
  printf("mode %d: out[0] = (%d, %d, %d, %d)\n", mode, result[0], result[1], result[2], result[3]);
  return 0;
}
