// Test fixtures for kernels: one OpenCL context per test suite (created in SetUpTestSuite, never in a
// static initialiser), on the device named by PENUMBRA_DEVICE (ctest sets "cpu", i.e. PoCL).
#pragma once

#include <memory>

#include <gtest/gtest.h>

#include "host/cl/context.h"

namespace penumbra::test {

class ClTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = std::make_unique<Context>(); }
  static void TearDownTestSuite() { context_.reset(); }
  static Context& ctx() { return *context_; }

 private:
  static inline std::unique_ptr<Context> context_;
};

template <class Param>
class ClTestWithParam : public ClTest, public ::testing::WithParamInterface<Param> {};

// A value no kernel writes by accident: outputs are filled with it before a launch, so an unwritten
// element shows up as a mismatch instead of a stale correct value.
inline constexpr float kPoison = -1234567.0f;

}  // namespace penumbra::test
