// Test fixtures for kernels: one OpenCL context per test suite (created in SetUpTestSuite, never in a
// static initialiser), on the device named by PENUMBRA_DEVICE (ctest sets "cpu", i.e. PoCL).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>

#include "host/cl/context.h"
#include "tools/selftest/kernels/probes.h"
#include "tools/selftest/reference/inputs.h"

namespace penumbra::test {

class ClTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    context_ = std::make_unique<Context>();
    withProbeKernels(*context_);
  }
  static void TearDownTestSuite() { context_.reset(); }
  static Context& ctx() { return *context_; }

 private:
  static inline std::unique_ptr<Context> context_;
};

template <class Param>
class ClTestWithParam : public ClTest, public ::testing::WithParamInterface<Param> {};

// A context on `like`'s device that reports at most `localBytes` of local memory and forces the GPU layouts
// (DeviceInfo's test hooks, what PENUMBRA_LOCAL_MEM_LIMIT and PENUMBRA_LAYOUTS=gpu set): every plan then tiles as on
// a small GPU, and a launch above the cap fails as it would there.
inline std::unique_ptr<Context> smallGpuContext(const Context& like, uint64_t localBytes) {
  DeviceInfo info = like.info();
  info.localMemBytes = std::min<uint64_t>(info.deviceLocalMemBytes, localBytes);
  info.layouts = "gpu";
  auto ctx = std::make_unique<Context>(info);
  withProbeKernels(*ctx);
  return ctx;
}

// Outputs are filled with it before a launch (tools/selftest/reference/inputs.h).
using ref::kPoison;

}  // namespace penumbra::test
