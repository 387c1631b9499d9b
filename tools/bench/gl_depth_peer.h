// The OpenGL peer of raster_bench (issue 3): the same triangles drawn depth-only by a driver's rasterizer through
// headless EGL (Mesa's llvmpipe on a CPU machine, the vendor's driver on a GPU one) into a 32-bit float depth
// texture, timed per frame by the wall clock around clear + draw + glFinish and by a GL_TIME_ELAPSED query.
#pragma once

#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "host/scene/scene.h"

namespace penumbra {

struct GlFrameTime {
  double wallMs = 0;    // clear + draw + glFinish on the host clock
  double queryMs = -1;  // GL_TIME_ELAPSED around clear + draw; < 0 when the driver has no timer query
};

// One EGL display and OpenGL core context, current on the thread that made it (every call must come from that
// thread). Every failure throws std::runtime_error naming the step; the destructor never throws.
class GlDepthPeer {
 public:
  GlDepthPeer();
  ~GlDepthPeer();
  GlDepthPeer(const GlDepthPeer&) = delete;
  GlDepthPeer& operator=(const GlDepthPeer&) = delete;

  const std::string& renderer() const;  // GL_RENDERER
  const std::string& version() const;   // GL_VERSION
  // Whether GL_RENDERER names one of Mesa's CPU rasterizers: there the timer query does not see the whole frame
  // and the wall clock is the honest time.
  bool software() const;

  // Uploads positions and triangles once (replacing the previous scene).
  void setScene(const Scene& scene);
  // Clears and draws the scene with clip = viewProj * world (OpenGL clip space, z in [-w, w]) into a
  // width x height depth texture (1 .. 8192 each; reallocated when the size changes).
  GlFrameTime draw(const glm::mat4& viewProj, int width, int height);
  // The depth texture of the last draw: width * height window depths, row 0 at the bottom, 1 where nothing drew.
  std::vector<float> readDepth();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
