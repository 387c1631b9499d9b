/* penumbra's C API: status codes, the thread-local error message, the version, and the export macro every public
 * function carries. No exception crosses the C boundary: each function catches everything and returns a status. */
#ifndef PENUMBRA_STATUS_H
#define PENUMBRA_STATUS_H

#include <CL/cl.h>
#include <stddef.h>
#include <stdint.h>

#include "penumbra/version.h"

/** @file
 *  Status codes, error messages and the library version. */

/* The library is built with hidden symbols; these are the ones it exports. */
#if defined(__GNUC__)
#define PN_API __attribute__((visibility("default")))
#else
#define PN_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/** What a call returned. Every failure also sets the calling thread's message (pn_last_error_message()) and writes
 *  nothing through the call's out-parameters: a handle, pointer or value the caller passed in stays as it was (a live
 *  handle is neither overwritten nor leaked). */
typedef enum pn_status {
  PN_SUCCESS = 0,                 /**< The call did what it says. */
  PN_ERROR_INVALID_ARGUMENT = 1,  /**< A bad value, size, name, handle or buffer; no kernel was enqueued. */
  PN_ERROR_NO_DEVICE = 2,         /**< No OpenCL device, or none matching the device spec. */
  PN_ERROR_OPENCL = 3,            /**< An OpenCL call failed; pn_last_cl_error() holds its code. */
  PN_ERROR_BUILD = 4,             /**< A kernel did not compile; the message holds the device, options and log. */
  PN_ERROR_SCENE = 5,             /**< A scene is missing, malformed or unsupported; the message names the file. */
  PN_ERROR_RUNTIME = 6,           /**< Anything else the library reports (a file not written, a missing feature). */
  PN_ERROR_OUT_OF_MEMORY = 7,     /**< Memory ran out, or a frame needs more than the device has (memory plan). */
  PN_ERROR_UNKNOWN = 8,           /**< An unexpected failure; the message says what is known. */
  PN_STATUS_MAX_ENUM = 0x7FFFFFFF /**< Not a status: keeps the type as wide as int, like the other enums. */
} pn_status;

/** The name of a status ("PN_ERROR_OPENCL"); "PN_UNKNOWN_STATUS" for a value that is none of them. */
PN_API const char* pn_status_name(pn_status status);

/** The message of the last call that failed on this thread ("" when none has). Valid until the next failing call on
 *  the same thread; a successful call leaves it alone. */
PN_API const char* pn_last_error_message(void);

/** The OpenCL error code (CL_OUT_OF_RESOURCES, ...) of the last call that failed on this thread with
 *  PN_ERROR_OPENCL; CL_SUCCESS after any other failure. */
PN_API cl_int pn_last_cl_error(void);

/** The library's version, "MAJOR.MINOR.PATCH" (the same as the CLI's `penumbra --version`, the pkg-config file and
 *  the `penumbra:version` attribute of every EXR it writes). */
PN_API const char* pn_version(void);

#ifdef __cplusplus
}
#endif

#endif
