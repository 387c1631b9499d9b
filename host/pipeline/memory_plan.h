// A frame's memory plan: before anything is allocated, the bytes each stage of the frame needs on the device and on
// the host, compared with the device's global memory, its largest single allocation and an optional caller's limit.
// A frame that does not fit is refused with one line naming the stage that needs the most and how much.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "host/cl/device.h"
#include "host/pipeline/frame_image.h"
#include "host/scene/camera.h"
#include "host/scene/light.h"
#include "host/techniques/technique.h"

namespace penumbra {

// Thrown when a frame does not fit: by the plan before any work, or when an allocation fails during the frame
// ("out of host memory in stage shade (needs 1.0 GiB)"). A std::runtime_error: exit 1 at the command line.
class MemoryError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MemoryStage {
  std::string name;            // "G-buffer", "light 0 (evsm4): maps", "image download", ...
  uint64_t deviceBytes = 0;    // held on the device while the frame runs
  uint64_t hostBytes = 0;      // held in host memory while the frame is read back
  uint64_t largestBuffer = 0;  // its largest single device buffer (against CL_DEVICE_MAX_MEM_ALLOC_SIZE)
};

struct MemoryPlan {
  std::vector<MemoryStage> stages;
  uint64_t deviceBytes() const;
  uint64_t hostBytes() const;
  const MemoryStage& largest() const;  // the stage with the most device bytes
  std::string describe()
      const;  // "G-buffer 2.8 GiB, light 0 (sm): maps 32 MiB, ..., image download 1.2 GiB on the host"
};

// How a frame's channels reach the caller (Renderer::render).
enum class FrameDownload {
  Image,     // downloaded whole into RenderResult::image
  Deferred,  // left on the device and read in bands by the writer (RenderResult::deferred): for a frame written once
  // Like Deferred, and nothing waited for once the frame is enqueued: no empty-frame check, no debug channels, the
  // pass times left to resolve (RenderResult::profile); the G-buffer's ids kept for the next frame. The library's
  // frames whose host channels are read on request (pn_renderer_enqueue).
  OnRequest,
};

// One light of a frame as the plan sees it (the renderer's FrameLight without the light's geometry).
struct PlannedLight {
  LightType type;
  const TechniqueInfo* technique;
  const Params* params;
};

// The scene as the rasterizer holds it (every draw: the camera's G-buffer and each light's maps).
struct PlannedScene {
  uint64_t triangles = 0, vertices = 0;
};

// The plan of one frame of `camera`'s size with `lights` over `scene`. Estimates, on the high side: the G-buffer, visibility and
// preview buffers are exact; a technique's maps are sized from its map-size, moment storage, blur, mip chain and
// layer parameters, and its per-pixel buffers (debug channels, filter scratch) at 32 bytes per pixel.
// A deferred download holds its writer's bands on the host (kDeferredHostBytes), not the image. The rasterizer's
// stage holds the uploaded scene and its queues at their first sizes (raster/rasterizer.cpp's sizeQueues): its
// largest buffer, 72 bytes a triangle of set-up records, is what meets the device's largest allocation first.
MemoryPlan planFrame(const Camera& camera, const std::vector<PlannedLight>& lights,
                     FrameDownload download = FrameDownload::Image, PlannedScene scene = {}, FrameOutputs outputs = {});

// What a deferred frame's writers hold at most: the EXR's band (32 MiB), the PNG's (8 MiB) and the float4 buffers'
// band caches (under 32 MiB).
inline constexpr uint64_t kDeferredHostBytes = uint64_t{72} << 20;

// Throws MemoryError naming the stage and the sizes when the plan needs more device memory than
// min(globalMemBytes, limit), a single buffer larger than maxAllocBytes, or more host memory than `limit`.
void checkMemoryPlan(const MemoryPlan& plan, const DeviceInfo& device, std::optional<uint64_t> limit);

// "1.5 GiB", "512 MiB", "64 KiB", "17 bytes".
std::string formatBytes(uint64_t bytes);

// "4GiB", "512MiB", "1.5G", "800M", "65536" (bytes): binary units, case-insensitive, optional "B"/"iB". Throws
// std::invalid_argument naming `what` and the text.
uint64_t parseMemorySize(std::string_view text, std::string_view what);

}  // namespace penumbra
