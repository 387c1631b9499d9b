// Light samples for the reference: concentric disk mapping, disk points for spot area lights and for sphere lights
// (the disk facing the receiver) and cone directions (area-preserving disk -> spherical cap map, cos theta = 1 - r^2
// (1 - cos alpha)) for sun disks.
#include "tools/reference/light_samples.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "host/scene/camera.h"

namespace penumbra::reference {
namespace {

// Ray end just short of a spot or point light's point, so geometry through the light point itself does not count.
constexpr float kSpotTfar = 1.0f - 1e-6f;

// Two unit vectors perpendicular to unit `axis` and to each other.
void diskBasis(const glm::vec3& axis, glm::vec3& tangent, glm::vec3& bitangent) {
  tangent = glm::normalize(glm::cross(axis, chooseUp(axis)));
  bitangent = glm::cross(axis, tangent);
}

}  // namespace

LightSampler::LightSampler(const Light& light)
    : type_(light.type), exact_(!light.isArea()), centre_(light.position), toLight_(-light.axis()) {
  diskBasis(light.axis(), tangent_, bitangent_);
  radius_ = light.radius;
  const float half = 0.5f * glm::radians(light.angularRadiusDeg);
  oneMinusCos_ = 2.0f * std::sin(half) * std::sin(half);  // 1 - cos alpha without cancellation for small alpha
}

glm::vec3 LightSampler::towardsCentre(const glm::vec3& p) const {
  if (type_ == LightType::Directional) return toLight_;
  const glm::vec3 d = centre_ - p;
  const float len = glm::length(d);
  return len > 0.0f ? d / len : -toLight_;
}

ShadowRay LightSampler::rayFromDisk(const glm::vec3& origin, glm::vec2 diskPoint) const {
  const glm::vec2 disk = exact_ ? glm::vec2(0.0f) : diskPoint;
  if (type_ == LightType::Spot) {
    const glm::vec3 point = centre_ + radius_ * (disk.x * tangent_ + disk.y * bitangent_);
    return {point - origin, kSpotTfar};
  }
  if (type_ == LightType::Point) {
    if (exact_) return {centre_ - origin, kSpotTfar};
    glm::vec3 tangent, bitangent;  // the sphere's disk faces the receiver
    diskBasis(towardsCentre(origin), tangent, bitangent);
    const glm::vec3 point = centre_ + radius_ * (disk.x * tangent + disk.y * bitangent);
    return {point - origin, kSpotTfar};
  }
  constexpr float kInf = std::numeric_limits<float>::infinity();
  if (exact_) return {toLight_, kInf};
  // |disk|^2 is uniform on [0, 1], so 1 - cos theta = |disk|^2 (1 - cos alpha) is uniform over the cap's solid
  // angle; the disk's direction is the azimuth.
  const float r2 = glm::dot(disk, disk);
  const float x = r2 * oneMinusCos_;  // 1 - cos theta
  const float cosTheta = 1.0f - x;
  const float sinTheta = std::sqrt(std::max(0.0f, x * (2.0f - x)));
  const float r = std::sqrt(r2);
  const glm::vec2 azimuth = r > 0.0f ? disk / r : glm::vec2(0.0f);
  return {cosTheta * toLight_ + sinTheta * (azimuth.x * tangent_ + azimuth.y * bitangent_), kInf};
}

}  // namespace penumbra::reference
