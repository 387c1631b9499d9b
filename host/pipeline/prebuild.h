// Building a context's programs before the calls that use them (the library's pn_context_prebuild): a program is
// otherwise built on first use, inside a call an engine expects to return at once (0.1-0.5 s a program on PoCL).
#pragma once

#include <string>
#include <vector>

#include "host/cl/context.h"

namespace penumbra {

// What prebuild() takes: every technique's name, the stages' ("moments", "blur", "sat", "pyramid", "reduce") and
// "all" (every one of them).
std::vector<std::string> prebuildNames();

// Builds (or loads from the context's disk cache) the programs each named item runs at its defaults, by running it
// once on a small input on the context's queue and waiting for it: a technique renders a 32x24 frame of builtin:box
// under its area light (the scene, G-buffer, fit and preview programs come with it); a stage runs every variant of
// its defaults (moments: every kind in fp32 and half; blur: Gaussian and box, both plans; sat: every precision the
// device has; pyramid: moment mips and min-max; reduce: the Lloyd statistics). Settings away from the defaults
// (another storage, filter or pattern) may still build a program of their own on first use. Throws
// std::invalid_argument naming an unknown item and the known ones, before any work.
void prebuild(Context& ctx, const std::vector<std::string>& names);

}  // namespace penumbra
