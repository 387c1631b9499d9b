// A point light's six cube faces as spot lights (kernels/shared/cube.h holds the face rule and frames shared with
// the kernels): each face is a square spot frustum at the light looking along +-X, +-Y or +-Z, widened by a guard
// band so that filters near the face's 90-degree edge read rendered texels; kernels/cube.cl classifies the camera's
// pixels by face, builds each face's own G-buffer and copies a face's visibility into the light's.
#pragma once

#include <cstdint>
#include <string>

#include <glm/glm.hpp>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/scene/light.h"
#include "kernels/shared/cube.h"
#include "raster/rasterizer.h"

namespace penumbra {

// The face of direction `d` from the light (cube_face: the major axis, ties x before y before z, NaN and zero +X).
int cubeFaceOf(const glm::vec3& d);
// "+X", "-X", "+Y", "-Y", "+Z", "-Z".
std::string cubeFaceName(int face);
// The face's frame in world space: the axis it looks along, its up and right vectors (unit, axis-aligned).
glm::vec3 cubeForward(int face);
glm::vec3 cubeUp(int face);
glm::vec3 cubeRight(int face);

// The spot light that draws face `face` of point light `point` with a window of half-width `tangent`
// (cube_window_tangent): at the point's position, aimed along the face's axis (its light eye has exactly the face's
// frame), full cone angle 2 atan(tangent), the point's radius as its disk radius (a sphere seen from a receiver is a
// disk facing it; the face's disk faces the face's axis instead) and the point's name.
Light cubeFaceLight(const Light& point, int face, float tangent);

// The face of every pixel of `gbuffer` (CUBE_NO_FACE for background) for a light at `light`: "cube/cube_classify".
void classifyCubeFaces(Context& ctx, const GBuffer& gbuffer, const glm::vec3& light, Buffer<int32_t>& faces);

// `out` becomes face `face`'s G-buffer: the camera's normals and ids (shared buffers), with positions and camera
// depths only where a pixel belongs to the face or lies within its window next to one that does, background
// elsewhere: "cube/cube_mask".
void maskCubeFace(Context& ctx, const GBuffer& camera, const Buffer<int32_t>& faces, const glm::vec3& light, int face,
                  float tangent, GBuffer& out);

// visibility[i] = faceVisibility[i] for the pixels of face `face`; the others keep theirs: "cube/cube_select".
void selectCubeFace(Context& ctx, const Buffer<int32_t>& faces, const Buffer<float>& faceVisibility, int face,
                    Buffer<float>& visibility);

}  // namespace penumbra
