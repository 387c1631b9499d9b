// The receiver plane's depth slope of kernels/shared/shadow_common.h (sc_depth_slope, the slope the slope-scaled bias
// and the bias cone of filter taps grow with) against the light's exact depths: the light ray through texels around
// the receiver's, intersected with its plane in double precision, differenced across the map. Directional and spot
// maps (a wide spot, far off its axis, where tan of the angle to the light is not the slope), random receivers and
// normals, edge-on planes (clamped to SHADOW_MAX_SLOPE) and a plane square to a spot's axis (slope 0). And pcf's unit
// grid summed texel by texel (sc_grid_plane_sum) against the taps it replaces.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/kernel.h"
#include "host/scene/light.h"
#include "host/views/views.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace shadow_slope_test {

constexpr float kMaxSlope = 10.0f;      // SHADOW_MAX_SLOPE
constexpr double kRelTolerance = 2e-3;  // float projections of one-texel steps against double ray casts

class ShadowSlope : public test::ClTest {
 protected:
  static std::vector<float> slopes(const LightView& lv, const std::vector<glm::vec3>& points,
                                   const std::vector<glm::vec3>& normals) {
    std::vector<cl_float4> p, n;
    for (size_t i = 0; i < points.size(); ++i) {
      p.push_back({{points[i].x, points[i].y, points[i].z, 1.0f}});
      n.push_back({{normals[i].x, normals[i].y, normals[i].z, 0.0f}});
    }
    Buffer<cl_float4> pb(ctx(), std::span<const cl_float4>(p)), nb(ctx(), std::span<const cl_float4>(n));
    Buffer<LightViewGpu> gpu(ctx(), std::span<const LightViewGpu>(&lv.gpu, 1), CL_MEM_READ_ONLY);
    Buffer<float> out(ctx(), points.size());
    out.fill(ctx(), test::kPoison);
    Kernel kernel(ctx(), "tools/selftest/kernels/shadow_probe.cl", "shadow_depth_slope_test", "test");
    kernel.args(pb, nb, static_cast<uint32_t>(points.size()), gpu, out).launch(points.size(), 64);
    return out.download(ctx());
  }

  // |d(light depth) / d(texel)| of the plane (point, normal) at the point's texel, in texel widths: central
  // differences of exact ray-plane depths over +-0.5 texel.
  static double exactSlope(const LightView& lv, const glm::vec3& point, const glm::vec3& normal) {
    const glm::dmat4 view(lv.raster.view), projection(lv.raster.projection), unproject = glm::inverse(projection);
    const glm::dvec3 pe(view * glm::dvec4(glm::dvec3(point), 1.0));
    const glm::dvec3 ne = glm::normalize(glm::dvec3(view * glm::dvec4(glm::dvec3(normal), 0.0)));
    const glm::dvec4 clip = projection * glm::dvec4(pe, 1.0);
    const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
    const double size = lv.gpu.width;
    auto depthAt = [&](glm::dvec2 texelOffset) {
      const glm::dvec2 at = ndc + texelOffset * (2.0 / size);
      const glm::dvec4 a4 = unproject * glm::dvec4(at, -1.0, 1.0), b4 = unproject * glm::dvec4(at, 1.0, 1.0);
      const glm::dvec3 a = glm::dvec3(a4) / a4.w, b = glm::dvec3(b4) / b4.w;
      const double s = glm::dot(ne, pe - a) / glm::dot(ne, b - a);
      return -(a + s * (b - a)).z;
    };
    const double gu = depthAt({0.5, 0.0}) - depthAt({-0.5, 0.0}), gv = depthAt({0.0, 0.5}) - depthAt({0.0, -0.5});
    const double depth = -pe.z;
    const double texel =
        lv.gpu.kind == LIGHT_KIND_SPOT ? lv.gpu.texelScale * depth : lv.gpu.texelScale;  // lv_texel_world
    return std::hypot(gu, gv) / texel;
  }

  // In front of the light and inside its map.
  static bool inMap(const LightView& lv, const glm::vec3& point) {
    const glm::dvec4 eye = glm::dmat4(lv.raster.view) * glm::dvec4(glm::dvec3(point), 1.0);
    const glm::dvec4 clip = glm::dmat4(lv.raster.projection) * eye;
    return eye.z < 0.0 && clip.w > 0.0 && std::abs(clip.x) < 0.99 * clip.w && std::abs(clip.y) < 0.99 * clip.w;
  }

  static glm::dvec3 toLight(const Light& light, const glm::vec3& point) {
    return light.type == LightType::Directional ? -glm::normalize(glm::dvec3(light.direction))
                                                : glm::normalize(glm::dvec3(light.position) - glm::dvec3(point));
  }

  // tan of the angle between the normal (turned to the light) and the direction to the light.
  static double tanToLight(const Light& light, const glm::vec3& point, const glm::vec3& normal) {
    const double c = std::abs(glm::dot(glm::normalize(glm::dvec3(normal)), toLight(light, point)));
    return std::sqrt(std::max(1.0 - c * c, 0.0)) / c;
  }
};

Bounds box(glm::vec3 lo, glm::vec3 hi) {
  Bounds b;
  b.grow(lo), b.grow(hi);
  return b;
}

// Random receivers on and above a 10 x 10 ground with random normals facing the light, no steeper than 80 degrees
// (tan 5.7, under the clamp): sc_depth_slope is the exact slope within kRelTolerance, spot and directional alike.
TEST_F(ShadowSlope, EqualsTheExactSlopeOfTheReceiverPlane) {
  const Bounds scene = box({-5, 0, -5}, {5, 1, 5});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const char* spec : {"dir:0.3,-1,0.2", "spot:1,3,0.5:0,0,0:150", "spot:-4,1.5,-4:0,0,0:60"}) {
    const Light light = parseLight(spec);
    const LightView lv = fitLightView(light, scene, 512);
    std::vector<glm::vec3> points, normals;
    while (points.size() < 500) {
      const glm::vec3 p(5.0f * u(rng), 0.5f + 0.5f * u(rng), 5.0f * u(rng));
      glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
      if (!std::isfinite(n.x)) continue;
      const glm::vec3 l(toLight(light, p));
      if (glm::dot(n, l) < 0.0f) n = -n;
      if (!inMap(lv, p)) continue;
      const double slope = exactSlope(lv, p, n);
      if (!(glm::dot(n, l) > std::cos(glm::radians(80.0f))) || !(slope < 0.9 * kMaxSlope)) continue;
      points.push_back(p), normals.push_back(n);
    }
    const std::vector<float> got = slopes(lv, points, normals);
    double worstOffAxis = 0;
    for (size_t i = 0; i < points.size(); ++i) {
      const double want = exactSlope(lv, points[i], normals[i]);
      ASSERT_NEAR(got[i], want, kRelTolerance * std::max(want, 0.1)) << spec << " point " << i;
      const double tan = tanToLight(light, points[i], normals[i]);
      if (tan > 0.2) worstOffAxis = std::max(worstOffAxis, want / tan);
      if (light.type == LightType::Directional) {  // orthographic: the slope is tan(theta)
        ASSERT_NEAR(want, tan, 1e-6 * std::max(want, 1.0)) << spec << " " << i;
      }
    }
    std::printf("  %-26s largest slope / tan(theta) (tan > 0.2) %.3f\n", spec, worstOffAxis);
  }
}

// The case that made tan(theta) wrong: a ground point 30 degrees off the axis of a 150-degree spot 2 above it, its ray
// 30 degrees from the normal: the slope is 0.86, tan(theta) 0.59.
TEST_F(ShadowSlope, OffTheAxisOfAWideSpotTheSlopeExceedsTanTheta) {
  const Light light = parseLight("spot:3,2,1:0,0,0:150");
  const LightView lv = fitLightView(light, box({-5, 0, -5}, {5, 1, 5}), 512);
  const glm::vec3 p(2.0169f, 0.0f, 0.3616f), n(0, 1, 0);
  const float got = slopes(lv, {p}, {n})[0];
  EXPECT_NEAR(got, exactSlope(lv, p, n), kRelTolerance * got);
  EXPECT_NEAR(got, 0.86f, 0.01f);
  EXPECT_NEAR(tanToLight(light, p, n), 0.59, 0.01);
}

// An edge-on receiver (the normal perpendicular to the ray) gets the clamp, never NaN or infinity; a ground square to
// a spot's axis has a constant light depth (eye z) however far its point is off the axis: slope 0 where tan(theta)
// is 0.37.
TEST_F(ShadowSlope, EdgeOnClampsAndAPlaneSquareToTheAxisIsFlat) {
  const Light light = parseLight("spot:0,3,0:0,0,0:90");
  const LightView lv = fitLightView(light, box({-5, 0, -5}, {5, 1, 5}), 512);
  const glm::vec3 ground(1.0f, 0.0f, 0.5f);
  const glm::vec3 ray = glm::normalize(ground - light.position);
  const glm::vec3 edgeOn = glm::normalize(glm::cross(ray, glm::vec3(1, 0, 0)));
  const std::vector<float> got = slopes(lv, {ground, ground}, {edgeOn, glm::vec3(0, 1, 0)});
  EXPECT_EQ(got[0], kMaxSlope) << "edge-on";
  EXPECT_NEAR(got[1], 0.0f, 1e-3f) << "square to the axis";
  EXPECT_NEAR(tanToLight(light, ground, glm::vec3(0, 1, 0)), 0.373, 0.001);
}

// sc_grid_plane_sum (pcf's unit grid against the receiver's plane, each texel compared once) equals the sum of the
// (2r+1)^2 taps it replaces, sc_compare_bilinear_plane at every unit offset, to rounding: maps of 1x1, 7x5 and 64x64
// texels holding random depths, background (+inf) and NaN; receivers inside, on texel edges and centres, beyond every
// side and far from the origin (uv ~ 4000); radii 0..4; planes flat and steep. A case is left out where a texel lies
// within 1e-3 of its comparison's depth (rounding may tip it either way), at most a few of the thousands.
TEST_F(ShadowSlope, GridSumEqualsItsTaps) {
  Context& ctx = ShadowSlope::ctx();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const glm::ivec2 size : {glm::ivec2(1, 1), glm::ivec2(7, 5), glm::ivec2(64, 64)}) {
    std::vector<float> map(static_cast<size_t>(size.x) * size.y);
    for (float& z : map) {
      const float u = unit(rng);
      z = u < 0.1f ? INFINITY : u < 0.15f ? NAN : unit(rng);
    }
    std::vector<cl_float4> receivers;
    std::vector<cl_float2> gradients;
    std::vector<int> radii;
    for (int k = 0; k < 2000; ++k) {
      glm::vec2 uv(-3.0f + unit(rng) * (size.x + 6.0f), -3.0f + unit(rng) * (size.y + 6.0f));
      if (k % 5 == 1) uv = glm::floor(uv) + 0.5f;  // texel centres: fraction 0
      if (k % 5 == 2) uv = glm::floor(uv);         // texel edges: fraction 0.5
      if (k % 7 == 3) uv += glm::vec2(4000.0f);    // far from the origin, beyond the map
      const float steep = k % 3 == 0 ? 2.0f : 0.05f;
      receivers.push_back({{uv.x, uv.y, unit(rng), 0.0f}});
      gradients.push_back({{steep * (2.0f * unit(rng) - 1.0f), steep * (2.0f * unit(rng) - 1.0f)}});
      radii.push_back(k % 5);
    }
    const size_t count = receivers.size();
    Buffer<float> mapBuffer(ctx, std::span<const float>(map));
    Buffer<cl_float4> receiverBuffer(ctx, std::span<const cl_float4>(receivers));
    Buffer<cl_float2> gradientBuffer(ctx, std::span<const cl_float2>(gradients));
    Buffer<int> radiusBuffer(ctx, std::span<const int>(radii));
    Buffer<float> out(ctx, 2 * count);
    out.fill(ctx, test::kPoison);
    Kernel kernel(ctx, "tools/selftest/kernels/shadow_probe.cl", "shadow_grid_plane_test", "test");
    kernel
        .args(mapBuffer, size.x, size.y, receiverBuffer, gradientBuffer, radiusBuffer, static_cast<uint32_t>(count),
              out)
        .launch(count, 64);
    const std::vector<float> sums = out.download(ctx);
    size_t compared = 0;
    for (size_t i = 0; i < count; ++i) {
      const glm::dvec2 uv(receivers[i].s[0], receivers[i].s[1]), g(gradients[i].s[0], gradients[i].s[1]);
      const int r = radii[i];
      const glm::ivec2 first = glm::ivec2(glm::floor(uv - 0.5)) - r;
      bool close = false;  // a texel within 1e-3 of its comparison's depth
      for (int y = first.y; y <= first.y + 2 * r + 1; ++y)
        for (int x = first.x; x <= first.x + 2 * r + 1; ++x) {
          if (x < 0 || y < 0 || x >= size.x || y >= size.y) continue;
          const double z = map[static_cast<size_t>(y) * size.x + x];
          const double depth = receivers[i].s[2] + glm::dot(g, glm::dvec2(x + 0.5, y + 0.5) - uv);
          close |= std::isfinite(z) && std::abs(z - depth) < 1e-3;
        }
      if (close) continue;
      ++compared;
      const float taps = sums[2 * i], grid = sums[2 * i + 1];
      ASSERT_TRUE(std::isfinite(taps) && std::isfinite(grid)) << i;
      EXPECT_NEAR(grid, taps, 1e-5f * (2 * r + 1) * (2 * r + 1))
          << size.x << "x" << size.y << " case " << i << " radius " << r;
    }
    EXPECT_GT(compared, count * 9 / 10) << size.x << "x" << size.y;
  }
}

}  // namespace shadow_slope_test
}  // namespace penumbra
