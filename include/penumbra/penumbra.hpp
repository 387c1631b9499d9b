// penumbra's C++ API, all of it (C++17, header-only over the C API in penumbra/penumbra.h): penumbra::Context,
// Scene, Camera, Light, Params, Renderer, Frame, Shader (techniques on the caller's map and G-buffer), the stages on
// cl_mem buffers, and penumbra::Error for failures.
#pragma once

/// @file
/// The C++ API's umbrella header.

#include "penumbra/context.hpp"
#include "penumbra/error.hpp"
#include "penumbra/penumbra.h"
#include "penumbra/renderer.hpp"
#include "penumbra/scene.hpp"
#include "penumbra/shade.hpp"
#include "penumbra/stages.hpp"
