// The filtering stages' checks, one function per case of tools/selftest/reference/cases.h: the stage on the case's
// input against the double-precision reference under the named margins. `penumbra selftest` registers them
// (addStageChecks) and the test suite's stage tests assert that they pass, so the two run the same code.
#pragma once

#include "host/cl/context.h"
#include "host/stages/blur.h"
#include "host/stages/moments.h"
#include "tools/selftest/reference/cases.h"
#include "tools/selftest/selftest.h"

namespace penumbra::selftest {

// The runs layout stages whole lines in local memory: NotApplicable for a direct plan in `config.layout` Runs whose
// lines do not fit the device's.
void requireLayoutFits(const Context& ctx, const ImageShape& shape, const BlurConfig& config);

// Every encoding in fp32 or half storage (half: within the fp32 margin plus half a half-ulp).
Measured checkMoments(Context& ctx, const ref::MomentsCase& c, MomentStorage storage);
Measured checkMomentsReduced(Context& ctx, const ref::MomentsReducedCase& c);  // block means
// The case's plan in `layout` (Auto: the device's; Runs: NotApplicable where its lines do not fit local memory).
Measured checkBlur(Context& ctx, const ref::BlurCase& c, BlurLayout layout);
// Fixed point exact (and a zero offset), floating point within ref::satTableTolerance and its zero-mean offset within
// ref::kSatMeanRelTol. NotApplicable: fp64 without cl_khr_fp64, tiled kernels that do not fit local memory.
Measured checkSat(Context& ctx, const ref::SatCase& c);
Measured checkMomentMips(Context& ctx, const ref::PyramidCase& c);  // every level, and every level's mean
Measured checkLogMips(Context& ctx, const ref::PyramidCase& c, float exponent);
Measured checkMinMax(Context& ctx, const ref::PyramidCase& c);        // exact
Measured checkMinMaxLevels(Context& ctx, const ref::PyramidCase& c);  // levels 1.. alone, exact, and the top
Measured checkLloyd(Context& ctx, const ref::ReduceCase& c);          // counts exact, sums, the same bits again

}  // namespace penumbra::selftest
