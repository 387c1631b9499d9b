// Point lights as six cube faces, shared by host and kernels so that both put every direction on the same face:
// the face indices (OpenGL's cube-map order), each face's frame (the light eye of a spot light aimed along the face's
// axis, with host/scene/camera.h chooseUp's up vector), the major-axis rule with its tie rule, and the guard band's
// window. Valid as OpenCL C and C++; no library calls, so host and device compute the same bits.
#ifndef PENUMBRA_KERNELS_SHARED_CUBE_H
#define PENUMBRA_KERNELS_SHARED_CUBE_H

#include "kernels/shared/common.h"

#define CUBE_FACES 6
#define CUBE_FACE_POS_X 0
#define CUBE_FACE_NEG_X 1
#define CUBE_FACE_POS_Y 2
#define CUBE_FACE_NEG_Y 3
#define CUBE_FACE_POS_Z 4
#define CUBE_FACE_NEG_Z 5
#define CUBE_NO_FACE (-1)  // a background pixel (cube_classify)

// The guard band on each side of a face is at most this share of the face map's width: a window tangent of at most
// 1 / (1 - 2 * 0.25) = 2 (a field of view of at most 126.9 degrees).
#define CUBE_MAX_GUARD_FRACTION 0.25f

// |v| by one comparison: -0 stays -0 and NaN stays NaN, the same on every device.
inline float cube_abs(float v) { return v < 0.0f ? -v : v; }

// The face a direction (x, y, z) from the light belongs to: the axis of its largest |component|, on the + side when
// that component is not negative (+0 and -0 both count as +). Ties go to the earlier axis, x before y before z: (1, 1,
// 0) and (1, 1, 1) are +X, (0, -1, 1) is -Y, (-1, -1, -1) is -X. The zero vector is +X, and so is any direction with
// a NaN component; infinities are the largest magnitudes (two infinite components: the tie rule).
inline int cube_face(float x, float y, float z) {
  const float ax = cube_abs(x), ay = cube_abs(y), az = cube_abs(z);
  if (!(ax == ax && ay == ay && az == az)) return CUBE_FACE_POS_X;
  if (ax >= ay && ax >= az) return x < 0.0f ? CUBE_FACE_NEG_X : CUBE_FACE_POS_X;
  if (ay >= az) return y < 0.0f ? CUBE_FACE_NEG_Y : CUBE_FACE_POS_Y;
  return z < 0.0f ? CUBE_FACE_NEG_Z : CUBE_FACE_POS_Z;
}

// A face's frame as world axes (0 x, 1 y, 2 z) with signs: forward (the axis the face looks along), up (+Y, or +Z
// for the +-Y faces: what chooseUp picks) and right = forward x up, the light eye's x, y and -z.
inline int cube_forward_axis(int face) { return face / 2; }
inline float cube_forward_sign(int face) { return face % 2 == 0 ? 1.0f : -1.0f; }
inline int cube_up_axis(int face) { return face / 2 == 1 ? 2 : 1; }
inline int cube_right_axis(int face) { return face / 2 == 0 ? 2 : 0; }
inline float cube_right_sign(int face) {
  return face == CUBE_FACE_NEG_X || face == CUBE_FACE_NEG_Y || face == CUBE_FACE_POS_Z ? -1.0f : 1.0f;
}

// Component `axis` of (x, y, z).
inline float cube_component(float x, float y, float z, int axis) { return axis == 0 ? x : axis == 1 ? y : z; }

// Whether direction (x, y, z) lies in the face's window: in front of it (forward > 0) with |right| and |up| at most
// `tangent` times forward. tangent 1 is the face's own 90-degree square, where the major-axis rule puts it.
inline int cube_in_window(float x, float y, float z, int face, float tangent) {
  const float w = cube_forward_sign(face) * cube_component(x, y, z, cube_forward_axis(face));
  const float u = cube_abs(cube_component(x, y, z, cube_right_axis(face)));
  const float v = cube_abs(cube_component(x, y, z, cube_up_axis(face)));
  return w > 0.0f && u <= tangent * w && v <= tangent * w;
}

// The window's half-width tangent for a face map of `size` texels with `guard` texels beyond the 90-degree square on
// each side: the square spans size - 2 guard texels of the 2 tangent units, so tangent = 1 / (1 - 2 guard / size).
// The guard is clamped to [0, CUBE_MAX_GUARD_FRACTION * size].
inline float cube_window_tangent(float guard, int size) {
  const float limit = CUBE_MAX_GUARD_FRACTION * (float)size;
  const float g = guard > limit ? limit : guard > 0.0f ? guard : 0.0f;
  return 1.0f / (1.0f - 2.0f * g / (float)size);
}

#endif
