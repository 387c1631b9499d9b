// pn_context: penumbra's own device and queue, or the caller's OpenCL objects (host/cl/context.h's interop
// constructor: retained while the context lives, never finished).
#include "api/guard.h"
#include "api/handles.h"

using penumbra::api::guard;
using penumbra::api::require;

extern "C" {

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
