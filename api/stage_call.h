// One stage call on the caller's objects (penumbra/stages.h): checks the wait list and the caller's cl_mem buffers
// (type, context, size), holds the context's lock, enqueues a barrier on the wait list before the stage's kernels
// and a marker after them for the caller's event, and flushes the queue without finishing it.
#pragma once

#include <fmt/format.h>

#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "api/guard.h"
#include "api/handles.h"
#include "host/cl/error.h"
#include "host/stages/image_layout.h"
#include "host/stages/image_shape.h"
#include "penumbra/stages.h"

namespace penumbra::api {

class StageCall {
 public:
  StageCall(pn_context* context, const char* function, cl_uint waitCount, const cl_event* waitList, cl_event* event)
      : function_(function), waitCount_(waitCount), waitList_(waitList), event_(event) {
    context_ = require(context, function, "context");
    if ((waitCount == 0) != (waitList == nullptr))
      throw std::invalid_argument(fmt::format("{}: a wait list of {} events {}", function, waitCount,
                                              waitList == nullptr ? "is NULL" : "is not NULL"));
    lock_ = std::unique_lock(context_->mutex);
  }

  Context& ctx() { return *context_->context; }

  // The caller's buffer `mem` as elements of T (as many as fit its size), retained for this call only.
  template <class T>
  Buffer<T> buffer(cl_mem mem, const char* what) const {
    if (mem == nullptr) throw std::invalid_argument(fmt::format("{}: {} is NULL", function_, what));
    cl_mem_object_type type = 0;
    const cl_int err = clGetMemObjectInfo(mem, CL_MEM_TYPE, sizeof(type), &type, nullptr);
    if (err == CL_INVALID_MEM_OBJECT)
      throw std::invalid_argument(fmt::format("{}: {} is not a valid cl_mem", function_, what));
    clCheck(err, "clGetMemObjectInfo", {}, "api");
    if (type != CL_MEM_OBJECT_BUFFER)
      throw std::invalid_argument(fmt::format("{}: {} is an image, not a buffer", function_, what));
    const cl_context owner = requireOwned(mem, what);
    size_t bytes = 0;
    clCheck(clGetMemObjectInfo(mem, CL_MEM_SIZE, sizeof(bytes), &bytes, nullptr), "clGetMemObjectInfo", {}, "api");
    return Buffer<T>::over(cl::Buffer(mem, true), bytes / sizeof(T), owner);
  }

  // A stage's input: the caller's buffer as buffer() takes it, or a cl_image2d of width x height texels of `channels`
  // T values each (CL_FLOAT images for float, CL_HALF_FLOAT for cl_half; CL_R, CL_RG or CL_RGBA), copied once into a
  // temporary buffer after the wait list's barrier (run()), since the stages' kernels read buffers.
  template <class T>
  Buffer<T> input(cl_mem mem, const char* what, uint32_t width, uint32_t height, uint32_t channels) {
    if (mem == nullptr) throw std::invalid_argument(fmt::format("{}: {} is NULL", function_, what));
    cl_mem_object_type type = 0;
    const cl_int err = clGetMemObjectInfo(mem, CL_MEM_TYPE, sizeof(type), &type, nullptr);
    if (err != CL_SUCCESS || type != CL_MEM_OBJECT_IMAGE2D) return buffer<T>(mem, what);
    requireOwned(mem, what);
    cl_image_format format{};
    size_t w = 0, h = 0;
    clCheck(clGetImageInfo(mem, CL_IMAGE_FORMAT, sizeof(format), &format, nullptr), "clGetImageInfo", {}, "api");
    clCheck(clGetImageInfo(mem, CL_IMAGE_WIDTH, sizeof(w), &w, nullptr), "clGetImageInfo", {}, "api");
    clCheck(clGetImageInfo(mem, CL_IMAGE_HEIGHT, sizeof(h), &h, nullptr), "clGetImageInfo", {}, "api");
    const cl_channel_type wantedType = sizeof(T) == sizeof(float) ? CL_FLOAT : CL_HALF_FLOAT;
    const cl_channel_order wantedOrder = channels == 1 ? CL_R : channels == 2 ? CL_RG : CL_RGBA;
    if (format.image_channel_data_type != wantedType || format.image_channel_order != wantedOrder)
      throw std::invalid_argument(fmt::format("{}: {} is an image of another format than {} {} channel{}", function_,
                                              what, channels, sizeof(T) == sizeof(float) ? "float" : "half",
                                              channels == 1 ? "" : "s"));
    if (w != width || h != height)
      throw std::invalid_argument(
          fmt::format("{}: {} is a {}x{} image for a {}x{} stage", function_, what, w, h, width, height));
    Buffer<T> copy(ctx(), size_t(width) * height * channels);
    const cl_mem target = copy.get()();
    clRetainMemObject(mem);  // held until the copy is enqueued (the caller may release it once the call returns)
    copies_.push_back({mem, target, width, height});
    return copy;
  }

  // The caller's image (penumbra/stages.h pn_device_image) of width x height texels of `channels` floats: a buffer in
  // place with its offset, pitch and row order, or a cl_image2d copied into a buffer after the wait list (input(): its
  // rows then packed); nothing when `image.memory` is NULL. The layout is checked by its user (imageLayout).
  std::optional<CallerImage> image(const pn_device_image& image, const std::string& what, uint32_t width,
                                   uint32_t height, uint32_t channels) {
    if (image.memory == nullptr) return std::nullopt;
    cl_mem_object_type type = 0;
    const bool isImage = clGetMemObjectInfo(image.memory, CL_MEM_TYPE, sizeof(type), &type, nullptr) == CL_SUCCESS &&
                         type == CL_MEM_OBJECT_IMAGE2D;
    if (isImage && channels == 3)
      throw std::invalid_argument(
          fmt::format("{}: {} is an image, whose texels have 1, 2 or 4 channels, not 3", function_, what));
    CallerImage out;
    out.buffer = input<float>(image.memory, what.c_str(), width, height, channels);
    out.offsetBytes = isImage ? 0 : image.offset;
    out.rowPitchBytes = isImage ? 0 : image.row_pitch;
    out.topDown = image.top_down != 0;
    return out;
  }

  // The caller's scratch buffer, or (NULL) a temporary of `count` elements, freed once the stage's commands are done.
  template <class T>
  Buffer<T> scratch(cl_mem mem, size_t count, const char* what) {
    return mem != nullptr ? buffer<T>(mem, what) : Buffer<T>(ctx(), count);
  }

  // Enqueues the barrier, runs `stage` (which enqueues the kernels), then the marker for the caller's event; flushes.
  template <class Stage>
  void run(Stage&& stage) {
    begin();
    stage();
    finish();
  }

  // run()'s halves, for a stage that checks its inputs between the call's start and its first command: the barrier on
  // the wait list and the images' copies; then the marker for the caller's event and the flush.
  void begin() {
    cl_command_queue queue = ctx().queue()();
    if (waitCount_ > 0)
      clCheck(clEnqueueBarrierWithWaitList(queue, waitCount_, waitList_, nullptr), "clEnqueueBarrierWithWaitList", {},
              function_);
    for (const ImageCopy& c : copies_) {
      const size_t origin[3] = {0, 0, 0}, region[3] = {c.width, c.height, 1};
      clCheck(clEnqueueCopyImageToBuffer(queue, c.image, c.buffer, origin, region, 0, 0, nullptr, nullptr),
              "clEnqueueCopyImageToBuffer", {}, function_);
    }
  }

  void finish() {
    cl_command_queue queue = ctx().queue()();
    cl_event marker = nullptr;  // the caller's event only once the call has succeeded (a failed one writes none)
    if (event_ != nullptr)
      clCheck(clEnqueueMarkerWithWaitList(queue, 0, nullptr, &marker), "clEnqueueMarkerWithWaitList", {}, function_);
    if (const cl_int err = clFlush(queue); err != CL_SUCCESS) {
      if (marker != nullptr) clReleaseEvent(marker);
      throw ClError(err, "clFlush", {}, function_);
    }
    if (event_ != nullptr) *event_ = marker;
  }

  const char* function() const { return function_; }

  ~StageCall() {
    for (const ImageCopy& c : copies_) clReleaseMemObject(c.image);  // the copy, once enqueued, holds its own
  }
  StageCall(const StageCall&) = delete;
  StageCall& operator=(const StageCall&) = delete;

 private:
  // The context `mem` belongs to, which must be the pn_context's.
  cl_context requireOwned(cl_mem mem, const char* what) const {
    cl_context owner = nullptr;
    clCheck(clGetMemObjectInfo(mem, CL_MEM_CONTEXT, sizeof(owner), &owner, nullptr), "clGetMemObjectInfo", {}, "api");
    if (owner != context_->context->context()())
      throw std::invalid_argument(
          fmt::format("{}: {} belongs to another OpenCL context than the pn_context's", function_, what));
    return owner;
  }

  struct ImageCopy {
    cl_mem image, buffer;
    size_t width, height;
  };
  std::vector<ImageCopy> copies_;  // input(): images copied into temporaries after the barrier
  const char* function_;
  pn_context* context_ = nullptr;
  cl_uint waitCount_;
  const cl_event* waitList_;
  cl_event* event_;
  std::unique_lock<std::mutex> lock_;
};

// Throws std::invalid_argument unless the image (named `what` in the message) has texels: a stage of a 0-wide or
// 0-high image is a caller's error, as a 0-wide camera is (api/convert.cpp).
inline void requireTexels(uint32_t width, uint32_t height, const char* function, const char* what = "image") {
  if (width == 0 || height == 0)
    throw std::invalid_argument(
        fmt::format("{}: {} {}x{} has no texels (width and height must be at least 1)", function, what, width, height));
}

// The caller's pn_image_shape (not NULL, with texels) as the core's ImageShape.
inline ImageShape stageShape(const pn_image_shape* shape, const char* function) {
  require(shape, function, "shape");
  requireTexels(shape->width, shape->height, function);
  return {shape->width, shape->height, shape->channels};
}

// Throws std::invalid_argument unless `value` is one of the enum's `count` values 0..count-1.
template <class Enum>
void checkEnum(Enum value, int count, const char* function, const char* what) {
  if (static_cast<int>(value) < 0 || static_cast<int>(value) >= count)
    throw std::invalid_argument(
        fmt::format("{}: {} {} is not one of 0..{}", function, what, static_cast<int>(value), count - 1));
}

}  // namespace penumbra::api
