#include "raster/caster_test.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra::raster {

CasterTest::CasterTest(const RasterLight& light, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::dvec4 source = light.directional ? glm::dvec4(glm::normalize(glm::dvec3(light.towards)),
                                                           std::sin(static_cast<double>(light.angularRadius)))
                                              : glm::dvec4(glm::dvec3(light.position), light.radius);
  if (!std::isfinite(source.x + source.y + source.z + source.w) || !(source.w >= 0.0) ||
      (light.directional && !(light.angularRadius < 0.5 * M_PI)))
    throw std::invalid_argument("raster view: the caster test's light is not finite, or a cone of half a sphere");
  light_ = source;
  source_ = light.directional ? RASTER_CASTERS_CONE : RASTER_CASTERS_BALL;
  empty_ = !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z);
  if (empty_) return;
  centre_ = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
  half_ = 0.5 * (glm::dvec3(hi) - glm::dvec3(lo));
  tolerance_ = 1e-5 * std::max({glm::length(half_), glm::length(centre_), 1e-30});
}

bool CasterTest::castsNothing(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) const {
  if (empty_) return false;
  const glm::dvec3 q0(a), n = glm::cross(glm::dvec3(b) - q0, glm::dvec3(c) - q0);
  const double size = glm::length(n);
  if (!(size > 0.0) || !std::isfinite(size)) return false;
  const glm::dvec3 light(light_);
  const double side = source_ == RASTER_CASTERS_BALL ? glm::dot(n, light - q0) : glm::dot(n, light);
  if (!(std::abs(side) > light_.w * size)) return false;  // the plane cuts the light (or touches it)
  const double nearest = std::copysign(1.0, side) * glm::dot(n, centre_ - q0) - glm::dot(glm::abs(n), half_);
  return nearest >= -tolerance_ * size;
}

void CasterTest::describe(RasterViewParams& p) const {
  if (empty_) return;
  p.casterSource = source_;
  p.casterTolerance = static_cast<float>(tolerance_);
  for (int i = 0; i < 4; ++i) p.casterLight[i] = static_cast<float>(light_[i]);
  for (int i = 0; i < 3; ++i)
    p.casterBoxCentre[i] = static_cast<float>(centre_[i]), p.casterBoxHalf[i] = static_cast<float>(half_[i]);
}

}  // namespace penumbra::raster
