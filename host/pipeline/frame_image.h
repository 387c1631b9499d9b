// A frame's G-buffer and visibility as the Image every command writes: the shaded preview (kernels/shade.cl:
// visibility x cos x spot cone plus ambient), visibility.Y, P.*, N.*, depth.Z. Shared by whatever produces a
// visibility buffer for the camera's G-buffer (the Renderer's techniques, the ray-traced reference).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/io/image.h"
#include "host/io/image_rows.h"
#include "host/scene/scene.h"
#include "raster/rasterizer.h"

namespace penumbra {

// What a frame makes besides each light's visibility buffer and channels (Renderer::render, planFrame): the shaded
// preview (channels R, G, B, A and RenderResult::preview), the G-buffer's surface channels (P.X/Y/Z, N.X/Y/Z,
// depth.Z) and the first light's technique's debug channels. A caller that reads the visibility alone (bench's
// accuracy, an engine that shades the frame itself) leaves the rest out: no preview pass, nothing else downloaded.
struct FrameOutputs {
  bool preview = true, surfaces = true, debug = true;
  static constexpr FrameOutputs visibilityOnly() { return {false, false, false}; }
  bool operator==(const FrameOutputs&) const = default;
};

// R,G,B,A (A = 1 where a surface is seen), visibility.Y (and visibility.<layer>.Y, the same), P.X/Y/Z, N.X/Y/Z,
// depth.Z, with the light, camera, device and version as provenance attributes and the standard worldToCamera and
// worldToNDC matrices. Rows stay bottom-up like the G-buffer: add any further bottom-up channels, then flipRows().
// `visibility` holds gbuffer.width * gbuffer.height values.
Image frameImage(Context& ctx, const GBuffer& gbuffer, const Buffer<float>& visibility, const Camera& camera,
                 const Light& light, const Bounds& bounds);

// One light of a frame and its visibility buffer (gbuffer.width * gbuffer.height values, rows bottom-up).
struct LightVisibility {
  const Light* light;
  const Buffer<float>* visibility;
};

// Several lights (at least one, their layers lightLayer() distinct): each light's visibility as
// "visibility.<layer>.Y" and the first's also as "visibility.Y"; the preview sums the lights' direct terms over one
// ambient term (one light: exactly the single-light preview); penumbra:light and penumbra:light-name are the first
// light's, penumbra:lights ("LAYER=FORM; ...") lists them all when there are several. `preview`, when given,
// receives the device RGBA the R,G,B,A channels are read from (rows bottom-up).
// `outputs` leaves channels out: without the preview no shading pass runs (`preview` is left empty).
Image frameImage(Context& ctx, const GBuffer& gbuffer, std::span<const LightVisibility> lights, const Camera& camera,
                 const Bounds& bounds, Buffer<cl_float4>* preview = nullptr, FrameOutputs outputs = {});

// The steps of frameImage for a frame whose channels stay on the device (written in bands: ImageRows):
// shadeFrame checks the lights as frameImage does and returns the shaded preview (R, G, B, A per pixel, rows
// bottom-up; an empty buffer and no shading pass without outputs.preview); frameHeader is the Image's size and header
// without channels; frameChannels reads each of frameImage's channels on demand, rows top-down (already flipped), one
// band of a float4 buffer downloaded once for all of its components. The readers hold the device buffers (OpenCL
// reference counts), so they outlive the renderer's own handles; their contents are the frame's until something writes
// them again (the renderer's next frame). The readers use `ctx`, which must outlive them.
Buffer<cl_float4> shadeFrame(Context& ctx, const GBuffer& gbuffer, std::span<const LightVisibility> lights,
                             const Camera& camera, const Bounds& bounds, FrameOutputs outputs = {});
Image frameHeader(Context& ctx, std::span<const LightVisibility> lights, const Camera& camera, const Bounds& bounds,
                  int width, int height);
std::vector<DeferredChannel> frameChannels(Context& ctx, const GBuffer& gbuffer,
                                           std::span<const LightVisibility> lights, const Buffer<cl_float4>& preview,
                                           FrameOutputs outputs = {});

// Whether any pixel of the G-buffer sees a surface (a finite depth), read in bands: the A channel's test without
// the channel.
bool seesSurface(Context& ctx, const GBuffer& gbuffer);

// "EX,EY,EZ:TX,TY,TZ:FOVY": the camera as the header's penumbra:camera records it (Camera::describe() for
// orthographic cameras and those with an up vector or clip planes of their own). A glTF camera's label()
// goes into penumbra:camera-source.
std::string cameraProvenance(const Camera& camera);

// The "lit.Y" mask of the G-buffer's pixels (same order): 1 where the preview's direct term can be non-zero, as
// kernels/shade.cl computes it: the normal turned towards the camera faces the light's centre (N.L > 0; a
// directional light: against its direction; a spot or point light: towards its position) and, for a spot light, the
// point lies inside the cone. 0 elsewhere and where no surface is seen (position.w == 0). Where it is 0 no
// visibility can show, so compare leaves it out.
std::vector<float> litMask(std::span<const cl_float4> position, std::span<const cl_float4> normal, const Camera& camera,
                           const Light& light);

}  // namespace penumbra
