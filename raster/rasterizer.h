// The binned compute rasterizer's host interface (in the spirit of Laine & Karras, "High-Performance
// Software Rasterization on GPUs", HPG 2011): triangle setup -> bin -> coarse -> fine, each stage its own
// kernel file in raster/. Used for light-view depth maps and the camera's G-buffer.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include <glm/glm.hpp>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/scene/scene.h"

namespace penumbra {

inline constexpr uint32_t kNoTriangle = 0xffffffffu;  // triangle id of background pixels

// What the depth buffer stores for a covered pixel (background is +INFINITY in every mode).
enum class DepthMode : int {
  kNdc = 0,       // window-space depth in [0, 1] (z_ndc * 0.5 + 0.5), as a hardware depth buffer
  kViewZ = 1,     // linear eye-space depth -z_eye (perspective and orthographic): what filtering wants
  kDistance = 2,  // Euclidean distance from the eye (world units): for omnidirectional/point-light tests
};

struct Scissor {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels [x0, x1) x [y0, y1)
};

struct RasterView {
  glm::mat4 view{1.0f};        // world -> eye
  glm::mat4 projection{1.0f};  // eye -> clip (perspective or orthographic, OpenGL convention)
  int width = 0, height = 0;   // 1x1 .. 8192x8192
  DepthMode depthMode = DepthMode::kViewZ;
  bool cullBackFaces = false;  // counter-clockwise front faces
  std::optional<Scissor> scissor;  // pixels outside are left untouched
};

// Depth-only targets (shadow maps): width * height each, row-major, row 0 at the bottom (y up in NDC).
struct RasterTargets {
  Buffer<float> depth;          // per DepthMode; +INFINITY where nothing was drawn
  Buffer<uint32_t> triangleId;  // index into Scene::triangles, kNoTriangle where nothing was drawn
};

// The camera's G-buffer, reconstructed exactly from the visible triangle per pixel.
struct GBuffer {
  int width = 0, height = 0;
  Buffer<float> depth;          // per DepthMode of the view; +INFINITY for background
  Buffer<cl_float4> position;   // world position (xyz), w = 1 where covered, 0 for background
  Buffer<cl_float4> normal;     // world shading normal (unit xyz, interpolated), w = geometric facing sign
  Buffer<uint32_t> triangleId;  // kNoTriangle for background
  Buffer<uint32_t> objectId;    // Scene::objectIds of the visible triangle, kNoTriangle for background
};

struct RasterStats {
  uint64_t trianglesIn = 0, trianglesSetUp = 0;  // after clipping, culling and dropping degenerates
  uint64_t binEntries = 0, tileEntries = 0;
  int retries = 0;  // grow-and-retry rounds after a capacity overflow
};

class Rasterizer {
 public:
  explicit Rasterizer(Context& ctx);
  ~Rasterizer();
  Rasterizer(const Rasterizer&) = delete;
  Rasterizer& operator=(const Rasterizer&) = delete;

  // Uploads the scene's world-space triangles once; later draws reuse them.
  void setScene(const Scene& scene);

  // Rasterizes into targets (allocated/resized as needed to view.width * view.height and cleared inside
  // the scissor). Launches are reported to the context's profiler under the stage name "raster".
  void draw(const RasterView& view, RasterTargets& targets);
  void drawGBuffer(const RasterView& view, GBuffer& gbuffer);

  const RasterStats& stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
