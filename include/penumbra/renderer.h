/* penumbra's C API: the shadow techniques and their parameters, the renderer (camera G-buffer, one technique per
 * light, shaded preview) and the frames it returns as host channels and as OpenCL buffers. */
#ifndef PENUMBRA_RENDERER_H
#define PENUMBRA_RENDERER_H

#include "penumbra/context.h"
#include "penumbra/scene.h"

/** @file
 *  Techniques, parameters, the renderer and its frames. */

#ifdef __cplusplus
extern "C" {
#endif

/** One parameter of a technique, as the registry declares it. Strings are static (valid for the program's life). */
typedef struct pn_param_info {
  const char* name;         /**< "pcf-radius" (the CLI's option without dashes). */
  const char* help;         /**< One line. */
  double default_value;     /**< Numbers; a choice's index into `choices`; outside [min, max]: "auto" (-1). */
  double min;               /**< Smallest valid number (inclusive). */
  double max;               /**< Largest valid number (inclusive). */
  const char* choices;      /**< Named choices, comma-separated ("uniform,adaptive"); "" for numbers and text. */
  int is_text;              /**< Non-zero: free-form text (a list such as "0.2,0.5"). */
  const char* text_default; /**< Text parameters: the default; "" otherwise. */
} pn_param_info;

/** Techniques in the registry ("sm", "pcf", "pcss", ...), in the order the CLI lists them. */
PN_API size_t pn_technique_count(void);
/** Name of technique `index`; NULL past the end. */
PN_API const char* pn_technique_name(size_t index);
/** One-line description of technique `index`; NULL past the end. */
PN_API const char* pn_technique_description(size_t index);
/** Parameters of the technique called `technique`; 0 for an unknown name (which also sets the error). */
PN_API size_t pn_technique_param_count(const char* technique);
/** Parameter `index` of `technique`. */
PN_API pn_status pn_technique_param(const char* technique, size_t index, pn_param_info* info);

/** A technique and values for its parameters. Reference counted; not for concurrent modification. */
typedef struct pn_params pn_params;

/** The technique called `technique` with every parameter at its default. PN_ERROR_INVALID_ARGUMENT lists the known
 *  techniques. */
PN_API pn_status pn_params_create(const char* technique, pn_params** params);
/** Adds a reference. */
PN_API pn_status pn_params_retain(pn_params* params);
/** Drops a reference; frees at 0. NULL is a no-op. */
PN_API pn_status pn_params_release(pn_params* params);
/** Sets a parameter from text, as the CLI's option would ("0.002", "adaptive"); the message names the parameter and
 *  the valid range or choices. */
PN_API pn_status pn_params_set(pn_params* params, const char* name, const char* value);
/** A number's value, or a choice's index (a text parameter is PN_ERROR_INVALID_ARGUMENT: see pn_params_describe). */
PN_API pn_status pn_params_get(const pn_params* params, const char* name, double* value);
/** The technique's name; valid while `params` lives. */
PN_API const char* pn_params_technique(const pn_params* params);
/** "bias=0.002 pcf-radius=2": every parameter, as frames record them; valid until `params` next changes. */
PN_API const char* pn_params_describe(const pn_params* params);

/** One light of a frame and the technique that shadows it. */
typedef struct pn_frame_light {
  const pn_light* light;   /**< The light (copied by the call). */
  const pn_params* params; /**< Its technique and parameters; NULL: the call's `params`. */
} pn_frame_light;

/** Draws frames of one scene on one context: uploads the triangles once and keeps each light's technique (and its
 *  device buffers) while the technique and parameters stay the same. Retains its context and scene. Reference
 *  counted; one render at a time (renders of one context are serialised by its lock). */
typedef struct pn_renderer pn_renderer;

/** A rendered frame: host channels and a device copy of each light's visibility. Immutable; reference counted. */
typedef struct pn_frame pn_frame;

/** A renderer of `scene` on `context` (both retained until the renderer is freed). */
PN_API pn_status pn_renderer_create(pn_context* context, pn_scene* scene, pn_renderer** renderer);
/** Adds a reference. */
PN_API pn_status pn_renderer_retain(pn_renderer* renderer);
/** Drops a reference; frees at 0. NULL is a no-op. */
PN_API pn_status pn_renderer_release(pn_renderer* renderer);

/** Renders one frame, synchronously: it returns when the frame's host channels and device buffers are complete
 *  (it waits on its own events, never finishes the queue).
 *  - `camera`: NULL for pn_scene_default_camera() (at its size).
 *  - `lights`, `light_count`: the frame's lights, each with its own technique or `params`; NULL and 0 for the
 *    scene's lights, else the framing light, all shadowed by `params` (as the CLI does without --light).
 *  - `params`: the technique of the lights that name none; may be NULL only when every light names one.
 *  A point light is shadowed as the six faces of a cube around it, with every technique
 *  (docs/techniques/point-lights.md); a light its technique cannot shadow is refused (PN_ERROR_INVALID_ARGUMENT)
 *  before any work. */
PN_API pn_status pn_renderer_render(pn_renderer* renderer, const pn_camera* camera, const pn_frame_light* lights,
                                    size_t light_count, const pn_params* params, pn_frame** frame);

/** How a frame's host channels are made (pn_render_options). */
typedef enum pn_frame_channels {
  /** Every channel, the technique's debug channels included, downloaded before the render call returns. */
  PN_FRAME_CHANNELS_ALL = 0,
  /** None downloaded by the render: pn_frame_channel reads the channel it is asked for from the frame's device buffers
   *  the first time (waiting for them), and keeps it; no debug channels. */
  PN_FRAME_CHANNELS_ON_REQUEST = 1,
  PN_FRAME_CHANNELS_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                             passes is one of its values (and refused). */
} pn_frame_channels;

/** What a frame of pn_renderer_enqueue makes besides each light's visibility (always made), as bits of
 *  pn_render_options::outputs. A caller that reads the visibility alone (an engine shading the frame itself) leaves
 *  the rest out: no preview shading pass, no copies of the G-buffer, nothing more to read back. */
typedef enum pn_frame_output_bits {
  PN_FRAME_OUTPUT_PREVIEW_BIT = 1,  /**< The shaded preview: PN_FRAME_PREVIEW and the channels R, G, B, A. */
  PN_FRAME_OUTPUT_SURFACES_BIT = 2, /**< PN_FRAME_POSITION, PN_FRAME_NORMAL, PN_FRAME_DEPTH and the channels P.X/Y/Z,
                                         N.X/Y/Z, depth.Z (the frame's copies of the G-buffer). */
  PN_FRAME_OUTPUT_DEBUG_BIT = 4,    /**< The first light's technique's debug channels (PN_FRAME_CHANNELS_ALL). */
  PN_FRAME_OUTPUTS_ALL = 7,         /**< Everything (the default). */
  PN_FRAME_OUTPUT_BITS_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int. */
} pn_frame_output_bits;

/** pn_renderer_enqueue's settings; pn_render_options_init() gives the defaults. */
typedef struct pn_render_options {
  size_t size; /**< sizeof(pn_render_options) as the caller compiled it (set by pn_render_options_init()): fields a
                    later version adds go after these and are read only when `size` holds them. */
  pn_frame_channels channels; /**< PN_FRAME_CHANNELS_ON_REQUEST (the default) or PN_FRAME_CHANNELS_ALL. */
  /** NULL, or one entry per light of the call: a buffer of the context's cl_context of at least width x height
   *  floats that the light's visibility (rows bottom-up) is written into instead of a buffer of the frame's (NULL
   *  entries: the frame's own). pn_frame_visibility_buffer then gives that buffer, which the frame retains; its
   *  channels on request read it, so write it only once they are read. */
  const cl_mem* visibility;
  size_t visibility_count; /**< Entries in `visibility` (0, or the call's light count). */
  /** pn_frame_output_bits: what the frame makes besides each light's visibility (PN_FRAME_OUTPUTS_ALL, the default).
   *  Added in 0.4: read only when `size` holds it, so a caller compiled against 0.3 gets everything. An output left
   *  out is not there: pn_frame_device_buffer refuses it, and its channels are not among the frame's. */
  unsigned outputs;
} pn_render_options;

/** The defaults: channels on request, visibility into the frame's own buffers, every output. */
PN_API void pn_render_options_init(pn_render_options* options);

/** pn_renderer_render without waiting for the frame: enqueues a barrier on the wait list, then the frame, on the
 *  context's queue, and returns `frame` and `event` (may be NULL; completes when the frame's device buffers and the
 *  caller's visibility buffers are written). `options` (NULL: the defaults) chooses the host channels and the
 *  outputs. The renderer reads back what its fits measure while it records the frame (the visible receivers' box the
 *  light's map is fitted to, the map size under map-size auto, auto radii and exponents): the call waits on the host
 *  for the commands before each such read, the wait list's included, so the wait list's events must complete without
 *  the caller's further action (user events the caller sets only after the call would never let it return). It waits
 *  for nothing after the last fit: the shading, the copies into the outputs, the channels (on request) and the pass
 *  times (resolved when first asked for) are not waited for. */
PN_API pn_status pn_renderer_enqueue(pn_renderer* renderer, const pn_camera* camera, const pn_frame_light* lights,
                                     size_t light_count, const pn_params* params, const pn_render_options* options,
                                     cl_uint num_events_in_wait_list, const cl_event* event_wait_list, cl_event* event,
                                     pn_frame** frame);

/** Adds a reference. */
PN_API pn_status pn_frame_retain(pn_frame* frame);
/** Drops a reference; frees at 0, releasing the device buffers it holds. NULL is a no-op. */
PN_API pn_status pn_frame_release(pn_frame* frame);
/** Width in pixels; 0 for NULL. */
PN_API int pn_frame_width(const pn_frame* frame);
/** Height in pixels; 0 for NULL. */
PN_API int pn_frame_height(const pn_frame* frame);
/** Channels: R, G, B, A (the shaded preview; A = 1 where a surface is seen), visibility.Y (the first light's),
 *  visibility.LAYER.Y per light, P.X/Y/Z, N.X/Y/Z, depth.Z and the first light's technique's debug channels. */
PN_API size_t pn_frame_channel_count(const pn_frame* frame);
/** Name of channel `index`; NULL past the end. */
PN_API const char* pn_frame_channel_name(const pn_frame* frame, size_t index);
/** The channel called `name`: width * height floats, row 0 the top row, valid while the frame lives. A missing
 *  channel is PN_ERROR_INVALID_ARGUMENT listing those the frame has. A frame whose channels come on request reads the
 *  channel from its device buffers the first time (a blocking read on the context's queue, under its lock). */
PN_API pn_status pn_frame_channel(const pn_frame* frame, const char* name, const float** data);
/** The frame's lights, in the order they were given. */
PN_API size_t pn_frame_light_count(const pn_frame* frame);
/** The EXR layer of light `index` ("light", or its name): its channel is "visibility.LAYER.Y". */
PN_API const char* pn_frame_light_layer(const pn_frame* frame, size_t index);
/** Light `index`'s visibility on the device: a buffer of width * height floats in the context's cl_context, rows
 *  bottom-up (row 0 the bottom row, as OpenCL and OpenGL framebuffers). Owned by the frame (valid while it lives;
 *  clRetainMemObject it to keep it longer). */
PN_API pn_status pn_frame_visibility_buffer(const pn_frame* frame, size_t index, cl_mem* buffer);

/** The frame's other device outputs (pn_frame_device_buffer): width * height elements each, rows bottom-up. */
typedef enum pn_frame_output {
  PN_FRAME_PREVIEW = 0,  /**< cl_float4 per pixel: the shaded preview's R, G, B, A (the channels R, G, B, A). */
  PN_FRAME_POSITION = 1, /**< cl_float4: world position xyz; w = 1 where a surface is seen, 0 for background. */
  PN_FRAME_NORMAL = 2,   /**< cl_float4: unit world shading normal xyz; w = the geometric facing sign. */
  PN_FRAME_DEPTH = 3,    /**< float: linear camera depth (the channel depth.Z); +infinity for background. */
  PN_FRAME_OUTPUT_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                           passes is one of its values (and refused). */
} pn_frame_output;

/** One of the frame's device outputs in the context's cl_context, owned by the frame like its visibility buffers
 *  (valid while it lives; clRetainMemObject it to keep it longer). An unknown `output` is
 *  PN_ERROR_INVALID_ARGUMENT. */
PN_API pn_status pn_frame_device_buffer(const pn_frame* frame, pn_frame_output output, cl_mem* buffer);
/** A provenance attribute ("penumbra:technique", "penumbra:version", "penumbra:light", ...); NULL when absent. */
PN_API const char* pn_frame_attribute(const pn_frame* frame, const char* name);
/** Named passes with device times, in recording order (a frame of pn_renderer_enqueue: resolved at the first call,
 *  which waits for the frame). */
PN_API size_t pn_frame_pass_count(const pn_frame* frame);
/** Pass `index`: its name ("shade/pcss_visibility") and summed device time (0 without queue profiling). */
PN_API pn_status pn_frame_pass(const pn_frame* frame, size_t index, const char** name, double* milliseconds);
/** Writes every channel and attribute to an OpenEXR file (32-bit float, ZIP), as `penumbra render` does. */
PN_API pn_status pn_frame_save_exr(const pn_frame* frame, const char* path);

#ifdef __cplusplus
}
#endif

#endif
