// SolidSides (raster/solid_sides.h): the view's centre of projection from its separable projection, and per solid
// whether that centre lies outside its box, into one RASTER_CULL_* code per triangle.
#include "raster/solid_sides.h"

#include <fmt/format.h>

#include <stdexcept>

#include "raster/constants.h"

namespace penumbra::raster {

std::optional<glm::dvec4> projectionCentre(const RasterView& view) {
  const glm::dmat4 P(view.projection);  // separable: x_c = P00 x + P20 z + P30, y_c likewise, w_c = P23 z + P33
  if (P[0][0] == 0.0 || P[1][1] == 0.0) return std::nullopt;
  glm::dvec4 eye(0.0, 0.0, 1.0, 0.0);  // orthographic: the depth test keeps the largest z_eye, towards +z
  if (P[2][3] != 0.0) {
    const double z = -P[3][3] / P[2][3];
    eye = {-(P[2][0] * z + P[3][0]) / P[0][0], -(P[2][1] * z + P[3][1]) / P[1][1], z, 1.0};
  }
  const glm::dmat4 toWorld = glm::inverse(glm::dmat4(view.view));
  const glm::dvec4 centre = toWorld * eye;
  if (!(std::isfinite(centre.x) && std::isfinite(centre.y) && std::isfinite(centre.z))) return std::nullopt;
  return centre;
}

void SolidSides::set(const RasterGeometry& g) {
  if (!g.solidOf.empty() && g.solidOf.size() != g.triangles.size())
    throw std::invalid_argument(
        fmt::format("raster scene: {} solid indices for {} triangles", g.solidOf.size(), g.triangles.size()));
  for (size_t t = 0; t < g.solidOf.size(); ++t)
    if (g.solidOf[t] != RasterGeometry::kNoSolid &&
        (g.solidOf[t] < 0 || static_cast<size_t>(g.solidOf[t]) >= g.solids.size()))
      throw std::invalid_argument(
          fmt::format("raster scene: triangle {} bounds solid {} of {}", t, g.solidOf[t], g.solids.size()));
  solidOf_.assign(g.solidOf.begin(), g.solidOf.end());
  solids_.assign(g.solids.begin(), g.solids.end());
  if (solidOf_.empty()) solids_.clear();
  codes_.clear();
  centre_.reset();
}

SolidSides::Codes SolidSides::codesFor(const RasterView& view) {
  const std::optional<glm::dvec4> centre = projectionCentre(view);
  if (!centre) return {};
  // A window mirrored by the projection (one axis scaled negatively, or a perspective looking down +z) turns the
  // windings over; glm's frustum and ortho, and crops of them, keep counter-clockwise towards the centre.
  const glm::mat4& P = view.projection;
  const bool mirrored = (P[0][0] * P[1][1] < 0.0f) != (P[2][3] > 0.0f);
  if (centre_ == centre && mirrored_ == mirrored) return {&codes_, false};
  std::vector<uint8_t> drop(solids_.size());
  for (size_t s = 0; s < solids_.size(); ++s) {
    const RasterSolid& solid = solids_[s];
    bool outside = true;  // a centre at infinity lies outside every box
    if (centre->w != 0.0) {
      const glm::dvec3 c = glm::dvec3(*centre) / centre->w, lo(solid.min), hi(solid.max);
      const double margin = 1e-4 * (glm::length(hi - lo) + glm::length(c - 0.5 * (lo + hi)));
      outside = glm::any(glm::lessThan(c, lo - margin)) || glm::any(glm::greaterThan(c, hi + margin));
    }
    drop[s] = !outside ? RASTER_CULL_NONE : (solid.counterClockwiseOut != mirrored) ? RASTER_CULL_CW : RASTER_CULL_CCW;
  }
  codes_.resize(solidOf_.size());
  for (size_t t = 0; t < solidOf_.size(); ++t)
    codes_[t] = solidOf_[t] == RasterGeometry::kNoSolid ? RASTER_CULL_NONE : drop[static_cast<size_t>(solidOf_[t])];
  centre_ = centre, mirrored_ = mirrored;
  return {&codes_, true};
}

}  // namespace penumbra::raster
