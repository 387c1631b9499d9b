/* penumbra's C API: the context every call works in (an OpenCL device, its context, one in-order queue and a
 * program cache), either penumbra's own or built on the caller's OpenCL objects (no second context, no copies). */
#ifndef PENUMBRA_CONTEXT_H
#define PENUMBRA_CONTEXT_H

#include "penumbra/status.h"

/** @file
 *  Contexts: penumbra's own, or one on the caller's cl_context, cl_device_id and cl_command_queue. */

#ifdef __cplusplus
extern "C" {
#endif

/** An OpenCL device, context and in-order queue with penumbra's compiled kernels. Reference counted: created with
 *  a count of 1, pn_context_retain() adds one, pn_context_release() drops one and frees it at 0. Calls on one
 *  context are serialised by a lock the context holds, so several threads may share it. */
typedef struct pn_context pn_context;

/** Opens a device of its own (context and queue with profiling). `device_spec`: NULL or "" for the PENUMBRA_DEVICE
 *  environment variable, else "auto" (first GPU, else first CPU), "cpu", "gpu", a case-insensitive name substring,
 *  or "P:D" (platform index or name substring, device index). PN_ERROR_NO_DEVICE lists the devices found. */
PN_API pn_status pn_context_create(const char* device_spec, pn_context** context);

/** A context on the caller's objects: penumbra creates no context or queue, enqueues all its work on `queue`, and
 *  keeps one retain on each of the three until the context is freed, releasing only those retains. It never calls
 *  clFinish on the queue (its synchronous calls wait on their own events only). The queue must be in order and
 *  belong to `cl_ctx` and `device` (PN_ERROR_INVALID_ARGUMENT otherwise); without CL_QUEUE_PROFILING_ENABLE the pass
 *  times of frames read 0. */
PN_API pn_status pn_context_create_from_cl(cl_context cl_ctx, cl_device_id device, cl_command_queue queue,
                                           pn_context** context);

/** A message from the library about a context's work (a program built, with the time it took, or loaded from the
 *  disk cache) and the caller's `user_data`. Called on the thread of the call that caused it, holding the context's
 *  lock: it must not call into the same context. */
typedef void (*pn_log_callback)(const char* message, void* user_data);

/** A context's settings beyond the OpenCL objects; pn_context_options_init() gives the defaults, which read the
 *  environment as the command line does. `size` is sizeof(pn_context_options) as the caller compiled it: fields a
 *  later version adds go after these, and a call reads only the fields that lie within `size`. */
typedef struct pn_context_options {
  size_t size;              /**< sizeof(pn_context_options), set by pn_context_options_init(). */
  const char* device;       /**< Own contexts: pn_context_create()'s device_spec (NULL: PENUMBRA_DEVICE, else auto). */
  const char* cache_dir;    /**< Folder for compiled programs on disk; NULL: PENUMBRA_CACHE_DIR; "": no disk cache. */
  uint64_t local_mem_limit; /**< Bytes of local memory the kernels plan with (at most the device's); 0:
                                 PENUMBRA_LOCAL_MEM_LIMIT, else the device's. */
  const char* layouts;      /**< Work-group layouts: "gpu", "nvidia", or "" (the device's own table); NULL:
                                 PENUMBRA_LAYOUTS. */
  pn_log_callback log;      /**< NULL: no messages. */
  void* log_user_data;      /**< Passed to `log`. */
  void (*log_release)(void* log_user_data); /**< Called with `log_user_data` once the context is freed, or when its
                                                 creation fails; NULL: nothing to release. */
} pn_context_options;

/** The defaults: size set, every other field NULL or 0 (the environment's settings, no messages). */
PN_API void pn_context_options_init(pn_context_options* options);

/** pn_context_create() with `options` (NULL: the defaults). PN_ERROR_INVALID_ARGUMENT for a `size` smaller than the
 *  first version's or a bad layouts name. */
PN_API pn_status pn_context_create_with_options(const pn_context_options* options, pn_context** context);

/** pn_context_create_from_cl() with `options` (NULL: the defaults; `device` must be NULL: the caller's device is
 *  the one). */
PN_API pn_status pn_context_create_from_cl_with_options(cl_context cl_ctx, cl_device_id device, cl_command_queue queue,
                                                        const pn_context_options* options, pn_context** context);

/** Builds, or loads from the disk cache, the programs the named items run at their defaults, so that later calls do
 *  not build them (a build takes 0.1-0.5 s a program): `names` holds `count` of "sm", "pcss", ... (every technique),
 *  "moments", "blur", "sat", "pyramid", "reduce" (the stages) or "all". Each item runs once on a small input on the
 *  context's queue (a technique a 32x24 frame of builtin:box under its area light) and the call waits for those
 *  commands alone. Settings away from the defaults (another storage, filter, pattern) may still build a program on
 *  first use. PN_ERROR_INVALID_ARGUMENT naming an unknown item, before any work. */
PN_API pn_status pn_context_prebuild(pn_context* context, const char* const* names, size_t count);

/** Adds a reference. PN_ERROR_INVALID_ARGUMENT for NULL. */
PN_API pn_status pn_context_retain(pn_context* context);
/** Drops a reference; at 0 frees the context, releasing its retains of the OpenCL objects. NULL is a no-op. */
PN_API pn_status pn_context_release(pn_context* context);

/** The OpenCL context (not retained for the caller: valid while the pn_context lives). NULL for a NULL context. */
PN_API cl_context pn_context_cl_context(const pn_context* context);
/** The OpenCL device (not retained for the caller). */
PN_API cl_device_id pn_context_cl_device(const pn_context* context);
/** The queue penumbra enqueues on (not retained for the caller). */
PN_API cl_command_queue pn_context_cl_queue(const pn_context* context);
/** The device's name ("cpu-haswell-AMD EPYC ..."), valid while the context lives. */
PN_API const char* pn_context_device_name(const pn_context* context);

#ifdef __cplusplus
}
#endif

#endif
