// The light model of the ray-traced reference, the same as the techniques' (host/scene/light.h,
// kernels/shared/light_view.h): a spot light is a point at `position`, or a disk of `radius` there facing along
// the axis (sampled uniformly by area); a point light is a point, or a sphere of `radius` there, sampled as the disk
// of that radius through its centre facing the receiver (uniformly by area: the sphere's outline seen from a distance
// D subtends asin(R / D), the disk atan(R / D)); a directional light is parallel rays, or a sun disk of angular radius
// alpha (directions uniform over the cone's solid angle). The spot cone is not part of visibility.
#pragma once

#include <glm/glm.hpp>

#include "host/scene/light.h"

namespace penumbra::reference {

struct ShadowRay {
  glm::vec3 direction;  // towards the light; not unit length for spot lights (it reaches the light point)
  float tfar;           // in units of |direction|: just short of the light point, or infinity
};

class LightSampler {
 public:
  explicit LightSampler(const Light& light);

  // A point (a spot or point light of radius 0) or parallel rays: one ray gives the exact answer.
  bool exact() const { return exact_; }
  // Unit vector from `p` towards the light's centre (what the ray origin is offset towards; a sphere's disk faces it).
  glm::vec3 towardsCentre(const glm::vec3& p) const;
  // The ray from `origin` to the light point or direction that `u` in [0,1)^2 selects; `u` is ignored when exact().
  ShadowRay ray(const glm::vec3& origin, glm::vec2 u) const { return rayFromDisk(origin, concentricDisk(u)); }
  // The same from `disk`, the unit-disk point concentricDisk(u) gives (izb's light pattern is made of such points).
  ShadowRay rayFromDisk(const glm::vec3& origin, glm::vec2 disk) const;

 private:
  LightType type_;
  bool exact_;
  glm::vec3 centre_;               // spot and point: light position
  glm::vec3 toLight_;              // directional: unit direction towards the light (-axis)
  glm::vec3 tangent_, bitangent_;  // orthonormal basis of the disk / cone, perpendicular to the axis (not points')
  float radius_;                   // spot and point: disk radius (world units)
  float oneMinusCos_;              // directional: 1 - cos(angular radius)
};

}  // namespace penumbra::reference
