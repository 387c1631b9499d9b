// A plain C++ reference for the binned rasterizer (raster/): the same snapping spec and top-left rule, written
// naively — every triangle against every pixel centre of its box with 64-bit edge functions — and depths in double
// from eye-space values, so it shares no code or shortcuts with the kernels (only the float clip matrix, which
// is part of the input by definition: rasterClipMatrix()).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "host/scene/scene.h"
#include "raster/rasterizer.h"

namespace penumbra::test {

struct RefRaster {
  int width = 0, height = 0;
  std::vector<uint32_t> triangleId;  // visible triangle per pixel, kNoTriangle for background and outside scissor
  std::vector<double> viewZ;         // -z_eye of the visible point, +inf for background
  std::vector<double> depth;         // per the view's DepthMode, +inf for background
  std::vector<int> coverage;         // how many drawn triangles cover each pixel centre (any depth)
  // 1 where an alpha-tested triangle covering the pixel centre has an alpha that float and double may decide either
  // way (kAlphaBorder, kUvSlack).
  std::vector<uint8_t> alphaBorder;
  size_t index(int x, int y) const { return static_cast<size_t>(y) * width + x; }
};

// Where a fragment's alpha test may go either way between the kernels (float barycentrics and texture coordinates) and
// this reference (double): an alpha within kAlphaBorder of the cutoff, or one that crosses it when the texture
// coordinate moves by kUvSlack times (1 + the triangle's largest |coordinate|) along u or v (NEAREST at texel edges,
// LINEAR on steep ramps). Float barycentrics from clip coordinates err by ~1e-6 relative; 1e-5 leaves room.
inline constexpr double kAlphaBorder = 2e-3;
inline constexpr double kUvSlack = 1e-5;

class RefRasterizer {
 public:
  // Alpha-tested triangles (Material::mayDiscard) are tested at each covered pixel centre with barycentrics of the
  // pixel ray against the unsnapped triangle in double and the double alpha reference
  // (tools/selftest/reference/alpha_ref.h); the rest is the opaque reference unchanged. Single-sided triangles are
  // culled like back faces when view.cullSingleSided is set.
  RefRasterizer(const Scene& scene, const RasterView& view);

  const RefRaster& result() const { return result_; }
  // View depth of scene triangle `id` at pixel (x, y) when one of its drawn pieces covers the centre.
  std::optional<double> viewZOf(uint32_t id, int x, int y) const;
  // Drawn (clipped, snapped, kept) triangles; a near-plane crossing may give two for one scene triangle.
  size_t drawnTriangles() const { return tris_.size(); }
  // Scene triangles whose clipped polygon has more than three vertices (fanned into several triangles).
  size_t fannedTriangles() const { return fanned_; }

 private:
  struct Vertex {
    double x, y, z, w;  // clip space
    double eyeZ;        // z_eye, carried through clipping
  };
  struct Tri {
    uint32_t id;
    int64_t X[3], Y[3];  // snapped, counter-clockwise
    double w[3], eyeZ[3];
    int x0, y0, x1, y1;  // pixel box inside the scissor
  };

  // An alpha-tested scene triangle: its vertices' clip coordinates, texture coordinates and material.
  struct AlphaTri {
    int material = -1;  // index into materials_; -1: opaque
    glm::dvec3 x, y, w;
    glm::dvec2 uv[3];
    double slack = 0;  // kUvSlack * (1 + largest |coordinate|)
  };
  // Whether the fragment of scene triangle `id` at pixel (x, y) survives its alpha test; sets *border near the cutoff.
  bool alphaKeeps(uint32_t id, int x, int y, bool* border) const;

  void addTriangle(uint32_t id, const Vertex (&v)[3]);
  void addSnapped(uint32_t id, const Vertex& a, const Vertex& b, const Vertex& c);
  std::optional<double> viewZAt(const Tri& t, int x, int y) const;
  double depthOf(double viewZ, int x, int y) const;

  RasterView view_;
  int sx0_, sy0_, sx1_, sy1_;  // scissor
  size_t fanned_ = 0;
  std::vector<Tri> tris_;
  std::vector<std::vector<size_t>> byId_;
  std::vector<AlphaTri> alpha_;  // per scene triangle when the scene has alpha-tested materials, else empty
  std::vector<bool> cull_;       // per scene triangle: culled when back-facing
  std::vector<Material> materials_;
  std::vector<AlphaTexture> textures_;
  std::vector<uint8_t> texels_;
  RefRaster result_;
};

}  // namespace penumbra::test
