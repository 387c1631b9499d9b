// Probe of the runtime's local-memory limit check (host/cl/kernel.h) for tests/runtime_test.cpp.

// A __local argument, so that the runtime's local-memory limit check has something to refuse.
__kernel void fill_local_test(__global float* out, uint count, __local float* scratch) {
  uint i = get_global_id(0);
  scratch[get_local_id(0)] = (float)i;
  barrier(CLK_LOCAL_MEM_FENCE);
  if (i < count) out[i] = scratch[get_local_id(0)];
}
