// penumbra's C++ API: the context (pn_context): penumbra's own device and queue, or the caller's OpenCL objects.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/context.h"
#include "penumbra/error.hpp"

/// @file
/// penumbra::Context.

namespace penumbra {
inline namespace v0 {

/// A context's settings beyond the OpenCL objects (pn_context_options); unset: the environment's.
struct ContextOptions {
  std::string device;                           ///< Own contexts: as pn_context_create() takes it.
  std::optional<std::string> cacheDir;          ///< Folder for compiled programs; "": no disk cache.
  uint64_t localMemLimit = 0;                   ///< Bytes of local memory the kernels plan with; 0: the device's.
  std::optional<std::string> layouts;           ///< "gpu", "nvidia" or "" (the device's own table).
  std::function<void(const std::string&)> log;  ///< Programs built or loaded (see pn_log_callback).
};

/// An OpenCL device, context and in-order queue with penumbra's kernels (see pn_context). Copies share one context.
class Context {
 public:
  /// Opens a device of its own with `options` (pn_context_create_with_options).
  explicit Context(const ContextOptions& options) {
    pn_context_options o = cOptions(options);
    pn_context* context = nullptr;
    detail::check(pn_context_create_with_options(&o, &context));
    handle_ = Handle(context);
  }
  /// On the caller's objects with `options` (pn_context_create_from_cl_with_options; `options.device` unused).
  Context(cl_context context, cl_device_id device, cl_command_queue queue, const ContextOptions& options) {
    ContextOptions own = options;
    own.device.clear();
    pn_context_options o = cOptions(own);
    pn_context* created = nullptr;
    detail::check(pn_context_create_from_cl_with_options(context, device, queue, &o, &created));
    handle_ = Handle(created);
  }
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
  /// Builds the programs of the named techniques and stages now (pn_context_prebuild).
  void prebuild(const std::vector<std::string>& names) const {
    std::vector<const char*> c;
    for (const std::string& name : names) c.push_back(name.c_str());
    detail::check(pn_context_prebuild(get(), c.data(), c.size()));
  }

  /// The C handle (not retained for the caller).
  pn_context* get() const noexcept { return handle_.get(); }

 private:
  // The C options of `options`; the log function is copied to the heap, owned by the context (log_release).
  static pn_context_options cOptions(const ContextOptions& options) {
    pn_context_options o;
    pn_context_options_init(&o);
    o.device = options.device.empty() ? nullptr : options.device.c_str();
    o.cache_dir = options.cacheDir ? options.cacheDir->c_str() : nullptr;
    o.local_mem_limit = options.localMemLimit;
    o.layouts = options.layouts ? options.layouts->c_str() : nullptr;
    if (options.log) {
      using Log = std::function<void(const std::string&)>;
      o.log = [](const char* message, void* user) { (*static_cast<Log*>(user))(message); };
      o.log_user_data = new Log(options.log);
      o.log_release = [](void* user) { delete static_cast<Log*>(user); };
    }
    return o;
  }

  using Handle = detail::Handle<pn_context, pn_context_retain, pn_context_release>;
  Handle handle_;
};

}  // namespace v0
}  // namespace penumbra
