// pn_frame: a rendered frame's host channels (host/io/image.h, rows top-down), its device copy of each light's
// visibility (rows bottom-up), provenance attributes, pass times and EXR output.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "api/guard.h"
#include "api/handles.h"
#include "host/io/exr.h"
#include "host/io/image_rows.h"

using penumbra::api::guard;
using penumbra::api::require;

pn_frame::~pn_frame() {
  deferred.clear();  // the readers refer to the context
  penumbra::api::releaseHandle(context);
}

namespace {

// The frame's channel names: those it holds, then those it reads on request.
std::vector<std::string> channelNames(const pn_frame& f) {
  std::vector<std::string> names = f.image.channelNames();
  for (const penumbra::DeferredChannel& c : f.deferred) names.push_back(c.name);
  return names;
}

// A channel read on request (rows top-down), read the first time under the frame's and the context's locks.
const float* fetch(const pn_frame& f, const penumbra::DeferredChannel& channel) {
  std::lock_guard lock(f.onRequest);
  auto it = f.fetched.find(channel.name);
  if (it == f.fetched.end()) {
    std::vector<float> rows(static_cast<size_t>(f.image.width()) * static_cast<size_t>(f.image.height()));
    std::lock_guard queue(f.context->mutex);
    channel.read(0, f.image.height(), rows);
    it = f.fetched.emplace(channel.name, std::move(rows)).first;
  }
  return it->second.data();
}

// The pass times, resolved from the frame's events the first time (waiting for them).
const std::vector<penumbra::PassTime>& passes(const pn_frame& f) {
  std::lock_guard lock(f.onRequest);
  if (f.pending) {
    f.passes = f.pending->resolve();
    f.pending.reset();
  }
  return f.passes;
}

}  // namespace

extern "C" {

pn_status pn_frame_retain(pn_frame* frame) { return penumbra::api::retainHandle(frame, "pn_frame_retain"); }

pn_status pn_frame_release(pn_frame* frame) { return penumbra::api::releaseHandle(frame); }

int pn_frame_width(const pn_frame* frame) { return frame != nullptr ? frame->image.width() : 0; }

int pn_frame_height(const pn_frame* frame) { return frame != nullptr ? frame->image.height() : 0; }

size_t pn_frame_channel_count(const pn_frame* frame) {
  return frame != nullptr ? frame->image.channels().size() + frame->deferred.size() : 0;
}

const char* pn_frame_channel_name(const pn_frame* frame, size_t index) {
  if (frame == nullptr) return nullptr;
  const size_t held = frame->image.channels().size();
  if (index < held) return frame->image.channels()[index].name.c_str();
  return index - held < frame->deferred.size() ? frame->deferred[index - held].name.c_str() : nullptr;
}

pn_status pn_frame_channel(const pn_frame* frame, const char* name, const float** data) {
  return guard([&] {
    require(data, "pn_frame_channel", "data");
    const pn_frame& f = *require(frame, "pn_frame_channel", "frame");
    if (const penumbra::ImageChannel* held = f.image.find(require(name, "pn_frame_channel", "name"))) {
      *data = held->data.data();
      return;
    }
    for (const penumbra::DeferredChannel& channel : f.deferred)
      if (channel.name == name) {
        *data = fetch(f, channel);
        return;
      }
    throw std::invalid_argument(fmt::format("pn_frame_channel: the frame has no channel \"{}\" (it has {})", name,
                                            fmt::join(channelNames(f), ", ")));
  });
}

size_t pn_frame_light_count(const pn_frame* frame) { return frame != nullptr ? frame->layers.size() : 0; }

const char* pn_frame_light_layer(const pn_frame* frame, size_t index) {
  if (frame == nullptr || index >= frame->layers.size()) return nullptr;
  return frame->layers[index].c_str();
}

pn_status pn_frame_visibility_buffer(const pn_frame* frame, size_t index, cl_mem* buffer) {
  return guard([&] {
    require(buffer, "pn_frame_visibility_buffer", "buffer");
    const pn_frame& f = *require(frame, "pn_frame_visibility_buffer", "frame");
    if (index >= f.visibility.size())
      throw std::out_of_range(
          fmt::format("pn_frame_visibility_buffer: light {} of a frame of {}", index, f.visibility.size()));
    *buffer = f.visibility[index].get()();
  });
}

pn_status pn_frame_device_buffer(const pn_frame* frame, pn_frame_output output, cl_mem* buffer) {
  return guard([&] {
    require(buffer, "pn_frame_device_buffer", "buffer");
    const pn_frame& f = *require(frame, "pn_frame_device_buffer", "frame");
    auto give = [&](const auto& kept, const char* name, const char* bit) {
      if (kept.empty())
        throw std::invalid_argument(fmt::format(
            "pn_frame_device_buffer: the frame has no {} (its pn_render_options::outputs left out {})", name, bit));
      *buffer = kept.get()();
    };
    switch (output) {
      case PN_FRAME_PREVIEW:
        return give(f.preview, "PN_FRAME_PREVIEW", "PN_FRAME_OUTPUT_PREVIEW_BIT");
      case PN_FRAME_POSITION:
        return give(f.position, "PN_FRAME_POSITION", "PN_FRAME_OUTPUT_SURFACES_BIT");
      case PN_FRAME_NORMAL:
        return give(f.normal, "PN_FRAME_NORMAL", "PN_FRAME_OUTPUT_SURFACES_BIT");
      case PN_FRAME_DEPTH:
        return give(f.depth, "PN_FRAME_DEPTH", "PN_FRAME_OUTPUT_SURFACES_BIT");
      case PN_FRAME_OUTPUT_MAX_ENUM:  // not an output
        break;
    }
    throw std::invalid_argument(
        fmt::format("pn_frame_device_buffer: output {} is none of PN_FRAME_PREVIEW, "
                    "PN_FRAME_POSITION, PN_FRAME_NORMAL, PN_FRAME_DEPTH",
                    static_cast<int>(output)));
  });
}

const char* pn_frame_attribute(const pn_frame* frame, const char* name) {
  if (frame == nullptr || name == nullptr) return nullptr;
  const auto& attributes = frame->image.attributes();
  auto it = attributes.find(name);
  return it != attributes.end() ? it->second.c_str() : nullptr;
}

size_t pn_frame_pass_count(const pn_frame* frame) {
  size_t count = 0;
  const pn_status status = guard([&] {
    if (frame != nullptr) count = passes(*frame).size();
  });
  return status == PN_SUCCESS ? count : 0;
}

pn_status pn_frame_pass(const pn_frame* frame, size_t index, const char** name, double* milliseconds) {
  return guard([&] {
    const std::vector<penumbra::PassTime>& all = passes(*require(frame, "pn_frame_pass", "frame"));
    if (index >= all.size())
      throw std::out_of_range(fmt::format("pn_frame_pass: pass {} of a frame of {}", index, all.size()));
    if (name != nullptr) *name = all[index].name.c_str();
    if (milliseconds != nullptr) *milliseconds = all[index].ms;
  });
}

pn_status pn_frame_save_exr(const pn_frame* frame, const char* path) {
  return guard([&] {
    const pn_frame& f = *require(frame, "pn_frame_save_exr", "frame");
    require(path, "pn_frame_save_exr", "path");
    if (f.deferred.empty()) return penumbra::writeExr(path, f.image);
    std::lock_guard lock(f.onRequest);  // the channels not read yet come down in bands, on the context's queue
    std::lock_guard queue(f.context->mutex);
    penumbra::writeExr(path, penumbra::ImageRows(f.image, f.deferred));
  });
}

}  // extern "C"
