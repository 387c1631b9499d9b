// Random inputs for the stage tests: the shared generators of tools/selftest/reference/inputs.h (images of values in
// [0, 1), light depth maps with background and NaN texels), which `penumbra selftest` runs on as well.
#pragma once

#include "tools/selftest/reference/inputs.h"

namespace penumbra::test {

using ref::randomDepthMap;
using ref::randomUnitImage;

}  // namespace penumbra::test
