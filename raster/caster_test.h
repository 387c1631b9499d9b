// The caster test of RasterView::casterLight: whether a triangle can hide no part of a light from any point of a box
// (the geometry's bounds), with the numbers setup reads (RasterViewParams::caster*), and the same test on the host in
// double precision for callers that pick casters themselves (izb's area-light lists).
#pragma once

#include <glm/glm.hpp>

#include "raster/rasterizer.h"
#include "raster/types.h"

namespace penumbra::raster {

class CasterTest {
 public:
  // Throws std::invalid_argument for a light that is not finite, a negative radius or a cone of half a sphere or more.
  // An empty box (lo above hi) leaves every triangle in.
  CasterTest(const RasterLight& light, const glm::vec3& lo, const glm::vec3& hi);

  // Whether (a, b, c) can shadow no point of the box: its plane has the whole light strictly on one side and the box
  // on that side too, up to the tolerance (10^-5 of the box's size and distance from the origin: far below any depth
  // bias, above the plane's rounding). Degenerate and non-finite triangles are kept.
  bool castsNothing(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const;

  // The same test for setup (raster/setup.cl setupCastsNothing, in float): RasterViewParams::casterSource and the rest.
  void describe(RasterViewParams& p) const;

 private:
  bool empty_ = true;
  uint32_t source_ = RASTER_CASTERS_ALL;
  glm::dvec4 light_{0.0};  // ball: centre, radius; cone: unit direction towards the light, sin(angular radius)
  glm::dvec3 centre_{0.0}, half_{0.0};
  double tolerance_ = 0.0;
};

}  // namespace penumbra::raster
