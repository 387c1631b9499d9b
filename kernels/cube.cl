// Point lights as six cube faces (host/views/cube.h): which face each G-buffer pixel belongs to (the major-axis rule
// of kernels/shared/cube.h on its direction from the light), each face's own G-buffer (the camera's, with the pixels
// the face does not shade made background, so a technique's kernels skip them), and the copy of a face's visibility
// into the light's for the pixels that belong to it.
#include "kernels/shared/cube.h"

// The face of every pixel, CUBE_NO_FACE for background (position.w == 0).
__kernel void cube_classify(__global const float4* position, uint count, float4 light, __global int* faces) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  const float4 p = position[i];
  faces[i] = p.w == 0.0f ? CUBE_NO_FACE : cube_face(p.x - light.x, p.y - light.y, p.z - light.z);
}

// Whether a pixel of the 3x3 block around (x, y) belongs to `face`.
inline int cube_block_has(__global const int* faces, uint width, uint height, uint x, uint y, int face) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = (int)x + dx, yy = (int)y + dy;
      if (xx >= 0 && yy >= 0 && xx < (int)width && yy < (int)height && faces[yy * (int)width + xx] == face) return 1;
    }
  return 0;
}

// The face's G-buffer positions and camera depths. A pixel keeps them when it belongs to the face, or lies inside the
// face's window (`tangent`, the guard band) next to one that does: the neighbours a technique measures footprints,
// receiver planes and 2x2 quads from are then the ones it sees in the camera's G-buffer. Every other pixel becomes
// background (w = 0, depth +INFINITY). Normals and ids are the camera G-buffer's own.
__kernel void cube_mask(__global const float4* position, __global const float* depth, __global const int* faces,
                        uint width, uint height, float4 light, int face, float tangent, __global float4* facePosition,
                        __global float* faceDepth) {
  const uint i = get_global_id(0);
  if (i >= width * height) return;
  const float4 p = position[i];
  int keep = faces[i] == face;
  if (!keep && p.w != 0.0f && cube_in_window(p.x - light.x, p.y - light.y, p.z - light.z, face, tangent))
    keep = cube_block_has(faces, width, height, i % width, i / width, face);
  facePosition[i] = keep ? p : (float4)(0.0f);
  faceDepth[i] = keep ? depth[i] : INFINITY;
}

// The light's visibility from the face's, for the pixels that belong to the face.
__kernel void cube_select(__global const int* faces, __global const float* faceVisibility, uint count, int face,
                          __global float* visibility) {
  const uint i = get_global_id(0);
  if (i >= count) return;
  if (faces[i] == face) visibility[i] = faceVisibility[i];
}
