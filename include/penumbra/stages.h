/* penumbra's C API: the filtering stages on the caller's buffers, in the manner of CLBlast: cl_mem in and out, an
 * event wait list in, an event out, nothing finished, copied or released behind the caller's back. Every stage
 * enqueues on the context's queue and returns at once: a barrier waits for `wait_list`, the stage's kernels follow,
 * and `event` (when not NULL) receives a new marker event that completes with them (the caller releases it). The
 * queue is flushed, never finished. Buffers must belong to the context's cl_context and hold at least the elements
 * a stage documents; scratch and temporary buffers the caller does not pass are penumbra's, freed when the stage's
 * commands complete. To work on part of a buffer, pass a sub-buffer (clCreateSubBuffer). */
#ifndef PENUMBRA_STAGES_H
#define PENUMBRA_STAGES_H

#include "penumbra/context.h"

/** @file
 *  Moments, blur, summed-area tables, pyramids and Lloyd reductions on cl_mem buffers. */

#ifdef __cplusplus
extern "C" {
#endif

/** An image of `width` x `height` texels of `channels` interleaved floats (1, 2 or 4), rows one after another with
 *  no padding; each side at most 32768. */
typedef struct pn_image_shape {
  uint32_t width;    /**< Texels per row. */
  uint32_t height;   /**< Rows. */
  uint32_t channels; /**< 1, 2 or 4 (use 4 for 3). */
} pn_image_shape;

/** The moment encodings of the moment-based shadow maps. */
typedef enum pn_moment_kind {
  PN_MOMENTS_VSM = 0,   /**< (z, z^2): 2 channels. */
  PN_MOMENTS_EVSM2 = 1, /**< (e^cz, e^2cz), positive warp: 2 channels. */
  PN_MOMENTS_EVSM4 = 2, /**< Positive and negative warps: 4 channels. */
  PN_MOMENTS_LVSM = 3,  /**< One (z, z^2) plane per layer, each over its own depth interval: 2 channels a plane. */
  PN_MOMENTS_MSM = 4,   /**< Hamburger 4-moment, quantised (Peters & Klein 2015): 4 channels. */
  PN_MOMENTS_ESM = 5,   /**< ESM, 1 channel: e^(c (z - 1)) for esm_exponent c in [1, 80], else z itself, which
                             pn_blur_moments then blurs in log space (the D of e^(c D) = the blurred e^(c z)). */
  PN_MOMENT_KIND_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                          passes is one of its values (and refused). */
} pn_moment_kind;

/** How moments are stored: fp32 (float elements) or IEEE half (cl_half elements, rounded to nearest even). */
typedef enum pn_moment_storage {
  PN_STORAGE_FLOAT32 = 0,                 /**< float. */
  PN_STORAGE_FLOAT16 = 1,                 /**< cl_half; EVSM exponents are clamped to 5.54, ESM's to 8. */
  PN_MOMENT_STORAGE_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                             passes is one of its values (and refused). */
} pn_moment_storage;

/** One LVSM layer: the interval [p, q] of normalised depth it resolves. */
typedef struct pn_lvsm_layer {
  float p; /**< Start. */
  float q; /**< End (> p). */
} pn_lvsm_layer;

/** The moments stage's settings (pn_moments_config_init() gives the defaults). */
typedef struct pn_moments_config {
  size_t size; /**< sizeof(pn_moments_config) as the caller compiled it (set by pn_moments_config_init()): fields a
                  later version adds go after these and are read only when `size` holds them. */
  pn_moment_kind kind;         /**< Encoding. */
  float depth_near;            /**< Light depth mapped to 0. */
  float depth_far;             /**< Light depth mapped to 1 (> depth_near). */
  float evsm_positive;         /**< EVSM positive exponent, clamped to the storage's limit. */
  float evsm_negative;         /**< EVSM negative exponent, clamped likewise. */
  pn_moment_storage storage;   /**< Element type of the output. */
  const pn_lvsm_layer* layers; /**< LVSM only: its layers. */
  size_t layer_count;          /**< LVSM only: 1..16 layers. */
  float esm_exponent;          /**< ESM's c of e^(c z), z in [0, 1]: 0..1000, at most 8 with half storage. */
} pn_moments_config;

/** VSM, depth [0, 1], EVSM exponents 40 and 5, ESM's 80, fp32, no layers. */
PN_API void pn_moments_config_init(pn_moments_config* config);
/** Floats (or halves) per texel of one plane of `kind`: 1 (ESM), 2 or 4; 0 for a value that is not a pn_moment_kind. */
PN_API uint32_t pn_moment_channels(pn_moment_kind kind);

/** Moments of `depth` (width * height floats of light depth; NaN and infinities count as the far value) into `out`
 *  (planes * width * height * pn_moment_channels(kind) elements of the storage type, texels interleaved, LVSM planes
 *  one after another). Half storage takes every kind but LVSM. */
PN_API pn_status pn_moments(pn_context* context, cl_mem depth, uint32_t width, uint32_t height,
                            const pn_moments_config* config, cl_mem out, cl_uint num_events_in_wait_list,
                            const cl_event* event_wait_list, cl_event* event);

/** The blur's filter. */
typedef enum pn_blur_filter {
  PN_BLUR_GAUSSIAN = 0,                /**< Gaussian of standard deviation `sigma` (taps out to ceil(3 sigma)). */
  PN_BLUR_BOX = 1,                     /**< Box of 2 `radius` + 1 taps. */
  PN_BLUR_FILTER_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                          passes is one of its values (and refused). */
} pn_blur_filter;

/** How the blur runs (the result is the same filter either way). */
typedef enum pn_blur_method {
  PN_BLUR_AUTO = 0,         /**< Direct taps for small footprints, running sums for large ones. */
  PN_BLUR_DIRECT = 1,       /**< A weighted sum of every tap (radius at most 128). */
  PN_BLUR_RUNNING_SUMS = 2, /**< Box running sums, cost independent of the radius (a Gaussian as three boxes). */
  PN_BLUR_METHOD_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                          passes is one of its values (and refused). */
} pn_blur_method;

/** The blur's settings (pn_blur_config_init() gives the defaults). */
typedef struct pn_blur_config {
  size_t size; /**< sizeof(pn_blur_config) as the caller compiled it (set by pn_blur_config_init()): fields a later
                   version adds go after these and are read only when `size` holds them. */
  pn_blur_filter filter; /**< Gaussian or box. */
  float sigma;           /**< Gaussian: standard deviation in texels (> 0). */
  int radius;            /**< Box: half-width in texels (>= 0). */
  pn_blur_method method; /**< How it runs. */
} pn_blur_config;

/** Gaussian, sigma 1, radius 1, auto. */
PN_API void pn_blur_config_init(pn_blur_config* config);

/** Separable blur with clamp-to-edge of `in` into `out` (may be the same buffer), both `shape` floats, through
 *  `scratch` (as many floats; NULL: a temporary of penumbra's). */
PN_API pn_status pn_blur(pn_context* context, cl_mem in, cl_mem out, cl_mem scratch, const pn_image_shape* shape,
                         const pn_blur_config* config, cl_uint num_events_in_wait_list, const cl_event* event_wait_list,
                         cl_event* event);

/** The moments of `depth` blurred, without the unblurred moments ever being written: bit for bit pn_moments then
 *  pn_blur over width x height x pn_moment_channels(kind). Any kind but LVSM; `out` holds elements of the storage
 *  type; ESM with an exponent outside [1, 80] takes direct blurs only (radius at most 32 under PN_BLUR_AUTO). `scratch`
 *  (NULL: a temporary) holds pn_blur_moments_scratch() floats. */
PN_API pn_status pn_blur_moments(pn_context* context, cl_mem depth, uint32_t width, uint32_t height,
                                 const pn_moments_config* moments, const pn_blur_config* blur, cl_mem out,
                                 cl_mem scratch, cl_uint num_events_in_wait_list, const cl_event* event_wait_list,
                                 cl_event* event);
/** Floats of scratch pn_blur_moments needs for these settings on this context's device. */
PN_API pn_status pn_blur_moments_scratch(pn_context* context, uint32_t width, uint32_t height,
                                         const pn_moments_config* moments, const pn_blur_config* blur, size_t* floats);

/** The summed-area table's element type. */
typedef enum pn_sat_precision {
  PN_SAT_FLOAT32 = 0, /**< float, offset to zero mean (the offset goes to the `offset` buffer). */
  PN_SAT_FIXED32 = 1, /**< uint32_t two's complement of round(x 2^fraction_bits), modular: box sums exact. */
  PN_SAT_FIXED64 = 2, /**< uint64_t likewise. */
  PN_SAT_FLOAT64 = 3, /**< double (devices with fp64 only). */
  PN_SAT_PRECISION_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                            passes is one of its values (and refused). */
} pn_sat_precision;

/** The scan that computes the table. */
typedef enum pn_sat_algorithm {
  PN_SAT_AUTO = 0,                       /**< Tiled on GPUs, lines on CPUs. */
  PN_SAT_TILED = 1,                      /**< Three-pass tiled scan (Nehab et al. 2011). */
  PN_SAT_LINES = 2,                      /**< Row then column line scans. */
  PN_SAT_HENSLEY = 3,                    /**< Recursive doubling (Hensley et al. 2005). */
  PN_SAT_ALGORITHM_MAX_ENUM = 0x7FFFFFFF /**< Not a value: makes the type as wide as int, so that any int a C caller
                                            passes is one of its values (and refused). */
} pn_sat_algorithm;

/** The SAT's settings (pn_sat_config_init() gives the defaults). */
typedef struct pn_sat_config {
  size_t size; /**< sizeof(pn_sat_config) as the caller compiled it (set by pn_sat_config_init()): fields a later
                   version adds go after these and are read only when `size` holds them. */
  pn_sat_precision precision; /**< Element type of the table. */
  pn_sat_algorithm algorithm; /**< Scan. */
  int fraction_bits;          /**< Fixed point: fraction bits; -1 for 16 (fixed32) or 32 (fixed64). */
  int zero_mean;              /**< fp32: subtract the per-channel mean of the finite texels first. */
  int has_offset;             /**< fp32: subtract `offset` instead of the mean. */
  float offset[4];            /**< With has_offset: the per-channel offset. */
} pn_sat_config;

/** fp32, auto, default fraction bits, zero mean. */
PN_API void pn_sat_config_init(pn_sat_config* config);

/** The summed-area table of `image` (`shape` floats) into `table` (`shape` elements of the precision's type:
 *  table[y][x] sums the texels [0, x] x [0, y]); the fp32 offset subtracted before summing into `offset` (4 floats;
 *  zeros for the other precisions; NULL: not kept). */
PN_API pn_status pn_sat(pn_context* context, cl_mem image, const pn_image_shape* shape, const pn_sat_config* config,
                        cl_mem table, cl_mem offset, cl_uint num_events_in_wait_list, const cl_event* event_wait_list,
                        cl_event* event);
/** The most fraction bits (at most 30, resp. 62) with which every box sum of up to `max_box_texels` texels of
 *  |value| <= `max_abs_value` stays exact in `precision` (fixed32 or fixed64). */
PN_API pn_status pn_sat_fraction_bits(pn_sat_precision precision, double max_box_texels, double max_abs_value,
                                      int* fraction_bits);

/** One level of a pyramid within its buffer. */
typedef struct pn_pyramid_level {
  uint32_t offset; /**< First texel of the level. */
  uint32_t width;  /**< Texels per row. */
  uint32_t height; /**< Rows. */
  uint32_t pad;    /**< Unused. */
} pn_pyramid_level;

/** The levels `first_level`.. down to 1x1 of a width x height base (each halves the last, floor, at least 1), one
 *  after another in one buffer: fills up to `capacity` of `levels` (may be NULL with 0), and sets `level_count` and
 *  `texels` (the buffer's size in texels; either may be NULL). */
PN_API pn_status pn_pyramid_layout(uint32_t width, uint32_t height, uint32_t first_level, pn_pyramid_level* levels,
                                   size_t capacity, size_t* level_count, size_t* texels);

/** Mip levels 1.. of `base` (`shape` elements, level 0) into `mips` (pn_pyramid_layout(w, h, 1) texels times
 *  channels elements): exact area averages, odd sizes keeping the mean. Elements are floats, or halves with
 *  PN_STORAGE_FLOAT16 (averaged in fp32, stored rounded to nearest even). */
PN_API pn_status pn_moment_mips(pn_context* context, cl_mem base, const pn_image_shape* shape,
                                pn_moment_storage storage, cl_mem mips, cl_uint num_events_in_wait_list,
                                const cl_event* event_wait_list, cl_event* event);

/** Levels 0.. of the min-max pyramid of `depth` (width * height floats) into `out` (pn_pyramid_layout(w, h, 0)
 *  texels of two floats, min then max); background and NaN texels are the empty interval (+inf, -inf). */
PN_API pn_status pn_minmax_pyramid(pn_context* context, cl_mem depth, uint32_t width, uint32_t height, cl_mem out,
                                   cl_uint num_events_in_wait_list, const cl_event* event_wait_list, cl_event* event);

/** Per-cluster statistics of one Lloyd relaxation step. */
typedef struct pn_lloyd_stats {
  float sum_w;      /**< Sum of the weights of the cluster's samples. */
  float sum_wx;     /**< Sum of w x. */
  float sum_wx2;    /**< Sum of w x^2. */
  uint32_t samples; /**< Samples counted (finite x, finite w > 0). */
} pn_lloyd_stats;

/** Weighted statistics of the samples (x[i], w[i]), i < count (two buffers of floats), by cluster: cluster k holds
 *  the x with exactly k of the `clusters` - 1 ascending `boundaries` (floats) <= x; `clusters` is 1..16. `out`
 *  receives `clusters` pn_lloyd_stats. Deterministic: the same sums on every run and device. */
PN_API pn_status pn_lloyd_stats_reduce(pn_context* context, cl_mem x, cl_mem w, size_t count, cl_mem boundaries,
                                       uint32_t clusters, cl_mem out, cl_uint num_events_in_wait_list,
                                       const cl_event* event_wait_list, cl_event* event);

/** One of the caller's float images. Texel (x, y), y counted from the bottom row, lies at byte
 *  offset + row * row_pitch + x * texel size of `memory`, row = top_down ? height - 1 - y : y. */
typedef struct pn_device_image {
  /** A buffer of the pn_context's cl_context, or (where a call reads the image) a cl_image2d of CL_FLOAT texels of
   *  the image's size and channels (CL_R, CL_RG or CL_RGBA; pn_shade: CL_R depth, CL_RGBA positions and normals),
   *  copied once into a buffer of penumbra's after the wait list (the image's own rows: offset and row_pitch are
   *  then ignored); NULL: not given. Retained for the call only. */
  cl_mem memory;
  size_t offset;    /**< Bytes before the first row in memory; a multiple of 4. */
  size_t row_pitch; /**< Bytes from one row in memory to the next, a multiple of 4; 0: rows packed. */
  int top_down;     /**< Non-zero: the first row in memory is the image's top row (Direct3D, Vulkan, image files);
                         0: its bottom row (OpenGL, OpenCL images, penumbra's own buffers). */
} pn_device_image;

/** Copies width x height texels of `texel_floats` four-byte words each (1 to 4: floats, or pairs of halves) from
 *  `src`'s layout into `dst`'s (a buffer): the stages read and write packed rows from the bottom at offset 0 (a
 *  pn_device_image of zeros), so an engine's image at an offset, with a row pitch or rows from the top (or a
 *  cl_image2d) is packed into a buffer before a stage and a stage's result unpacked into the engine's layout after it,
 *  chained by events. One pass on the device (8 bytes per word), after a barrier on the wait list. The images may not
 *  overlap. */
PN_API pn_status pn_image_copy(pn_context* context, const pn_device_image* src, const pn_device_image* dst,
                               uint32_t width, uint32_t height, uint32_t texel_floats, cl_uint num_events_in_wait_list,
                               const cl_event* event_wait_list, cl_event* event);

#ifdef __cplusplus
}
#endif

#endif
