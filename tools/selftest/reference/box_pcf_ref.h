// Double-precision reference of percentage-closer filtering over a box: the fraction of unoccluded texels
// in a (2r+1)^2 box, read bilinearly between texel centres (what a box-blurred VSM must equal for one
// planar occluder over a parallel receiver, Donnelly & Lauritzen 2006). Written from the definition, not
// from the kernels.
#pragma once

#include <glm/glm.hpp>
#include <vector>

namespace penumbra::ref {

class BoxPcf {
 public:
  // `occluded`: size*size flags (1 = the texel holds an occluder in front of the receiver), rows bottom-up.
  BoxPcf(const std::vector<double>& occluded, int size, int radius);
  // Visibility at continuous texel coordinates (texel centres at +0.5), clamped to the edge.
  double visibility(glm::dvec2 texel) const;

 private:
  int size_;
  std::vector<double> filtered_;  // box-filtered occlusion at the texel centres
};

}  // namespace penumbra::ref
