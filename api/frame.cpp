// pn_frame: a rendered frame's host channels (host/io/image.h, rows top-down), its device copy of each light's
// visibility (rows bottom-up), provenance attributes, pass times and EXR output.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "api/guard.h"
#include "api/handles.h"
#include "host/io/exr.h"

using penumbra::api::guard;
using penumbra::api::require;

extern "C" {

pn_status pn_frame_retain(pn_frame* frame) { return penumbra::api::retainHandle(frame, "pn_frame_retain"); }

pn_status pn_frame_release(pn_frame* frame) { return penumbra::api::releaseHandle(frame); }

int pn_frame_width(const pn_frame* frame) { return frame != nullptr ? frame->image.width() : 0; }

int pn_frame_height(const pn_frame* frame) { return frame != nullptr ? frame->image.height() : 0; }

size_t pn_frame_channel_count(const pn_frame* frame) { return frame != nullptr ? frame->image.channels().size() : 0; }

const char* pn_frame_channel_name(const pn_frame* frame, size_t index) {
  if (frame == nullptr || index >= frame->image.channels().size()) return nullptr;
  return frame->image.channels()[index].name.c_str();
}

pn_status pn_frame_channel(const pn_frame* frame, const char* name, const float** data) {
  return guard([&] {
    require(data, "pn_frame_channel", "data");
    const pn_frame& f = *require(frame, "pn_frame_channel", "frame");
    const penumbra::ImageChannel* channel = f.image.find(require(name, "pn_frame_channel", "name"));
    if (channel == nullptr)
      throw std::invalid_argument(fmt::format("pn_frame_channel: the frame has no channel \"{}\" (it has {})", name,
                                              fmt::join(f.image.channelNames(), ", ")));
    *data = channel->data.data();
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
    switch (output) {
      case PN_FRAME_PREVIEW:
        *buffer = f.preview.get()();
        return;
      case PN_FRAME_POSITION:
        *buffer = f.position.get()();
        return;
      case PN_FRAME_NORMAL:
        *buffer = f.normal.get()();
        return;
      case PN_FRAME_DEPTH:
        *buffer = f.depth.get()();
        return;
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

size_t pn_frame_pass_count(const pn_frame* frame) { return frame != nullptr ? frame->passes.size() : 0; }

pn_status pn_frame_pass(const pn_frame* frame, size_t index, const char** name, double* milliseconds) {
  return guard([&] {
    const pn_frame& f = *require(frame, "pn_frame_pass", "frame");
    if (index >= f.passes.size())
      throw std::out_of_range(fmt::format("pn_frame_pass: pass {} of a frame of {}", index, f.passes.size()));
    if (name != nullptr) *name = f.passes[index].name.c_str();
    if (milliseconds != nullptr) *milliseconds = f.passes[index].ms;
  });
}

pn_status pn_frame_save_exr(const pn_frame* frame, const char* path) {
  return guard([&] {
    const pn_frame& f = *require(frame, "pn_frame_save_exr", "frame");
    penumbra::writeExr(require(path, "pn_frame_save_exr", "path"), f.image);
  });
}

}  // extern "C"
