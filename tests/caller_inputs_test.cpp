// The kernels that read the caller's images (kernels/caller_inputs.cl, host/stages/image_layout.h) against plain
// host code: depth conversions in every convention with NaN, +INFINITY, cleared and beyond-far texels; G-buffer
// positions from a depth buffer at 1x1 and at odd sizes; derived normals on a tilted plane (exact) and on an isolated
// pixel; copies between layouts at 1x1 and odd sizes. Outputs are poisoned before each run.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "host/cl/kernel.h"
#include "host/stages/image_layout.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace caller_inputs_test {

constexpr float kPoison = -12345.0f;

class CallerInputs : public test::ClTest {};

CallerDepthGpu readingOf(const glm::mat4& p, bool linear, bool zeroToOne, float farWindow, float farSign, float zFar) {
  CallerDepthGpu d{};
  d.storage = linear ? CALLER_DEPTH_LINEAR : CALLER_DEPTH_WINDOW;
  d.ndcZeroToOne = zeroToOne ? 1 : 0;
  d.farWindow = farWindow, d.farSign = farSign;
  d.p22 = p[2][2], d.p23 = p[3][2], d.p32 = p[2][3], d.p33 = p[3][3];
  d.zFar = zFar;
  return d;
}

// The host's reading of one value, in double: +INFINITY where empty.
double hostDepth(const CallerDepthGpu& d, float v) {
  if (!std::isfinite(v)) return INFINITY;
  if (d.storage == CALLER_DEPTH_LINEAR) return v < d.zFar ? double(v) : INFINITY;
  if ((double(v) - d.farWindow) * d.farSign >= 0.0) return INFINITY;
  const double w = std::clamp(double(v), 0.0, 1.0);  // in front of the near plane: the near plane
  const double ndc = d.ndcZeroToOne ? w : 2.0 * w - 1.0;
  return -(double(d.p23) - ndc * d.p33) / (ndc * d.p32 - double(d.p22));
}

TEST_F(CallerInputs, DepthInEveryConventionWithAdversarialTexels) {
  const glm::mat4 gl = glm::perspective(1.2f, 1.0f, 0.5f, 40.0f);
  glm::mat4 reversed = gl;  // Direct3D's reversed Z: z_ndc = (w - z) / 2w, 1 at the near plane
  for (int c = 0; c < 4; ++c) reversed[c][2] = 0.5f * (gl[c][3] - gl[c][2]);
  const glm::mat4 ortho = glm::ortho(-5.0f, 5.0f, -5.0f, 5.0f, -3.0f, 17.0f);
  struct Case {
    const char* name;
    CallerDepthGpu reading;
  } cases[] = {{"OpenGL window", readingOf(gl, false, false, 1.0f, 1.0f, 40.0f)},
               {"reversed Z", readingOf(reversed, false, true, 0.0f, -1.0f, 40.0f)},
               {"orthographic window", readingOf(ortho, false, false, 1.0f, 1.0f, 17.0f)},
               {"linear", readingOf(gl, true, false, 1.0f, 1.0f, 40.0f)}};
  const std::vector<float> special = {NAN, INFINITY, -INFINITY, 0.0f, 1.0f, 1.5f, -0.25f, 0.5f, 1e-7f, 0.9999999f};
  for (const Case& c : cases)
    for (const int side : {1, 3, 7}) {
      std::vector<float> texels(size_t(side) * side);
      for (size_t i = 0; i < texels.size(); ++i)
        texels[i] = i < special.size() ? special[i] : float(i % 13) / 13.0f * (c.reading.storage ? 45.0f : 1.0f);
      Buffer<float> src(ctx(), std::span<const float>(texels)), out(ctx(), texels.size());
      out.fill(ctx(), kPoison);
      CallerImage image{src};
      const CallerImageGpu layout = imageLayout(image, side, side, 1, "map");
      Kernel(ctx(), "kernels/caller_inputs.cl", "caller_light_depth", "test")
          .args(src, layout, c.reading, out)
          .launch(texels.size(), 64);
      const std::vector<float> got = out.download(ctx());
      for (size_t i = 0; i < texels.size(); ++i) {
        const double want = hostDepth(c.reading, texels[i]);
        if (std::isinf(want)) {
          EXPECT_EQ(got[i], INFINITY) << c.name << " texel " << texels[i];
        } else {  // float evaluation of the same rational function: a few ulps of the depth
          EXPECT_NEAR(got[i], want, 1e-5 * std::abs(want) + 1e-4) << c.name << " texel " << texels[i];
        }
      }
    }
}

TEST_F(CallerInputs, PositionsFromDepthAndNormalsFromPositions) {
  // A camera looking down at the tilted plane y = 0.5 x: positions from its depth buffer lie on the plane, and the
  // normals derived from them are the plane's (up to sign), but at a pixel without covered neighbours (+y).
  const glm::mat4 view = glm::lookAt(glm::vec3(0.3f, 6.0f, 0.2f), glm::vec3(0.0f), glm::vec3(0, 0, -1));
  const glm::mat4 projection = glm::perspective(0.8f, 1.0f, 1.0f, 20.0f);
  const glm::mat4 inverse = glm::inverse(projection * view);
  for (const int side : {1, 5, 9}) {
    std::vector<float> depth(size_t(side) * side);
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) {  // intersect the pixel's ray with the plane, in double
        const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / float(side) * 2.0f - 1.0f;
        const glm::dvec4 a = glm::dmat4(inverse) * glm::dvec4(ndc.x, ndc.y, -1, 1),
                         b = glm::dmat4(inverse) * glm::dvec4(ndc.x, ndc.y, 1, 1);
        const glm::dvec3 o = glm::dvec3(a) / a.w, d = glm::dvec3(b) / b.w - o;
        const double t = (0.5 * o.x - o.y) / (d.y - 0.5 * d.x);
        const glm::dvec4 clip = glm::dmat4(projection * view) * glm::dvec4(o + t * d, 1.0);
        depth[size_t(y) * side + x] = float(clip.z / clip.w * 0.5 + 0.5);
      }
    if (side > 1) depth[0] = 1.0f;  // background: the cleared value (1x1: one covered pixel, no neighbours)
    Buffer<float> src(ctx(), std::span<const float>(depth));
    Buffer<cl_float4> position(ctx(), depth.size()), normal(ctx(), depth.size());
    position.fill(ctx(), cl_float4{{kPoison, kPoison, kPoison, kPoison}});
    normal.fill(ctx(), cl_float4{{kPoison, kPoison, kPoison, kPoison}});
    CallerImage image{src};
    const CallerImageGpu layout = imageLayout(image, side, side, 1, "depth");
    const CallerDepthGpu reading = readingOf(projection, false, false, 1.0f, 1.0f, 20.0f);
    cl_float4 rows[4];
    for (int r = 0; r < 4; ++r) rows[r] = {{inverse[0][r], inverse[1][r], inverse[2][r], inverse[3][r]}};
    Kernel(ctx(), "kernels/caller_inputs.cl", "caller_positions_from_depth", "test")
        .args(src, layout, reading, rows[0], rows[1], rows[2], rows[3], position)
        .launch(depth.size(), 64);
    Kernel(ctx(), "kernels/caller_inputs.cl", "caller_derived_normals", "test")
        .args(position, uint32_t(side), uint32_t(side), normal)
        .launch(depth.size(), 64);
    const std::vector<cl_float4> p = position.download(ctx()), n = normal.download(ctx());
    if (side > 1) {
      EXPECT_EQ(p[0].s[3], 0.0f) << side;  // background
    }
    const glm::vec3 plane = glm::normalize(glm::vec3(-0.5f, 1.0f, 0.0f));
    for (size_t i = side > 1 ? 1 : 0; i < p.size(); ++i) {
      ASSERT_EQ(p[i].s[3], 1.0f) << side << " pixel " << i;
      EXPECT_NEAR(p[i].s[1], 0.5f * p[i].s[0], 2e-4f) << side << " pixel " << i;  // on the plane, to depth precision
      const glm::vec3 normalGot(n[i].s[0], n[i].s[1], n[i].s[2]);
      if (side == 1) continue;
      EXPECT_NEAR(std::abs(glm::dot(normalGot, plane)), 1.0f, 1e-3f) << side << " pixel " << i;
    }
    if (side == 1) {  // an isolated pixel: no surface to follow
      EXPECT_EQ(glm::vec3(n[0].s[0], n[0].s[1], n[0].s[2]), glm::vec3(0, 1, 0));
    }
  }
}

TEST_F(CallerInputs, PositionsAndNormalsOfTheCallers) {
  // 3x2 pixels, rows from the top at a pitch: covered, background (w = 0), non-finite (background), covered ...;
  // normals non-unit (normalised), zero and NaN (the fallback from the neighbours' positions: the plane y = 0's).
  const int w = 3, h = 2;
  const std::vector<glm::vec4> positions = {{0, 0, 0, 1}, {1, 0, 0, 0},   {2, 0, 0, 1},
                                            {0, 0, 1, 1}, {NAN, 0, 1, 1}, {2, 0, 1, 7}};
  const std::vector<glm::vec4> normals = {{0, 3, 0, 0}, {0, 0, 0, 0},   {0, 0, 0, 0},
                                          {1, 1, 0, 9}, {NAN, 0, 0, 0}, {0, 0, 0, 0}};
  const size_t pitch = w * 4 + 2, offset = 1;  // floats
  std::vector<float> positionRows(offset + pitch * h, kPoison), normalRows(offset + pitch * h, kPoison);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) {  // memory row 0 is the image's top row (y = 1)
        positionRows[offset + (h - 1 - y) * pitch + x * 4 + c] = positions[size_t(y) * w + x][c];
        normalRows[offset + (h - 1 - y) * pitch + x * 4 + c] = normals[size_t(y) * w + x][c];
      }
  Buffer<float> positionSrc(ctx(), std::span<const float>(positionRows)),
      normalSrc(ctx(), std::span<const float>(normalRows));
  Buffer<cl_float4> position(ctx(), size_t(w) * h), normal(ctx(), size_t(w) * h);
  position.fill(ctx(), cl_float4{{kPoison, kPoison, kPoison, kPoison}});
  normal.fill(ctx(), cl_float4{{kPoison, kPoison, kPoison, kPoison}});
  const CallerImage positionImage{positionSrc, offset * 4, pitch * 4, true},
      normalImage{normalSrc, offset * 4, pitch * 4, true};
  Kernel(ctx(), "kernels/caller_inputs.cl", "caller_positions", "test")
      .args(positionSrc, imageLayout(positionImage, w, h, 4, "positions"), position)
      .launch(size_t(w) * h, 64);
  Kernel(ctx(), "kernels/caller_inputs.cl", "caller_normals", "test")
      .args(normalSrc, imageLayout(normalImage, w, h, 4, "normals"), position, normal)
      .launch(size_t(w) * h, 64);
  const std::vector<cl_float4> p = position.download(ctx()), n = normal.download(ctx());
  const float wOf[] = {1, 0, 1, 1, 0, 1};  // covered (w = 1), background (w = 0)
  for (size_t i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p[i].s[3], wOf[i]) << i;
    if (wOf[i] == 1) {
      EXPECT_EQ(glm::vec3(p[i].s[0], p[i].s[1], p[i].s[2]), glm::vec3(positions[i])) << i;
    }
  }
  const float r = 1.0f / std::sqrt(2.0f);
  const glm::vec3 want[] = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {r, r, 0}, {0, 1, 0}, {0, 1, 0}};
  for (size_t i = 0; i < n.size(); ++i) {
    EXPECT_NEAR(glm::length(glm::vec3(n[i].s[0], n[i].s[1], n[i].s[2]) - want[i]), 0.0f, 1e-6f) << i;
    EXPECT_EQ(n[i].s[3], 1.0f) << i;
  }
}

TEST_F(CallerInputs, CopiesBetweenLayouts) {
  for (const auto& [w, h, channels] : {std::array<int, 3>{1, 1, 1}, {5, 3, 2}, {7, 9, 4}, {64, 2, 3}}) {
    std::vector<float> packed(size_t(w) * h * channels);
    for (size_t i = 0; i < packed.size(); ++i) packed[i] = float(i) * 0.5f - 3.0f;
    const size_t offset = 5, pitch = size_t(w) * channels + 3;
    Buffer<float> src(ctx(), std::span<const float>(packed)), dst(ctx(), offset + pitch * h);
    dst.fill(ctx(), kPoison);
    CallerImage from{src}, to{dst, offset * 4, pitch * 4, true};
    copyImage(ctx(), from, imageLayout(from, w, h, channels, "src"), to, imageLayout(to, w, h, channels, "dst"));
    std::vector<float> want(offset + pitch * h, kPoison);
    for (int y = 0; y < h; ++y)
      for (int i = 0; i < w * channels; ++i)
        want[offset + (h - 1 - y) * pitch + i] = packed[size_t(y) * w * channels + i];
    EXPECT_EQ(dst.download(ctx()), want) << w << "x" << h << "x" << channels;
  }
}

}  // namespace caller_inputs_test
}  // namespace penumbra
