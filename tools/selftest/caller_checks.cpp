// The caller-input kernels against plain host code (tools/selftest/caller_checks.h).
#include "tools/selftest/caller_checks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <span>
#include <string>
#include <vector>

#include "host/cl/kernel.h"
#include "host/stages/image_layout.h"
#include "host/views/views.h"
#include "tools/selftest/reference/inputs.h"
#include "tools/selftest/selftest.h"

namespace penumbra::selftest {

namespace {

constexpr char kCallerSource[] = "kernels/caller_inputs.cl";

CallerDepthGpu depthReadingOf(const glm::mat4& p, bool linear, bool zeroToOne, float farWindow, float farSign,
                              float zFar) {
  CallerDepthGpu d{};
  d.storage = linear ? CALLER_DEPTH_LINEAR : CALLER_DEPTH_WINDOW;
  d.ndcZeroToOne = zeroToOne ? 1 : 0;
  d.farWindow = farWindow, d.farSign = farSign;
  d.p22 = p[2][2], d.p23 = p[3][2], d.p32 = p[2][3], d.p33 = p[3][3];
  d.zFar = zFar;
  return d;
}

// The reading of one value in double (kernels/shared/caller_inputs.h): +INFINITY where empty, a window value in front
// of the near plane read as the near plane.
double hostDepth(const CallerDepthGpu& d, float v) {
  if (!std::isfinite(v)) return INFINITY;
  if (d.storage == CALLER_DEPTH_LINEAR) return v < d.zFar ? double(v) : INFINITY;
  if ((double(v) - d.farWindow) * d.farSign >= 0.0) return INFINITY;
  const double w = std::clamp(double(v), 0.0, 1.0);
  const double ndc = d.ndcZeroToOne ? w : 2.0 * w - 1.0;
  return -(double(d.p23) - ndc * d.p33) / (ndc * d.p32 - double(d.p22));
}

// Components xyz (or xyzw) of float4s, flattened.
std::vector<float> float4Components(const std::vector<cl_float4>& v, int count) {
  std::vector<float> out;
  for (const cl_float4& x : v)
    for (int c = 0; c < count; ++c) out.push_back(x.s[c]);
  return out;
}

}  // namespace

ref::Comparison callerDepth(Context& ctx) {
  const glm::mat4 gl = glm::perspective(1.2f, 1.0f, 0.5f, 40.0f);
  glm::mat4 reversed = gl;  // Direct3D's reversed Z: z_ndc = (w - z) / 2w, 1 at the near plane
  for (int c = 0; c < 4; ++c) reversed[c][2] = 0.5f * (gl[c][3] - gl[c][2]);
  const glm::mat4 ortho = glm::ortho(-5.0f, 5.0f, -5.0f, 5.0f, -3.0f, 17.0f);
  const struct {
    const char* name;
    CallerDepthGpu reading;
  } cases[] = {{"OpenGL window", depthReadingOf(gl, false, false, 1.0f, 1.0f, 40.0f)},
               {"reversed Z", depthReadingOf(reversed, false, true, 0.0f, -1.0f, 40.0f)},
               {"orthographic window", depthReadingOf(ortho, false, false, 1.0f, 1.0f, 17.0f)},
               {"linear", depthReadingOf(gl, true, false, 1.0f, 1.0f, 40.0f)}};
  const std::vector<float> special = {NAN, INFINITY, -INFINITY, 0.0f, 1.0f, 1.5f, -0.25f, 0.5f, 1e-7f, 0.9999999f};
  ref::Comparison all;
  for (const auto& c : cases)
    for (const int side : {1, 3, 7}) {
      std::vector<float> texels(size_t(side) * side);
      for (size_t i = 0; i < texels.size(); ++i)
        texels[i] = i < special.size() ? special[i] : float(i % 13) / 13.0f * (c.reading.storage ? 45.0f : 1.0f);
      Buffer<float> src(ctx, std::span<const float>(texels)), out(ctx, texels.size());
      out.fill(ctx, ref::kPoison);
      const CallerImage image{src};
      Kernel(ctx, kCallerSource, "caller_light_depth", "caller")
          .args(src, imageLayout(image, side, side, 1, "map"), c.reading, out)
          .launch(texels.size(), 64);
      std::vector<double> expected;
      for (float v : texels) expected.push_back(hostDepth(c.reading, v));
      const std::vector<float> got = out.download(ctx);
      all.merge(ref::compare(std::span<const float>(got), std::span<const double>(expected), kCallerDepthTol, side),
                std::string(c.name) + " " + std::to_string(side) + "x" + std::to_string(side));
    }
  return all;
}

ref::Comparison callerPositionsFromDepth(Context& ctx) {
  const glm::mat4 view = glm::lookAt(glm::vec3(0.3f, 6.0f, 0.2f), glm::vec3(0.0f), glm::vec3(0, 0, -1));
  const glm::mat4 projection = glm::perspective(0.8f, 1.0f, 1.0f, 20.0f);
  const glm::mat4 inverse = glm::inverse(projection * view);
  const glm::dvec3 plane = glm::normalize(glm::dvec3(-0.5, 1.0, 0.0));  // y = x / 2
  ref::Comparison all;
  for (const int side : {1, 5, 9}) {
    const size_t pixels = size_t(side) * side;
    std::vector<float> depth(pixels);
    std::vector<double> expectedPositions, expectedNormals;
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x) {  // the pixel's ray against the plane, in double
        const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / float(side) * 2.0f - 1.0f;
        const glm::dvec4 a = glm::dmat4(inverse) * glm::dvec4(ndc.x, ndc.y, -1, 1);
        const glm::dvec4 b = glm::dmat4(inverse) * glm::dvec4(ndc.x, ndc.y, 1, 1);
        const glm::dvec3 o = glm::dvec3(a) / a.w, d = glm::dvec3(b) / b.w - o;
        const glm::dvec3 hit = o + (0.5 * o.x - o.y) / (d.y - 0.5 * d.x) * d;
        const glm::dvec4 clip = glm::dmat4(projection * view) * glm::dvec4(hit, 1.0);
        depth[size_t(y) * side + x] = float(clip.z / clip.w * 0.5 + 0.5);
        for (int c = 0; c < 3; ++c) expectedPositions.push_back(hit[c]);
        expectedPositions.push_back(1.0);
      }
    if (side > 1) {  // one background pixel: the cleared value
      depth[0] = 1.0f;
      for (int c = 0; c < 4; ++c) expectedPositions[c] = 0.0;
    }
    Buffer<float> src(ctx, std::span<const float>(depth));
    Buffer<cl_float4> position(ctx, pixels), normal(ctx, pixels);
    position.fill(ctx, cl_float4{{ref::kPoison, ref::kPoison, ref::kPoison, ref::kPoison}});
    normal.fill(ctx, cl_float4{{ref::kPoison, ref::kPoison, ref::kPoison, ref::kPoison}});
    const CallerImage image{src};
    cl_float4 r[4];
    setLightViewRows(r, inverse);
    Kernel(ctx, kCallerSource, "caller_positions_from_depth", "caller")
        .args(src, imageLayout(image, side, side, 1, "depth"),
              depthReadingOf(projection, false, false, 1.0f, 1.0f, 20.0f), r[0], r[1], r[2], r[3], position)
        .launch(pixels, 64);
    Kernel(ctx, kCallerSource, "caller_derived_normals", "caller")
        .args(position, uint32_t(side), uint32_t(side), normal)
        .launch(pixels, 64);
    const std::vector<cl_float4> p = position.download(ctx), n = normal.download(ctx);
    const std::string label = std::to_string(side) + "x" + std::to_string(side);
    all.merge(ref::compare(std::span<const float>(float4Components(p, 4)), std::span<const double>(expectedPositions),
                           kCallerPositionTol, size_t(side) * 4),
              "positions " + label);
    // |n . plane| = 1 on covered pixels with neighbours; an isolated pixel's normal is +y.
    std::vector<double> got, want;
    for (size_t i = side > 1 ? 1 : 0; i < pixels; ++i) {
      const glm::dvec3 normalGot(n[i].s[0], n[i].s[1], n[i].s[2]);
      got.push_back(side > 1 ? std::abs(glm::dot(normalGot, plane)) : normalGot.y);
      want.push_back(1.0);
    }
    all.merge(ref::compare(std::span<const double>(got), std::span<const double>(want), kCallerNormalTol),
              "normals " + label);
  }
  return all;
}

ref::Comparison callerImages(Context& ctx) {
  // 3x2 pixels, rows from the top at a pitch: covered, background (w = 0), non-finite (background), covered ...;
  // normals non-unit (normalised), zero and NaN (the fallback: the plane y = 0 of the neighbours, or +y).
  const int w = 3, h = 2;
  const std::vector<glm::vec4> positions = {{0, 0, 0, 1}, {1, 0, 0, 0},   {2, 0, 0, 1},
                                            {0, 0, 1, 1}, {NAN, 0, 1, 1}, {2, 0, 1, 7}};
  const std::vector<glm::vec4> normals = {{0, 3, 0, 0}, {0, 0, 0, 0},   {0, 0, 0, 0},
                                          {1, 1, 0, 9}, {NAN, 0, 0, 0}, {0, 0, 0, 0}};
  const size_t pitch = w * 4 + 2, offset = 1;  // floats
  std::vector<float> positionRows(offset + pitch * h, ref::kPoison), normalRows(offset + pitch * h, ref::kPoison);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) {  // memory row 0 is the image's top row (y = 1)
        positionRows[offset + (h - 1 - y) * pitch + x * 4 + c] = positions[size_t(y) * w + x][c];
        normalRows[offset + (h - 1 - y) * pitch + x * 4 + c] = normals[size_t(y) * w + x][c];
      }
  Buffer<float> positionSrc(ctx, std::span<const float>(positionRows));
  Buffer<float> normalSrc(ctx, std::span<const float>(normalRows));
  Buffer<cl_float4> position(ctx, size_t(w) * h), normal(ctx, size_t(w) * h);
  position.fill(ctx, cl_float4{{ref::kPoison, ref::kPoison, ref::kPoison, ref::kPoison}});
  normal.fill(ctx, cl_float4{{ref::kPoison, ref::kPoison, ref::kPoison, ref::kPoison}});
  const CallerImage positionImage{positionSrc, offset * 4, pitch * 4, true};
  const CallerImage normalImage{normalSrc, offset * 4, pitch * 4, true};
  Kernel(ctx, kCallerSource, "caller_positions", "caller")
      .args(positionSrc, imageLayout(positionImage, w, h, 4, "positions"), position)
      .launch(size_t(w) * h, 64);
  Kernel(ctx, kCallerSource, "caller_normals", "caller")
      .args(normalSrc, imageLayout(normalImage, w, h, 4, "normals"), position, normal)
      .launch(size_t(w) * h, 64);
  const double r = 1.0 / std::sqrt(2.0);
  const std::vector<double> wantPositions = {0, 0, 0, 1, 0, 0, 0, 0, 2, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 2, 0, 1, 1};
  const std::vector<double> wantNormals = {0, 1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1, r, r, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1};
  ref::Comparison c = ref::compare(std::span<const float>(float4Components(position.download(ctx), 4)),
                                   std::span<const double>(wantPositions), {}, w * 4);
  c.merge(ref::compare(std::span<const float>(float4Components(normal.download(ctx), 4)),
                       std::span<const double>(wantNormals), {1e-6, 0.0}, w * 4),
          "normals");
  return c;
}

ref::Comparison imageCopies(Context& ctx) {
  ref::Comparison all;
  for (const auto& [w, h, channels] : {std::array<int, 3>{1, 1, 1}, {5, 3, 2}, {7, 9, 4}, {64, 2, 3}}) {
    std::vector<float> packed(size_t(w) * h * channels);
    for (size_t i = 0; i < packed.size(); ++i) packed[i] = float(i) * 0.5f - 3.0f;
    const size_t offset = 5, pitch = size_t(w) * channels + 3;
    Buffer<float> src(ctx, std::span<const float>(packed)), dst(ctx, offset + pitch * h);
    dst.fill(ctx, ref::kPoison);
    const CallerImage from{src};
    CallerImage to{dst, offset * 4, pitch * 4, true};
    copyImage(ctx, from, imageLayout(from, w, h, channels, "src"), to, imageLayout(to, w, h, channels, "dst"));
    std::vector<double> want(offset + pitch * h, ref::kPoison);
    for (int y = 0; y < h; ++y)
      for (int i = 0; i < w * channels; ++i)
        want[offset + (h - 1 - y) * pitch + i] = packed[size_t(y) * w * channels + i];
    const std::vector<float> got = dst.download(ctx);
    all.merge(ref::compare(std::span<const float>(got), std::span<const double>(want), {}, pitch),
              std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(channels));
  }
  return all;
}

void addCallerChecks(std::vector<Check>& out) {
  out.push_back({"caller", "depth_conventions", true, [](Context& ctx) {
                   return Measured{callerDepth(ctx), "depth"};
                 }});
  out.push_back(
      {"caller", "positions_from_depth", true, [](Context& ctx) { return Measured{callerPositionsFromDepth(ctx)}; }});
  out.push_back({"caller", "positions_and_normals", true, [](Context& ctx) { return Measured{callerImages(ctx)}; }});
  out.push_back({"caller", "image_copy", true, [](Context& ctx) { return Measured{imageCopies(ctx)}; }});
}

}  // namespace penumbra::selftest
