// Embree BVH of the scene and the threaded shadow-ray loop: worker threads take chunks of points, generate each
// point's stratified light samples from a per-point seeded generator (deterministic for any thread count), trace
// them in streams with rtcOccluded1M and reduce the replicates to a mean and its standard error.
#include "tools/reference/tracer.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "host/techniques/izb_pattern.h"
#include "tools/reference/alpha_filter.h"
#include "tools/reference/embree_api.h"
#include "tools/reference/light_samples.h"

namespace penumbra::reference {
namespace {

constexpr size_t kChunkPoints = 64;   // points a worker takes at a time (load balance vs atomic traffic)
constexpr size_t kStreamRays = 1024;  // rays per rtcOccluded1M call: amortises the call, stays in L1/L2

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// splitmix64 (Steele, Lea & Flood, OOPSLA 2014): a counter-based generator, seeded per point.
struct Random {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  float uniform() { return static_cast<float>(next() >> 40) * 0x1p-24f; }  // [0, 1)
};

}  // namespace

SampleLayout SampleLayout::fromSpp(int spp) {
  const int k = static_cast<int>(std::lround(std::sqrt(std::max(spp, 0) / double{kReplicates})));
  if (k < 1 || k > 64 || kReplicates * k * k != spp)
    throw std::invalid_argument(
        fmt::format("spp {}: must be {} k^2 for k in 1..64 ({} independent k x k stratified grids), e.g. 64, 256, 1024",
                    spp, kReplicates, kReplicates));
  return {kReplicates, k};
}

struct ShadowTracer::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::mutex errorMutex;
  std::string error;  // the first Embree error, from its callback
  float sceneRadius = 0;
  double buildSeconds = 0;
  std::unique_ptr<AlphaFilter> alpha;  // read by the geometry's filter functions

  static void onError(void* self, RTCError code, const char* message) {
    auto* impl = static_cast<Impl*>(self);
    std::lock_guard lock(impl->errorMutex);
    if (impl->error.empty()) impl->error = fmt::format("Embree error {}: {}", static_cast<int>(code), message);
  }
  void check(const char* what) {
    std::lock_guard lock(errorMutex);
    if (!error.empty()) throw std::runtime_error(fmt::format("reference: {}: {}", what, error));
  }
  void build(const Scene& scene);
};

void ShadowTracer::Impl::build(const Scene& source) {
  RTCGeometry mesh = embree().rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  check("rtcNewGeometry");
  auto* vertices = static_cast<float*>(embree().rtcSetNewGeometryBuffer(
      mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), source.positions.size()));
  auto* indices = static_cast<unsigned*>(embree().rtcSetNewGeometryBuffer(
      mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), source.triangles.size()));
  check("rtcSetNewGeometryBuffer");
  for (size_t i = 0; i < source.positions.size(); ++i)
    for (int c = 0; c < 3; ++c) vertices[3 * i + c] = source.positions[i][c];
  for (size_t i = 0; i < source.triangles.size(); ++i)
    for (int c = 0; c < 3; ++c) indices[3 * i + c] = source.triangles[i][c];
  alpha = std::make_unique<AlphaFilter>(device, source);
  alpha->attach(mesh);
  embree().rtcCommitGeometry(mesh);
  embree().rtcAttachGeometry(scene, mesh);
  embree().rtcReleaseGeometry(mesh);
  // Robust traversal: watertight, so shadow rays through shared edges of a closed mesh cannot slip through.
  embree().rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  embree().rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  embree().rtcCommitScene(scene);
  check("building the BVH");
}

ShadowTracer::ShadowTracer(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  const Clock::time_point start = Clock::now();
  impl_->device = embree().rtcNewDevice(nullptr);
  if (impl_->device == nullptr)
    throw std::runtime_error(fmt::format("reference: rtcNewDevice failed (error {})",
                                         static_cast<int>(embree().rtcGetDeviceError(nullptr))));
  embree().rtcSetDeviceErrorFunction(impl_->device, &Impl::onError, impl_.get());
  impl_->scene = embree().rtcNewScene(impl_->device);
  impl_->check("rtcNewScene");
  if (!scene.triangles.empty())
    impl_->build(scene);
  else
    embree().rtcCommitScene(impl_->scene);
  impl_->sceneRadius = scene.boundingRadius();
  impl_->buildSeconds = secondsSince(start);
}

ShadowTracer::~ShadowTracer() {
  if (impl_->scene != nullptr) embree().rtcReleaseScene(impl_->scene);
  if (impl_->device != nullptr) embree().rtcReleaseDevice(impl_->device);
}

double ShadowTracer::buildSeconds() const { return impl_->buildSeconds; }

float ShadowTracer::rayOffset(const glm::vec3& p) const {
  const float extent = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), impl_->sceneRadius});
  return kRayOffset * std::max(extent, std::numeric_limits<float>::min());
}

namespace {

// One worker's rays for a chunk of points: generates, streams through Embree, counts per (point, replicate).
class ChunkTracer {
 public:
  ChunkTracer(RTCScene scene, const ShadowTracer& tracer, const LightSampler& sampler, SampleLayout layout,
              const TraceSettings& settings, const IzbLightPattern* pattern, TraceResult& out)
      : scene_(scene),
        tracer_(tracer),
        sampler_(sampler),
        layout_(layout),
        seed_(settings.seed),
        patternKeys_(settings.patternKeys),
        pattern_(pattern),
        out_(out) {
    rays_.reserve(kStreamRays + static_cast<size_t>(layout.spp()));
    tags_.reserve(rays_.capacity());
    counts_.resize(kChunkPoints * static_cast<size_t>(layout.replicates));
  }

  void run(std::span<const ShadowPoint> points, size_t begin, size_t end) {
    std::fill(counts_.begin(), counts_.end(), 0u);
    for (size_t i = begin; i < end; ++i) {
      addRays(points[i], i, static_cast<uint32_t>(i - begin));
      if (rays_.size() >= kStreamRays) flush();
    }
    flush();
    for (size_t i = begin; i < end; ++i) reduce(i, i - begin);
  }

 private:
  void addRays(const ShadowPoint& point, size_t index, uint32_t local) {
    // Two-sided like the techniques: leave the surface on the side that faces the light's centre.
    const glm::vec3 toLight = sampler_.towardsCentre(point.position);
    const glm::vec3 n = glm::dot(point.normal, toLight) < 0.0f ? -point.normal : point.normal;
    const glm::vec3 origin = point.position + n * tracer_.rayOffset(point.position);
    Random random{seed_ ^ (0x632be59bd9b4e019ull * (index + 1))};
    const float cell = 1.0f / static_cast<float>(layout_.grid);
    for (int r = 0; r < layout_.replicates; ++r)
      for (int y = 0; y < layout_.grid; ++y)
        for (int x = 0; x < layout_.grid; ++x) {
          const ShadowRay ray =
              pattern_ ? sampler_.rayFromDisk(origin, pattern_->point(patternKeys_[index], y * layout_.grid + x))
                       : sampler_.ray(origin, glm::vec2((static_cast<float>(x) + random.uniform()) * cell,
                                                        (static_cast<float>(y) + random.uniform()) * cell));
          rays_.push_back(RTCRay{origin.x, origin.y, origin.z, 0.0f, ray.direction.x, ray.direction.y, ray.direction.z,
                                 0.0f, ray.tfar, 0xffffffffu, 0u, 0u});
          tags_.push_back(local * static_cast<uint32_t>(layout_.replicates) + static_cast<uint32_t>(r));
        }
  }

  void flush() {
    if (rays_.empty()) return;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // one point's rays share an origin and a small light
    embree().rtcOccluded1M(scene_, &context, rays_.data(), static_cast<unsigned>(rays_.size()), sizeof(RTCRay));
    for (size_t k = 0; k < rays_.size(); ++k) counts_[tags_[k]] += rays_[k].tfar >= 0.0f;  // occluded: -inf
    rays_.clear();
    tags_.clear();
  }

  // Mean of the replicate means, and the standard error from their spread (n - 1 in the variance).
  void reduce(size_t index, size_t local) {
    const int n = layout_.replicates;
    const double perReplicate = static_cast<double>(layout_.grid * layout_.grid);
    double sum = 0, sumSq = 0;
    for (int r = 0; r < n; ++r) {
      const double v = counts_[local * static_cast<size_t>(n) + static_cast<size_t>(r)] / perReplicate;
      sum += v, sumSq += v * v;
    }
    const double mean = sum / n;
    const double variance = n > 1 ? std::max(0.0, (sumSq - n * mean * mean) / (n - 1)) : 0.0;
    out_.visibility[index] = static_cast<float>(mean);
    out_.standardError[index] = static_cast<float>(std::sqrt(variance / n));
  }

  RTCScene scene_;
  const ShadowTracer& tracer_;
  const LightSampler& sampler_;
  SampleLayout layout_;
  uint64_t seed_;
  std::span<const uint32_t> patternKeys_;  // izb's light pattern's key per point (with pattern_)
  const IzbLightPattern* pattern_;         // izb's light pattern, or null
  TraceResult& out_;
  std::vector<RTCRay> rays_;
  std::vector<uint32_t> tags_;    // (point in chunk) * replicates + replicate, per ray
  std::vector<uint32_t> counts_;  // unoccluded rays per (point in chunk, replicate)
};

}  // namespace

TraceResult ShadowTracer::trace(std::span<const ShadowPoint> points, const Light& light,
                                const TraceSettings& settings) const {
  const LightSampler sampler(light);
  const bool pattern = settings.izbLightGrid > 0 && !sampler.exact();
  if (pattern && settings.patternKeys.size() != points.size())
    throw std::invalid_argument(fmt::format("trace: izb's light pattern needs a key per point ({} keys, {} points)",
                                            settings.patternKeys.size(), points.size()));
  const SampleLayout layout = sampler.exact() ? SampleLayout{}
                              : pattern       ? SampleLayout{1, settings.izbLightGrid}
                                              : SampleLayout::fromSpp(settings.spp);
  const std::unique_ptr<IzbLightPattern> izbPattern =
      pattern ? std::make_unique<IzbLightPattern>(settings.izbLightGrid) : nullptr;  // shared by the workers
  TraceResult result;
  result.visibility.assign(points.size(), 1.0f);
  result.standardError.assign(points.size(), 0.0f);
  result.spp = layout.spp();
  result.rays = static_cast<uint64_t>(points.size()) * static_cast<uint64_t>(layout.spp());
  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  result.threads = settings.threads > 0 ? settings.threads : static_cast<int>(hardware);
  const Clock::time_point start = Clock::now();
  std::atomic<size_t> next{0};
  auto work = [&] {
    ChunkTracer chunk(impl_->scene, *this, sampler, layout, settings, izbPattern.get(), result);
    for (size_t begin; (begin = next.fetch_add(kChunkPoints)) < points.size();)
      chunk.run(points, begin, std::min(begin + kChunkPoints, points.size()));
  };
  {
    std::vector<std::jthread> workers;
    for (int t = 1; t < result.threads; ++t) workers.emplace_back(work);
    work();
  }
  result.seconds = secondsSince(start);
  impl_->check("tracing");
  return result;
}

std::vector<uint32_t> ShadowTracer::firstHits(std::span<const glm::vec3> origins,
                                               std::span<const glm::vec3> directions) const {
  if (origins.size() != directions.size()) throw std::invalid_argument("firstHits: origins and directions differ");
  std::vector<uint32_t> hits(origins.size(), kNoHit);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = 0; i < origins.size(); ++i) {
    const glm::vec3 o = origins[i], d = directions[i];
    RTCRayHit rh{};
    rh.ray = RTCRay{o.x, o.y, o.z, 0.0f, d.x, d.y, d.z, 0.0f, std::numeric_limits<float>::infinity(), 0xffffffffu, 0u, 0u};
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    embree().rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) hits[i] = rh.hit.primID;
  }
  impl_->check("tracing primary rays");
  return hits;
}

}  // namespace penumbra::reference
