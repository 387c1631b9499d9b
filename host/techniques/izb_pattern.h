// The light points `izb` traces under an area light (kernels/izb.cl izb_soft_test), and `penumbra reference
// --izb-light-samples N` with it, so that the two can be compared ray for ray: one k x k stratified, jittered pattern
// over the unit disk (Shirley & Chiu's concentric map), turned per pixel by one of IZB_ROTATIONS angles. And the
// bitmask tables of that pattern (after Schwarz & Stamminger 2007, "Bitmask soft shadows"): for every line across the
// light's plane, quantised by its normal's angle and its offset, the points that may lie on its inner side and those
// that certainly do, so that a caster's projection onto the light, three lines, covers its points in three lookups.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace penumbra {

class IzbLightPattern {
 public:
  // grid = k: N = k^2 points, k in IZB_MIN_LIGHT_GRID .. IZB_MAX_LIGHT_GRID (std::invalid_argument otherwise).
  explicit IzbLightPattern(int grid);

  int grid() const { return grid_; }
  int count() const { return grid_ * grid_; }
  // Point j of the unturned pattern, in the unit disk.
  const std::vector<glm::vec2>& points() const { return points_; }
  // The IZB_ROTATIONS turns (cos, sin); pixel `key` uses rotations()[izb_rotation_of(key)].
  const std::vector<glm::vec2>& rotations() const { return rotations_; }
  // Point j of pixel `key`: points()[j] turned by its rotation, computed as izb_soft_test computes it.
  glm::vec2 point(uint32_t key, int j) const;

  // The points where the light's plane holds them, as izb_soft_test compares them with a caster's projection (units
  // of the disk's radius, or for a sun of tan(alpha)): a disk light's are points() themselves, a sun's are its
  // directions' tangents, radial(|p|) p / |p| with radial(r) = tan(theta(r)) / tan(alpha), 1 - cos(theta(r)) = r^2 (1 -
  // cos(alpha)).
  std::vector<glm::dvec2> planePoints(bool sun, float oneMinusCos) const;

  // The masks (IZB_MASK_WORDS words each) of izb_soft_test's lookups, for points that lie in the light's plane at
  // `radial(|p|) * p / |p|` (a disk light's are the points themselves, radial = identity; a sun's are its directions'
  // tangents over tan(alpha)): index ((angle * IZB_MASK_OFFSETS + offset) * 2 + certain) * IZB_MASK_WORDS + word.
  // `margin` (units of the disk's radius) separates "may" from "certainly": a point within it of a line is neither
  // certainly inside nor certainly outside.
  std::vector<uint32_t> masks(bool sun, float oneMinusCos, float margin) const;

 private:
  int grid_;
  std::vector<glm::vec2> points_, rotations_;
};

}  // namespace penumbra
