// VSSM's per-pixel kernel (kernels/vssm.cl through the probe vssm_visibility_receivers) against the double-precision
// reference (reference/vssm_ref.h) on random and adversarial maps: the cases, their maps and receivers, the run and
// the counts both the test suite (tests/vssm_test.cpp) and `penumbra selftest` judge.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/cl/context.h"
#include "host/techniques/vssm_maps.h"

namespace penumbra::selftest {

// fp32 kernel against double reference: the discrete decisions (E(x) >= t, sigma^2 < Threshold, a tap's depth test,
// the HSM level) flip for receivers within rounding of a threshold, and a flip moves visibility by up to one
// sub-kernel's share. A receiver is a flip when it differs by more than kVssmVisTol (fp32 moments: |z| <= 1 with
// ~1e-7 relative error, over <= 85 sub-kernels).
inline constexpr double kVssmVisTol = 2e-3;
inline constexpr double kVssmMaxPathShare = 0.03;  // at most 3% of receivers may take another path
inline constexpr double kVssmMeanVisTol = 2e-3;    // mean |difference| over all receivers

struct VssmCase {
  std::string name;
  uint32_t width, height;
  float zNear, zFar;
  int searchScheme, shadeScheme;  // VSSM_SCHEME_*
  VssmSatMode sat = VssmSatMode::Fixed64;
  bool spot = true;
  float holes = 0.05f;  // share of NaN / empty texels
  double visTol = kVssmVisTol;
  int diskStrips = 0;    // beyond the paper: disk kernels of at most this many strips
  double stacked = 0.1;  // beyond the paper: the stacked-blocker PCF fallback's threshold (the default; 0 = never)
  int narrowings = 2;    // beyond the paper: search-kernel narrowings (vssm-search adaptive, the default; 0 = full)
  int satReduce = 1;     // beyond the paper: the moments' SAT over blocks of satReduce^2 texels
  bool firstMoment = true;  // beyond the paper: the shading's Chebyshev bound capped by the first moment (the default)
  double tilt = 0.05;  // beyond the paper: a tilted receiver's kernel filtered by the taps (the default; 0 = never)
  bool steep = false;  // a third of the receivers on planes steep in the map (slope-scaled biases up to 200x larger)
  bool quick = false;
};
std::vector<VssmCase> vssmCases();

// What one case measured: receivers compared, flips (beyond the case's visTol), receivers on another path, the
// receivers the reference sent down the subdivision, stacked-blocker and tilted-receiver paths and those whose search
// the HSM ended with no blocker instead of subdividing (vssm.cl vssm_no_blocker), the mean and the worst difference.
struct VssmOutcome {
  size_t receivers = 0, flips = 0, paths = 0, subdivided = 0, stacked = 0, tilted = 0, noBlocker = 0, descents = 0,
         outOfRange = 0;
  double meanDifference = 0.0, worstDifference = 0.0;
  std::string report;  // the first flips
  // The suite's verdict: visibility in [0, 1], paths and mean within their margins, the subdivision path taken where
  // the case subdivides, the HSM's no-blocker test where it narrows the search, and the stacked fallback where it is
  // on (and never where it is off), and the tilted receivers' taps where it has steep receivers (never where they are
  // off). Empty when it passes.
  std::string failure(const VssmCase& c) const;
};

// Throws NotApplicable for fp64 tables on a device without cl_khr_fp64. The context must hold the probe kernels.
VssmOutcome runVssmCase(Context& ctx, const VssmCase& c);

}  // namespace penumbra::selftest
