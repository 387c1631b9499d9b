// Checks of the kernels that read the caller's images (kernels/caller_inputs.cl: pn_shade's map and G-buffer, and
// pn_image_copy) against plain host code. The test suite (tests/caller_inputs_test.cpp) and `penumbra selftest` run
// the same.
#pragma once

#include "host/cl/context.h"
#include "tools/selftest/reference/tolerance.h"

namespace penumbra::selftest {

// A float evaluation of a depth reading's rational function against the double one: a few ulps of the depth.
inline constexpr ref::Tolerance kCallerDepthTol{1e-4, 1e-5};
// Positions unprojected from a window depth: the depth buffer's float resolution at the plane's distance.
inline constexpr ref::Tolerance kCallerPositionTol{2e-4, 0.0};
// A normal from the cross product of two neighbour steps on a plane: float round-off of the steps.
inline constexpr ref::Tolerance kCallerNormalTol{1e-3, 0.0};

// caller_light_depth: OpenGL, reversed-Z and orthographic window depths and linear depths, at 1x1, 3x3 and 7x7 texels
// holding NaN, infinities, 0, 1, values beyond the far plane and in front of the near one, against the reading in
// double (+INFINITY where empty).
ref::Comparison callerDepth(Context& ctx);

// caller_positions_from_depth and caller_derived_normals: a camera over the tilted plane y = x / 2 at 1x1, 5x5 and 9x9
// pixels (one background pixel): positions against the ray-plane hits in double, normals against the plane's (up to
// sign), an isolated pixel's +y.
ref::Comparison callerPositionsFromDepth(Context& ctx);

// caller_positions and caller_normals on a pitched, top-down image: covered, background and non-finite positions;
// non-unit, zero and NaN normals (zero and NaN fall back to the neighbours' plane, else +y).
ref::Comparison callerImages(Context& ctx);

// caller_copy between a packed image and a pitched, top-down one at 1x1, 5x3x2, 7x9x4 and 64x2x3: exact, nothing
// written outside.
ref::Comparison imageCopies(Context& ctx);

}  // namespace penumbra::selftest
