/* penumbra's C API, all of it: status codes and messages, contexts (penumbra's own or the caller's OpenCL objects),
 * scenes, cameras and lights, techniques and parameters, the renderer and its frames, techniques on the caller's own
 * light map and G-buffer (pn_shade), and the filtering stages on the caller's cl_mem buffers.
 * Link with -lpenumbra (pkg-config penumbra, or CMake's penumbra::penumbra). */
#ifndef PENUMBRA_PENUMBRA_H
#define PENUMBRA_PENUMBRA_H

/** @file
 *  The C API's umbrella header. */

#include "penumbra/context.h"
#include "penumbra/renderer.h"
#include "penumbra/scene.h"
#include "penumbra/shade.h"
#include "penumbra/stages.h"
#include "penumbra/status.h"
#include "penumbra/version.h"

#endif
