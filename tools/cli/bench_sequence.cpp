// The sequence bench: cameras from the path (camera_path.h, the same as `plan`'s), references traced per frame and
// kept, then per cell one Renderer over the frames in order (warm-up frames on frame 0 first), each frame compared with
// its reference (coverage and lit mask as `bench` does) and with the frame before it where the reference is stable.
#include "tools/cli/bench_sequence.h"

#include <fmt/format.h>

#include <filesystem>
#include <sstream>

#include "host/eval/metrics.h"
#include "host/io/atomic_file.h"
#include "host/io/bounded_read.h"
#include "host/pipeline/renderer.h"
#include "host/scene/light_names.h"
#include "tools/cli/camera_path.h"
#include "tools/cli/input_limits.h"
#include "tools/eval/bench_report.h"
#include "tools/eval/bench_stats.h"
#include "tools/eval/shimmer.h"
#include "tools/reference/reference.h"

namespace penumbra::cli {
namespace {

struct SequenceRow {
  std::string technique, setting, parameters, light;
  double ms = 0, mae = 0;
  ShimmerMetrics shimmer;
};

nlohmann::json readPath(const std::string& text) {
  std::string json = text;
  if (!text.empty() && text[0] == '@') {
    try {
      json = readBoundedFile(text.substr(1), kMaxCameraPathBytes, "the camera path");
    } catch (const std::runtime_error& e) {
      throw std::invalid_argument(fmt::format("--camera-path: {}", e.what()));
    }
  }
  try {
    return nlohmann::json::parse(json);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(fmt::format("--camera-path: not JSON: {}", e.what()));
  }
}

std::vector<Camera> pathCameras(const BenchOptions& o, const Scene& scene) {
  const nlohmann::json path = readPath(o.cameraPath);
  std::vector<Camera> cameras;
  for (int f = 0; f < o.frames; ++f) {
    ViewOptions view = o.view;
    view.camera = cameraOnPath(path, f, o.frames);
    cameras.push_back(resolveCamera(view, scene));
  }
  return cameras;
}

SequenceRow measureCell(const BenchOptions& o, Context& ctx, const Scene& scene, const std::vector<Camera>& cameras,
                        const std::vector<Image>& refs, const BenchJob& job, const Light& light,
                        const CompareSpec& spec) {
  Renderer renderer(ctx, scene);
  for (int i = 0; i < o.warmup; ++i) benchFrame(renderer, cameras[0], light, job);
  std::vector<std::vector<PassTime>> runs;
  std::vector<ShimmerMetrics> pairs;
  double mae = 0;
  std::vector<float> previous, previousPixels;
  for (size_t f = 0; f < cameras.size(); ++f) {
    RenderResult result = benchFrame(renderer, cameras[f], light, job);
    runs.push_back(result.passes);
    mae += compareImages(result.image, refs[f], spec).mae / static_cast<double>(cameras.size());
    std::vector<float> visibility = result.image.require(spec.channel).data;
    std::vector<float> pixels = comparedPixels(result.image, refs[f], spec);
    if (f > 0)
      pairs.push_back(frameShimmer(previous, visibility, refs[f - 1].require(spec.channel).data,
                                   refs[f].require(spec.channel).data, previousPixels, pixels));
    previous = std::move(visibility), previousPixels = std::move(pixels);
  }
  return {job.technique->name,  job.setting.label,           job.params.describe(),
          lightLayer(light),    summariseRuns(runs).totalMs, mae,
          combineShimmer(pairs)};
}

void writeRows(const BenchOptions& o, const std::string& device, const Camera& camera,
               const std::vector<SequenceRow>& rows) {
  std::ostringstream csv;
  csv << "scene,technique,setting,parameters,light,width,height,frames,device,ms,mae,shimmer,shimmer_fraction,"
         "shimmer_max,shimmer_pixels\n";
  for (const SequenceRow& r : rows)
    csv << fmt::format("{},{},{},{},{},{},{},{},{},{:.6f},{:.6g},{:.6g},{:.6g},{:.6g},{}\n", csvField(o.view.scene),
                       r.technique, csvField(r.setting), csvField(r.parameters), csvField(r.light), camera.width,
                       camera.height, o.frames, csvField(device), r.ms, r.mae, r.shimmer.mean, r.shimmer.fraction,
                       r.shimmer.maxAbs, r.shimmer.pixels);
  const std::filesystem::path path = o.output;
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  writeFileAtomically(path, csv.str());
}

}  // namespace

int runSequenceBench(const BenchOptions& o, const std::vector<BenchJob>& jobs) {
  if (o.noReference || !o.reference.empty() || !o.json.empty() || o.interleave)
    throw std::invalid_argument(
        "--camera-path traces its own references: no --reference, --no-reference, --json "
        "or --interleave");
  const Scene scene = loadViewScene(o.view);
  const std::vector<Camera> cameras = pathCameras(o, scene);
  const std::vector<Light> lights = resolveLights(o.view, scene);
  for (const BenchJob& job : jobs)
    for (const Light& light : lights) refuseUnsupportedLight(light, *job.technique);
  Context ctx(o.device);
  const std::string device = fmt::format("{} ({})", ctx.info().name, ctx.info().platformName);
  reference::TraceSettings trace;
  trace.spp = o.spp;
  std::vector<Image> refs;
  for (size_t f = 0; f < cameras.size(); ++f) {
    if (!o.quiet) fmt::print(stderr, "bench: tracing the reference of frame {} of {}\n", f + 1, cameras.size());
    refs.push_back(reference::renderReference(ctx, scene, cameras[f], lights, trace).image);
  }
  CompareSpec base;
  if (o.noMask) base.mask.clear();
  std::vector<SequenceRow> rows;
  for (const BenchJob& job : jobs)
    for (const Light& light : lights) {
      if (!o.quiet)
        fmt::print(stderr, "bench: {} {} over {} frames\n", job.technique->name, job.setting.label, o.frames);
      rows.push_back(measureCell(o, ctx, scene, cameras, refs, job, light, lightSpec(base, light, lights.size())));
    }
  writeRows(o, device, cameras[0], rows);
  if (!o.quiet) {
    fmt::print("{}: {}x{}, {} frames of a camera path\n  {:<8} {:<24} {:<8} {:>10} {:>9} {:>9} {:>9}\n", device,
               cameras[0].width, cameras[0].height, o.frames, "technique", "setting", "light", "ms", "mae", "shimmer",
               "shim. px");
    for (const SequenceRow& r : rows)
      fmt::print("  {:<8} {:<24} {:<8} {:>10.3f} {:>9.5f} {:>9.5f} {:>9.5f}\n", r.technique, r.setting, r.light, r.ms,
                 r.mae, r.shimmer.mean, r.shimmer.fraction);
    fmt::print("wrote {}\n", o.output);
  }
  return 0;
}

}  // namespace penumbra::cli
