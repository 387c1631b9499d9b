// Ray-traced shadow visibility with Embree (occlusion queries, rtcOccluded1M): the ground truth the shadow
// techniques are measured against. Soft lights use stratified samples in independent replicates, so each point
// gets an unbiased standard error of its own estimate. Alpha-tested materials' holes let rays through as they let
// the rasterizer's fragments (alpha_filter.h). Embree stays inside this target (penumbra::reference).
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <span>
#include <vector>

#include "host/scene/light.h"
#include "host/scene/scene.h"

namespace penumbra::reference {

// A receiver: a surface point and its geometric normal (either side; the ray origin moves to the light's side).
struct ShadowPoint {
  glm::vec3 position;
  glm::vec3 normal;
};

// Samples per point of a soft light: `replicates` independent k x k jittered grids over the light (concentric
// disk map), spp = replicates * k^2. Their spread gives the standard error of the mean.
struct SampleLayout {
  static constexpr int kReplicates = 4;
  // Throws std::invalid_argument unless spp = 4 k^2 with 1 <= k <= 64 (4, 16, 36, 64, ..., 256, 1024, ...).
  static SampleLayout fromSpp(int spp);
  int replicates = 1, grid = 1;
  int spp() const { return replicates * grid * grid; }
};

struct TraceSettings {
  int spp = 1024;     // soft lights only; see SampleLayout
  uint64_t seed = 1;  // same seed, same points, same light: the same result on any thread count
  int threads = 0;    // 0: one per hardware thread
  // Soft lights: izb's light pattern instead of spp (host/techniques/izb_pattern.h: izbLightGrid^2 jittered stratified
  // points, turned for point i by its key patternKeys[i], its G-buffer pixel), so the tracer and `izb` trace the same
  // rays; one replicate, so no standard error. 0: off.
  int izbLightGrid = 0;
  std::span<const uint32_t> patternKeys = {};
};

struct TraceResult {
  std::vector<float> visibility;     // per point: fraction of the light's samples that reach it, 0..1
  std::vector<float> standardError;  // per point: standard error of `visibility` (0 for exact lights)
  uint64_t rays = 0;
  int spp = 1;  // rays per point
  int threads = 0;
  double seconds = 0;  // wall time of tracing (BVH build excluded)
};

class ShadowTracer {
 public:
  // Builds the BVH of the scene's triangles (robust traversal, high build quality). Throws std::runtime_error
  // carrying Embree's message on failure.
  explicit ShadowTracer(const Scene& scene);
  ~ShadowTracer();
  ShadowTracer(const ShadowTracer&) = delete;
  ShadowTracer& operator=(const ShadowTracer&) = delete;

  TraceResult trace(std::span<const ShadowPoint> points, const Light& light, const TraceSettings& settings) const;

  // The nearest triangle along each ray (origin, unit direction; kNoHit where none), with the camera's G-buffer rules:
  // alpha-tested triangles' holes let rays through and single-sided triangles are not hit from behind. Shadow rays
  // (trace) see through the same holes and hit both sides. One thread; for checking G-buffers.
  static constexpr uint32_t kNoHit = 0xffffffffu;
  std::vector<uint32_t> firstHits(std::span<const glm::vec3> origins, std::span<const glm::vec3> directions) const;

  double buildSeconds() const;
  // World distance each ray origin is moved off its surface at point p: kRayOffset * max(|p|_inf, scene radius)
  // (float positions carry relative error, so the offset scales with the coordinates and the scene).
  float rayOffset(const glm::vec3& p) const;
  static constexpr float kRayOffset = 1e-4f;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::reference
