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
