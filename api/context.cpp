// pn_context: penumbra's own device and queue, or the caller's OpenCL objects (host/cl/context.h's interop
// constructor: retained while the context lives, never finished).
#include <fmt/format.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "api/guard.h"
#include "api/handles.h"
#include "host/pipeline/prebuild.h"

using penumbra::api::guard;
using penumbra::api::require;

namespace {

// The options as the core takes them, and the device spec; NULL options: the defaults.
penumbra::ContextOptions contextOptions(const pn_context_options* options, const char* function, std::string* device) {
  penumbra::ContextOptions out;
  if (options == nullptr) return out;
  const pn_context_options& o =
      penumbra::api::requireSized(options, sizeof(pn_context_options), function, "options", "pn_context_options_init");
  if (o.log != nullptr) {
    // The caller's data lives while the function does (the context's, or this call's when it fails): the last copy
    // to go releases it.
    const std::shared_ptr<void> user(o.log_user_data, [release = o.log_release](void* data) {
      if (release != nullptr) release(data);
    });
    out.log = [log = o.log, user](const std::string& message) { log(message.c_str(), user.get()); };
  } else if (o.log_release != nullptr) {
    o.log_release(o.log_user_data);  // no callback to keep it for
  }
  if (o.device != nullptr) {
    if (device == nullptr)
      throw std::invalid_argument(
          fmt::format("{}: options.device must be NULL for a context on the caller's device", function));
    *device = o.device;
  }
  if (o.cache_dir != nullptr) out.cacheDir = o.cache_dir;
  if (o.local_mem_limit != 0) out.device.localMemLimit = o.local_mem_limit;
  if (o.layouts != nullptr) out.device.layouts = o.layouts;
  return out;
}

}  // namespace

extern "C" {

void pn_context_options_init(pn_context_options* options) {
  if (options != nullptr)
    *options = pn_context_options{sizeof(pn_context_options), nullptr, nullptr, 0, nullptr, nullptr, nullptr, nullptr};
}

pn_status pn_context_create_with_options(const pn_context_options* options, pn_context** context) {
  return guard([&] {
    std::string device;
    const penumbra::ContextOptions core = contextOptions(options, "pn_context_create_with_options", &device);
    require(context, "pn_context_create_with_options", "context");
    auto created = std::make_unique<pn_context>();
    created->context = std::make_unique<penumbra::Context>(device, core);
    *context = created.release();
  });
}

pn_status pn_context_create_from_cl_with_options(cl_context cl_ctx, cl_device_id device, cl_command_queue queue,
                                                 const pn_context_options* options, pn_context** context) {
  return guard([&] {
    const penumbra::ContextOptions core = contextOptions(options, "pn_context_create_from_cl_with_options", nullptr);
    require(context, "pn_context_create_from_cl_with_options", "context");
    auto created = std::make_unique<pn_context>();
    created->context = std::make_unique<penumbra::Context>(cl_ctx, device, queue, core);
    *context = created.release();
  });
}

pn_status pn_context_prebuild(pn_context* context, const char* const* names, size_t count) {
  return guard([&] {
    pn_context& c = *require(context, "pn_context_prebuild", "context");
    if (count > 0) require(names, "pn_context_prebuild", "names");
    std::vector<std::string> items;
    for (size_t i = 0; i < count; ++i) {
      if (names[i] == nullptr) throw std::invalid_argument(fmt::format("pn_context_prebuild: names[{}] is NULL", i));
      items.push_back(names[i]);
    }
    std::lock_guard lock(c.mutex);
    penumbra::prebuild(*c.context, items);
  });
}

pn_status pn_context_create(const char* device_spec, pn_context** context) {
  return guard([&] {
    require(context, "pn_context_create", "context");
    auto created = std::make_unique<pn_context>();
    created->context = std::make_unique<penumbra::Context>(device_spec != nullptr ? device_spec : "");
    *context = created.release();
  });
}

pn_status pn_context_create_from_cl(cl_context cl_ctx, cl_device_id device, cl_command_queue queue,
                                    pn_context** context) {
  return guard([&] {
    require(context, "pn_context_create_from_cl", "context");
    auto created = std::make_unique<pn_context>();
    created->context = std::make_unique<penumbra::Context>(cl_ctx, device, queue);
    *context = created.release();
  });
}

pn_status pn_context_retain(pn_context* context) { return penumbra::api::retainHandle(context, "pn_context_retain"); }

pn_status pn_context_release(pn_context* context) { return penumbra::api::releaseHandle(context); }

cl_context pn_context_cl_context(const pn_context* context) {
  return context != nullptr ? context->context->context()() : nullptr;
}

cl_device_id pn_context_cl_device(const pn_context* context) {
  return context != nullptr ? context->context->device()() : nullptr;
}

cl_command_queue pn_context_cl_queue(const pn_context* context) {
  return context != nullptr ? context->context->queue()() : nullptr;
}

const char* pn_context_device_name(const pn_context* context) {
  return context != nullptr ? context->context->info().name.c_str() : nullptr;
}

}  // extern "C"
