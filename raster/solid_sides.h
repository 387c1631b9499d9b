// Which side of each triangle a view may drop (RasterView::cullSolidsFarSides): the RASTER_CULL_* code of every
// triangle bounding a solid (RasterGeometry::solids) whose box the view's centre of projection lies outside, made
// once per centre on the host.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "raster/geometry.h"
#include "raster/rasterizer.h"

namespace penumbra::raster {

// The centre of projection of `view`'s separable projection in homogeneous world coordinates: where x_c, y_c and w_c
// vanish (w = 0: the direction towards which an orthographic view's depth test prefers fragments); nullopt for a
// singular one.
std::optional<glm::dvec4> projectionCentre(const RasterView& view);

class SolidSides {
 public:
  // Copies the geometry's solids (none: every view draws both sides). Throws std::invalid_argument when solidOf is
  // neither empty nor one entry per triangle, or names a solid that is not there.
  void set(const RasterGeometry& geometry);
  bool empty() const { return solids_.empty(); }

  // The codes for `view`, whose projection is separable; `changed` when they differ from the last call's. Null when
  // its centre cannot be found.
  struct Codes {
    const std::vector<uint8_t>* codes = nullptr;
    bool changed = false;
  };
  Codes codesFor(const RasterView& view);

 private:
  std::vector<int32_t> solidOf_;
  std::vector<RasterSolid> solids_;
  std::vector<uint8_t> codes_;
  std::optional<glm::dvec4> centre_;  // the centre codes_ were made for
  bool mirrored_ = false;             // and whether that view's window was mirrored
};

}  // namespace penumbra::raster
