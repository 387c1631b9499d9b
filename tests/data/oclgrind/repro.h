// What the standalone Oclgrind reproductions beside it share: CHECK, and the first device's context, queue and the
// program built from one source. Header-only C, so each stays one `gcc NAME.c -lOpenCL` away.
#ifndef PENUMBRA_OCLGRIND_REPRO_H
#define PENUMBRA_OCLGRIND_REPRO_H
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <stdio.h>
#include <stdlib.h>

#define CHECK(x)                                                       \
  do {                                                                 \
    cl_int e_ = (x);                                                   \
    if (e_ != CL_SUCCESS) {                                            \
      fprintf(stderr, "%s:%d: %s = %d\n", __FILE__, __LINE__, #x, e_); \
      exit(1);                                                         \
    }                                                                  \
  } while (0)

typedef struct {
  cl_device_id device;
  cl_context ctx;
  cl_command_queue q;
  cl_program prog;
} Repro;

// The first platform's first device, and `source` built with `options`; any failure exits 1 naming the call.
static Repro repro_open(const char* source, const char* options) {
  Repro r;
  cl_platform_id platform;
  cl_int err;
  CHECK(clGetPlatformIDs(1, &platform, NULL));
  CHECK(clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 1, &r.device, NULL));
  r.ctx = clCreateContext(NULL, 1, &r.device, NULL, NULL, &err);
  CHECK(err);
  r.q = clCreateCommandQueue(r.ctx, r.device, 0, &err);
  CHECK(err);
  r.prog = clCreateProgramWithSource(r.ctx, 1, &source, NULL, &err);
  CHECK(err);
  CHECK(clBuildProgram(r.prog, 1, &r.device, options, NULL, NULL));
  return r;
}

#endif
