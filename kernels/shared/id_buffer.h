// The ID buffer (Luksch sec. 9.1, after Forsyth, "Shadowbuffers", GDC 2007): the light's map stores, beside the
// depth, which triangle covers each texel (the rasterizer's triangle id). A receiver is lit where the map sees
// its own id (looked up at the receiver's own map position, without the normal offset of the depth test, which moves
// a grazing receiver off its thin footprint in the map); four nearest texels are consulted against the edge acne of a
// nearest-texel lookup ("only shadow the surface if all four IDs do not match"). Modes, shared by host and kernels:
//   object:   ids are scene objects (Scene::objectIds): no bias at all, but no self-shadowing within an object;
//   polygon:  ids are triangles: self-shadowing between an object's own triangles, but a receiver whose texels are
//             covered by its neighbouring triangles of the same smooth mesh shadows itself at fine tessellation;
//   combined: the id test between objects, the biased depth test where the nearest texel holds the receiver's own
//             object (the paper: "use the common depth comparison with a suitable bias for self shadowing").
#ifndef PENUMBRA_KERNELS_SHARED_ID_BUFFER_H
#define PENUMBRA_KERNELS_SHARED_ID_BUFFER_H

#include "kernels/shared/common.h"
#include "kernels/shared/light_view.h"

#define ID_BUFFER_OFF 0
#define ID_BUFFER_OBJECT 1
#define ID_BUFFER_POLYGON 2
#define ID_BUFFER_COMBINED 3

#define ID_NONE 0xffffffffu  // an empty texel or a background pixel (the rasterizer's RASTER_NO_TRIANGLE)

#if !PENUMBRA_HOST
// The id of map texel (x, y) in the mode's id space: its triangle (polygon) or that triangle's object.
inline uint id_fetch(__global const uint* mapIds, __global const uint* objectIds, int width, int height, int x, int y,
                     int mode) {
  if (x < 0 || y < 0 || x >= width || y >= height) return ID_NONE;
  uint t = mapIds[y * width + x];
  return t == ID_NONE || mode == ID_BUFFER_POLYGON ? t : objectIds[t];
}

// The id lookups' position of the receiver at world `p`: its own map position, without the depth test's normal
// offset; read only with an ID buffer, so not projected without one.
inline float2 id_uv(__constant const LightViewGpu* lv, float3 p, int mode) {
  return mode == ID_BUFFER_OFF ? (float2)(0.0f) : lv_project(lv, p).xy;
}

// The receiver's own id in the mode's id space.
inline uint id_own(int mode, uint triangle, uint object) { return mode == ID_BUFFER_POLYGON ? triangle : object; }

// The four-neighbour rule at continuous texel coordinate `uv`: lit (1) when any of the four texels nearest `uv`
// holds the receiver's id `own` or nothing, shadowed (0) when all four hold other ids.
inline float id_lit(__global const uint* mapIds, __global const uint* objectIds, int width, int height, float2 uv,
                    uint own, int mode) {
  float2 base = pn_floor2(uv - 0.5f);
  int x = (int)base.x, y = (int)base.y;
  for (int k = 0; k < 4; ++k) {
    uint id = id_fetch(mapIds, objectIds, width, height, x + (k & 1), y + (k >> 1), mode);
    if (id == own || id == ID_NONE) return 1.0f;
  }
  return 0.0f;
}

// Whether the depth test decides at `uv`: always without an ID buffer, in combined mode where the nearest texel
// holds the receiver's own object (or nothing), never in the pure id modes.
inline int id_depth_decides(__global const uint* mapIds, __global const uint* objectIds, int width, int height,
                            float2 uv, uint ownObject, int mode) {
  if (mode == ID_BUFFER_OFF) return 1;
  if (mode != ID_BUFFER_COMBINED) return 0;
  uint id = id_fetch(mapIds, objectIds, width, height, (int)pn_floor(uv.x), (int)pn_floor(uv.y), ID_BUFFER_OBJECT);
  return id == ownObject || id == ID_NONE;
}

// The G-buffer's id of pixel i under `mode`: read only with an ID buffer (0 without: never compared).
inline uint id_pixel(__global const uint* ids, uint i, int mode) { return mode == ID_BUFFER_OFF ? 0u : ids[i]; }

// The visibility of one lookup at `uv` whose depth test gave `depthLit`, under the ID-buffer mode.
inline float id_visibility(__global const uint* mapIds, __global const uint* objectIds, int width, int height,
                           float2 uv, uint ownTriangle, uint ownObject, int mode, float depthLit) {
  if (id_depth_decides(mapIds, objectIds, width, height, uv, ownObject, mode)) return depthLit;
  int idMode = mode == ID_BUFFER_COMBINED ? ID_BUFFER_OBJECT : mode;
  return id_lit(mapIds, objectIds, width, height, uv, id_own(idMode, ownTriangle, ownObject), idMode);
}
#endif

#endif
