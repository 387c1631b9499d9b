// Where the camera and the light look: the camera's near/far fitted to the scene bounds, and the light's
// view (perspective for spot lights, orthographic for directional lights) fitted to the scene bounds.
// Fitting the light to the visible receivers and their casters only is issue 5's shadow-map fitting.
#pragma once

#include "host/scene/scene.h"
#include "kernels/shared/light_view.h"
#include "raster/rasterizer.h"

namespace penumbra {

// The camera's raster view with near/far fitted to the bounds (near clamped to far * 1e-4).
RasterView cameraView(const Camera& camera, const Bounds& bounds);

// The light's raster view (linear depth) for a square map of `size` texels, and the matching GPU struct.
struct LightView {
  RasterView raster;
  LightViewGpu gpu;
};
LightView fitLightView(const Light& light, const Bounds& bounds, int size);

}  // namespace penumbra
