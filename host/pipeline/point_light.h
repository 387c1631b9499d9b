// A point light shadowed as six cube faces (host/views/cube.h): the light's technique renders every face that owns a
// pixel as a square spot light, from the face's own G-buffer, into a face visibility buffer, and cube_select copies
// the face's pixels into the light's visibility. Shared by the faces: the scene upload, the camera's G-buffer, the
// one classification pass and the technique instance with its buffers. Not shared: each face's map is drawn by the
// rasterizer from triangle setup on, since setup and binning transform and clip the triangles in that face's clip
// space and viewport.
#pragma once

#include <cstdint>

#include "host/cl/buffer.h"
#include "host/techniques/technique.h"
#include "raster/rasterizer.h"

namespace penumbra {

class CubeShadows {
 public:
  // Writes the visibility of `frame.light` (a point light) seen from `frame.gbuffer` (the camera's) into
  // `visibility`: each face's own pixels from the technique's render of that face, 1 for background. `size` (the
  // technique's map size for this frame) and `cubeGuard` (texels) set the face window. Faces without a pixel are
  // skipped. Records
  // "penumbra:cube" (guard, window, faces drawn) and every attribute a face recorded, as "+X: ...; -Y: ...", in
  // frame.attributes. frame.receivers is not used (each face reduces its own).
  void render(ShadowFrame& frame, Technique& technique, int size, float cubeGuard, Buffer<float>& visibility);

  // The face of every pixel in the last render (CUBE_NO_FACE for background), rows bottom-up.
  const Buffer<int32_t>& faces() const { return faces_; }

 private:
  Buffer<int32_t> faces_;
  GBuffer face_;  // the face's G-buffer: own positions and depths, the camera's normals and ids
  Buffer<float> faceVisibility_;
};

}  // namespace penumbra
