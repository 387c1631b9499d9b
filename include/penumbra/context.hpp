// penumbra's C++ API: the context (pn_context): penumbra's own device and queue, or the caller's OpenCL objects.
#pragma once

#include <string>

#include "penumbra/context.h"
#include "penumbra/error.hpp"

/// @file
/// penumbra::Context.

namespace penumbra {
inline namespace v0 {

/// An OpenCL device, context and in-order queue with penumbra's kernels (see pn_context). Copies share one context.
class Context {
 public:
  /// Opens a device of its own: `device` as pn_context_create() takes it ("" for PENUMBRA_DEVICE, else auto).
  explicit Context(const std::string& device = {}) {
    pn_context* context = nullptr;
    detail::check(pn_context_create(device.c_str(), &context));
    handle_ = Handle(context);
  }
  /// Works on the caller's objects, retained while the context lives and never finished (pn_context_create_from_cl).
  Context(cl_context context, cl_device_id device, cl_command_queue queue) {
    pn_context* created = nullptr;
    detail::check(pn_context_create_from_cl(context, device, queue, &created));
    handle_ = Handle(created);
  }

  /// The OpenCL context (not retained for the caller).
  cl_context clContext() const { return pn_context_cl_context(get()); }
  /// The OpenCL device.
  cl_device_id clDevice() const { return pn_context_cl_device(get()); }
  /// The queue penumbra enqueues on.
  cl_command_queue clQueue() const { return pn_context_cl_queue(get()); }
  /// The device's name.
  std::string deviceName() const { return pn_context_device_name(get()); }
  /// The C handle (not retained for the caller).
  pn_context* get() const noexcept { return handle_.get(); }

 private:
  using Handle = detail::Handle<pn_context, pn_context_retain, pn_context_release>;
  Handle handle_;
};

}  // namespace v0
}  // namespace penumbra
