// A frame's G-buffer and visibility as the Image every command writes: the shaded preview (kernels/shade.cl:
// visibility x cos x spot cone plus ambient), visibility.Y, P.*, N.*, depth.Z. Shared by whatever produces a
// visibility buffer for the camera's G-buffer (the Renderer's techniques, the ray-traced reference).
#pragma once

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/io/image.h"
#include "host/scene/scene.h"
#include "raster/rasterizer.h"

namespace penumbra {

// R,G,B,A (A = 1 where a surface is seen), visibility.Y, P.X/Y/Z, N.X/Y/Z, depth.Z, with the light, camera and
// device as provenance attributes. Rows stay bottom-up like the G-buffer: add any further bottom-up channels,
// then flipRows(). `visibility` holds gbuffer.width * gbuffer.height values.
Image frameImage(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& visibility, const Camera& camera,
                 const Light& light, const Bounds& bounds);

}  // namespace penumbra
