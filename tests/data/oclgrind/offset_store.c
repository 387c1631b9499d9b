// Oclgrind 21.10's uninitialised-value check (OCLGRIND_UNINITIALIZED=1) and host-side stores: a store of S bytes at
// byte offset O of a buffer (clEnqueueWriteBuffer, clEnqueueCopyBuffer; clEnqueueFillBuffer stores each pattern so)
// reaches Uninitialized::hostMemoryStore, whose allocAndStoreShadowMemory first replaces the buffer's whole shadow
// memory with a fresh S-byte one (ShadowMemory::allocate keys it by buffer, ignores O and frees the old shadow), then
// stores S clean bytes at O, which ShadowMemory::store drops unless O + S <= S, i.e. unless O = 0. Kernels' stores are
// tracked element by element and are not affected, through sub-buffers neither (a sub-buffer's address is its
// parent's plus its origin). The sum kernel below reports "Uninitialized value written" for modes 1, 2, 3, 6 and 7:
//   mode 0 (control): one write of all 2N floats                        -> no report
//   mode 1: write [0,N), then [N,2N)                                    -> report
//   mode 2: copy an N-float buffer to [0,N), then to [N,2N)             -> report (penumbra's pssm and psvsm atlases)
//   mode 3: one write of [N,2N) alone, the kernel reads [N,2N) alone   -> report
//   mode 4: as 2, the copies done by a kernel                           -> no report (penumbra's workaround)
//   mode 5: a kernel writes [0,N), and [N,2N) through a sub-buffer      -> no report
//   mode 6: write [0,N), then a sub-buffer of [N,2N) at its offset 0   -> report
//   mode 7: clEnqueueFillBuffer of all 2N floats (2N stores of 4 bytes) -> report
// Build and run: gcc offset_store.c -o offset_store -lOpenCL
//   OCL_ICD_VENDORS=DIR_WITH_OCLGRIND_ICD OCLGRIND_UNINITIALIZED=1 ./offset_store MODE
#include "repro.h"

#define N 64

static const char* kSource =
    "__kernel void sum(__global const float* in, __global float* out, uint first, uint count) {\n"
    "  float s = 0.0f;\n"
    "  for (uint i = first; i < first + count; ++i) s += in[i];\n"
    "  out[0] = s;\n"
    "}\n"
    "__kernel void copy_at(__global const float* in, __global float* out, uint offset) {\n"
    "  out[offset + get_global_id(0)] = in[get_global_id(0)];\n"
    "}\n";

int main(int argc, char** argv) {
  int mode = argc > 1 ? atoi(argv[1]) : 0;
  Repro r = repro_open(kSource, "");
  cl_context ctx = r.ctx;
  cl_command_queue q = r.q;
  cl_program prog = r.prog;
  cl_int err;
  cl_kernel sum = clCreateKernel(prog, "sum", &err);
  CHECK(err);
  cl_kernel copy = clCreateKernel(prog, "copy_at", &err);
  CHECK(err);

  float host[2 * N];
  for (int i = 0; i < 2 * N; ++i) host[i] = (float)i;
  cl_mem dst = clCreateBuffer(ctx, CL_MEM_READ_WRITE, sizeof host, NULL, &err);
  CHECK(err);
  cl_mem src = clCreateBuffer(ctx, CL_MEM_READ_WRITE, N * sizeof(float), NULL, &err);
  CHECK(err);
  cl_mem out = clCreateBuffer(ctx, CL_MEM_READ_WRITE, sizeof(float), NULL, &err);
  CHECK(err);
  CHECK(clEnqueueWriteBuffer(q, src, CL_TRUE, 0, N * sizeof(float), host, 0, NULL, NULL));
  const size_t half = N * sizeof(float);
  cl_uint first = 0, count = 2 * N;
  switch (mode) {
    case 0:
      CHECK(clEnqueueWriteBuffer(q, dst, CL_TRUE, 0, sizeof host, host, 0, NULL, NULL));
      break;
    case 1:
      CHECK(clEnqueueWriteBuffer(q, dst, CL_TRUE, 0, half, host, 0, NULL, NULL));
      CHECK(clEnqueueWriteBuffer(q, dst, CL_TRUE, half, half, host + N, 0, NULL, NULL));
      break;
    case 2:
      CHECK(clEnqueueCopyBuffer(q, src, dst, 0, 0, half, 0, NULL, NULL));
      CHECK(clEnqueueCopyBuffer(q, src, dst, 0, half, half, 0, NULL, NULL));
      break;
    case 3:
      CHECK(clEnqueueWriteBuffer(q, dst, CL_TRUE, half, half, host + N, 0, NULL, NULL));
      first = N;
      count = N;
      break;
    case 4:
      for (cl_uint offset = 0; offset < 2 * N; offset += N) {
        size_t items = N;
        CHECK(clSetKernelArg(copy, 0, sizeof src, &src));
        CHECK(clSetKernelArg(copy, 1, sizeof dst, &dst));
        CHECK(clSetKernelArg(copy, 2, sizeof offset, &offset));
        CHECK(clEnqueueNDRangeKernel(q, copy, 1, NULL, &items, NULL, 0, NULL, NULL));
      }
      break;
    case 5:
    case 6: {
      cl_buffer_region region = {half, half};
      cl_mem sub = clCreateSubBuffer(dst, 0, CL_BUFFER_CREATE_TYPE_REGION, &region, &err);
      CHECK(err);
      if (mode == 6) {
        CHECK(clEnqueueWriteBuffer(q, dst, CL_TRUE, 0, half, host, 0, NULL, NULL));
        CHECK(clEnqueueWriteBuffer(q, sub, CL_TRUE, 0, half, host + N, 0, NULL, NULL));
        break;
      }
      cl_mem targets[2] = {dst, sub};
      for (int t = 0; t < 2; ++t) {
        size_t items = N;
        cl_uint offset = 0;
        CHECK(clSetKernelArg(copy, 0, sizeof src, &src));
        CHECK(clSetKernelArg(copy, 1, sizeof targets[t], &targets[t]));
        CHECK(clSetKernelArg(copy, 2, sizeof offset, &offset));
        CHECK(clEnqueueNDRangeKernel(q, copy, 1, NULL, &items, NULL, 0, NULL, NULL));
      }
      break;
    }
    case 7: {
      const float one = 1.0f;
      CHECK(clEnqueueFillBuffer(q, dst, &one, sizeof one, 0, sizeof host, 0, NULL, NULL));
      break;
    }
    default:
      fprintf(stderr, "mode 0-7\n");
      return 2;
  }
  CHECK(clSetKernelArg(sum, 0, sizeof dst, &dst));
  CHECK(clSetKernelArg(sum, 1, sizeof out, &out));
  CHECK(clSetKernelArg(sum, 2, sizeof first, &first));
  CHECK(clSetKernelArg(sum, 3, sizeof count, &count));
  size_t one = 1;
  CHECK(clEnqueueNDRangeKernel(q, sum, 1, NULL, &one, NULL, 0, NULL, NULL));
  float result;
  CHECK(clEnqueueReadBuffer(q, out, CL_TRUE, 0, sizeof result, &result, 0, NULL, NULL));
  printf("mode %d: sum of %u floats from %u = %g\n", mode, count, first, result);
  return 0;
}
