/* penumbra's C API: a technique shaded from the caller's own light depth map and camera G-buffer (pn_shade). An
 * engine that draws its shadow maps and G-buffer itself, usually in hardware, hands them over as cl_mem buffers and
 * gets each pixel's visibility back in a buffer of its own; the technique's stages (moments, blur, SAT, pyramids, the
 * fits that measure the penumbrae) run on the pn_shader's buffers, on the context's queue. */
#ifndef PENUMBRA_SHADE_H
#define PENUMBRA_SHADE_H

#include "penumbra/context.h"
#include "penumbra/renderer.h"
#include "penumbra/scene.h"
#include "penumbra/stages.h"

/** @file
 *  pn_shade: techniques on the caller's light depth map and G-buffer. */

#ifdef __cplusplus
extern "C" {
#endif

/** How a depth image stores its values. */
typedef enum pn_depth_storage {
  PN_DEPTH_WINDOW = 0, /**< A depth buffer's value d in [0, 1], as the projection and the viewport left it. */
  PN_DEPTH_LINEAR = 1, /**< The eye depth -z_eye in world units (a colour target written by the caller's shader). */
  PN_DEPTH_STORAGE_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                            passes is one of its values (and refused). */
} pn_depth_storage;

/** Which z_ndc a depth buffer's d = 0 and d = 1 are: the projection's clip-space depth convention. */
typedef enum pn_ndc_depth {
  PN_NDC_DEPTH_MINUS_ONE_TO_ONE = 0, /**< OpenGL: z_ndc in [-1, 1], d = z_ndc / 2 + 1/2. */
  PN_NDC_DEPTH_ZERO_TO_ONE = 1,      /**< Direct3D, Vulkan, glClipControl: d = z_ndc (reversed Z included). */
  PN_NDC_DEPTH_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller passes
                                        is one of its values (and refused). */
} pn_ndc_depth;

/** What pn_shade reads and writes (its images: pn_device_image, penumbra/stages.h); pn_shade_desc_init() fills the
 *  defaults. Matrices are 16 floats in OpenGL's
 *  column-major order (glm's memory layout; m[12], m[13], m[14] the translation), for column vectors. */
typedef struct pn_shade_desc {
  size_t size; /**< sizeof(pn_shade_desc) as the caller compiled it (set by pn_shade_desc_init()): fields a later
                    version adds go after these and are read only when `size` holds them. */

  /* The light. */
  pn_light_type light_type;       /**< PN_LIGHT_SPOT (a perspective map) or PN_LIGHT_DIRECTIONAL (orthographic). */
  float light_radius;             /**< Spot: the disk's radius in world units; 0: a point source. */
  float light_angular_radius_deg; /**< Directional: the sun disk's angular radius in degrees, in [0, 45). */

  /* Its depth map, square. */
  pn_device_image light_depth;          /**< light_map_size^2 floats. */
  uint32_t light_map_size;              /**< Texels per side. */
  pn_depth_storage light_depth_storage; /**< PN_DEPTH_WINDOW (default) or PN_DEPTH_LINEAR. */
  pn_ndc_depth light_ndc_depth;         /**< The light projection's convention (PN_NDC_DEPTH_MINUS_ONE_TO_ONE). */
  float light_view[16]; /**< World -> light eye: a rotation and a translation (depths in world units). */
  /** Light eye -> clip: a perspective projection (w_c = -k z_eye; off-centre frusta are fine) for a spot light, an
   *  orthographic one for a directional light, with square texels and a finite far plane; no warps (LiSPSM). A
   *  window value at or beyond the far plane's (the cleared value) is empty, as are linear values not below the far
   *  plane and values that are not finite; a window value in front of the near plane reads as the near plane. */
  float light_projection[16];
  /** The light-eye depth of the projection's near plane as the caller built it (0 with light_depth_far 0: both
   *  recovered from the projection, to float round-off); the moment techniques normalise depths by this range. */
  float light_depth_near;
  float light_depth_far; /**< The light-eye depth of the projection's far plane (0: recovered). */

  /* The camera's G-buffer: width x height pixels, the visibility's size. */
  uint32_t width;  /**< G-buffer and visibility width, pixels. */
  uint32_t height; /**< G-buffer and visibility height, pixels. */
  /** float4 per pixel: world position xyz, w = 0 for background (any other w: covered). Either this or `depth`. */
  pn_device_image positions;
  /** A depth buffer (window values, camera_ndc_depth's convention; camera_clear_depth, values beyond it and NaN are
   *  background), turned into positions through camera_inverse_view_projection at each pixel's centre. */
  pn_device_image depth;
  float camera_inverse_view_projection[16]; /**< With `depth`: clip -> world. */
  pn_ndc_depth camera_ndc_depth;            /**< With `depth` (PN_NDC_DEPTH_MINUS_ONE_TO_ONE). */
  float camera_clear_depth;                 /**< With `depth`: the value it was cleared to: 1, or 0 with reversed Z. */
  /** Optional: float4 per pixel, world normal xyz (any length; w ignored). Without it each pixel's geometric normal
   *  is taken from its neighbours' positions (the cross product of the shorter steps along x and y). */
  pn_device_image normals;

  /** Non-zero: the scene's box, which scales vssm's and savsm's thresholds as a pn_renderer's scene does; 0: the
   *  light's frustum between its near and far planes stands in. */
  int has_scene_bounds;
  float scene_min[3]; /**< With has_scene_bounds: the scene box's least corner. */
  float scene_max[3]; /**< With has_scene_bounds: its greatest corner. */

  /** Output: width x height floats, each pixel's visibility of the light (0..1; 1 for background). Written straight
   *  by the technique when rows are packed from the bottom at offset 0; otherwise through a buffer of penumbra's. */
  pn_device_image visibility;
} pn_shade_desc;

/** The defaults: identity matrices, window depth in OpenGL's convention, camera_clear_depth 1, nothing given. */
PN_API void pn_shade_desc_init(pn_shade_desc* desc);

/** Shades techniques from the caller's maps on one context: keeps the technique's instance and its buffers while the
 *  technique, its parameters and the map size stay the same. Retains its context. Reference counted; calls on one
 *  context are serialised by its lock. */
typedef struct pn_shader pn_shader;

/** A shader on `context` (retained until the shader is freed). */
PN_API pn_status pn_shader_create(pn_context* context, pn_shader** shader);
/** Adds a reference. */
PN_API pn_status pn_shader_retain(pn_shader* shader);
/** Drops a reference; frees at 0. NULL is a no-op. */
PN_API pn_status pn_shader_release(pn_shader* shader);

/** Shades `params`' technique for the light whose map `desc` gives, at the pixels of its G-buffer, into
 *  desc->visibility. The techniques that shade from one map: sm, pcf, pcss, vsm, evsm2, evsm4, esm, msm, savsm, vssm,
 *  lvsm (pn_technique_takes_caller_map); the others draw maps of their own choosing or none and are refused with the
 *  reason. The map's size overrides the parameters' map-size; warp must be none and id-buffer off (a caller's map
 *  carries no ids). Every command goes to the context's queue after a barrier on the wait list; `event` (may be NULL)
 *  completes when the visibility is written. The fits that choose a radius or an exponent per frame (the parameters'
 *  "auto" values) read a few bytes back, waiting for the commands before them, as a pn_renderer's frame does. Inputs
 *  that cannot work are PN_ERROR_INVALID_ARGUMENT naming the field, before any command is enqueued. */
PN_API pn_status pn_shade(pn_shader* shader, const pn_params* params, const pn_shade_desc* desc,
                          cl_uint num_events_in_wait_list, const cl_event* event_wait_list, cl_event* event);

/** What the last successful pn_shade recorded ("penumbra:light-fit", "penumbra:pcf-radius", ... as a frame's
 *  attributes); NULL when absent. Valid until the shader's next call. */
PN_API const char* pn_shader_attribute(const pn_shader* shader, const char* name);

/** Non-zero when the technique called `technique` shades from a caller's map; 0 otherwise, or for an unknown name.
 *  With `reason` non-NULL, *reason is why it cannot (static text; "" when it can or the name is unknown). */
PN_API int pn_technique_takes_caller_map(const char* technique, const char** reason);

#ifdef __cplusplus
}
#endif

#endif
