// Google Benchmark of the filtering stages (moments, blur, SAT, pyramid, reduce) on 2048^2 and 4096^2
// float2 images: device time from OpenCL profiling events (warm-up excluded) beside the bandwidth floor,
// i.e. the minimum bytes a stage must move divided by the device copy bandwidth measured here first.
// Device: PENUMBRA_DEVICE (or "auto"). With Boost.Compute available, its inclusive_scan over the same
// data runs side by side with the SAT.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/cl/kernel.h"
#include "host/cl/profiler.h"
#include "host/stages/blur.h"
#include "host/stages/moments.h"
#include "host/stages/pyramid.h"
#include "host/stages/reduce.h"
#include "host/stages/sat.h"
#include "tools/selftest/reference/inputs.h"

#if __has_include(<boost/compute/algorithm/inclusive_scan.hpp>)
#define PENUMBRA_BENCH_BOOST_COMPUTE 1
#include <boost/compute/algorithm/inclusive_scan.hpp>
#include <boost/compute/command_queue.hpp>
#include <boost/compute/container/vector.hpp>
#endif

namespace penumbra {
namespace {

// Device time in ms of everything `work` enqueues.
double deviceMs(Context& ctx, const std::function<void()>& work) {
  Profiler profiler;
  ProfilerScope scope(ctx, profiler);
  work();
  ctx.finish();
  if (profiler.empty()) throw std::runtime_error("deviceMs: the work enqueued nothing on the profiled queue");
  double ms = 0.0;
  for (const PassTime& pass : profiler.resolve())
    if (pass.name.rfind("transfer/", 0) != 0) ms += pass.ms;
  return ms;
}

// Host wall-clock ms of `work` until the queue drains: for code whose launches bypass our profiler
// (Boost.Compute) and for a like-for-like comparison with it.
double wallMs(Context& ctx, const std::function<void()>& work) {
  ctx.finish();
  const auto start = std::chrono::steady_clock::now();
  work();
  ctx.finish();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Copy bandwidth in bytes/s: copy_float4 over 256 MiB (64 MiB on CPUs), best of 5.
double copyBandwidth(Context& ctx) {
  const size_t count = (ctx.info().isGpu() ? 256u : 64u) * 1024 * 1024 / 16;
  Buffer<cl_float4> in(ctx, count), out(ctx, count);
  in.fill(ctx, {{1.0f, 2.0f, 3.0f, 4.0f}});
  Kernel copy(ctx, "kernels/fill.cl", "copy_float4", "bench");
  double best = 1e30;
  for (int i = 0; i < 6; ++i) {
    const double ms = deviceMs(ctx, [&] { copy.args(in, out, uint32_t(count)).launch(count, 256); });
    if (i > 0) best = std::min(best, ms);  // the first run warms up
  }
  return 2.0 * count * 16 / (best * 1e-3);
}

struct Setup {
  Context& ctx;
  double bandwidth;  // bytes/s
};

// Registers `name/size` timing `work` (after one warm-up) against a floor of `floorBytes` moved.
void add(Setup& setup, const std::string& name, uint32_t size, double floorBytes,
         std::function<std::function<void()>(uint32_t)> prepare, bool wallClock = false) {
  benchmark::RegisterBenchmark(fmt::format("{}/{}", name, size).c_str(),
                               [&setup, size, floorBytes, prepare, wallClock](benchmark::State& state) {
                                 const std::function<void()> work = prepare(size);
                                 const auto time = wallClock ? wallMs : deviceMs;
                                 time(setup.ctx, work);
                                 double totalMs = 0.0;
                                 for (auto _ : state) {
                                   const double ms = time(setup.ctx, work);
                                   totalMs += ms;
                                   state.SetIterationTime(ms * 1e-3);
                                 }
                                 const double meanUs = totalMs * 1e3 / double(state.iterations());
                                 const double floorUs = floorBytes / setup.bandwidth * 1e6;
                                 state.counters["floor_us"] = floorUs;
                                 state.counters["x_floor"] = meanUs / floorUs;  // 1 = at the bandwidth floor
                                 state.counters["floor_GB/s"] = floorBytes / (meanUs * 1e3);
                               })
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
}

template <class T>
void addSat(Setup& s, const std::string& name, uint32_t size, SatConfig config, bool wallClock = false) {
  const double texels = double(size) * size;
  add(
      s, name, size, texels * (8 + 2 * sizeof(T)),
      [&s, config](uint32_t n) {
        const ImageShape shape{n, n, 2};
        auto image =
            std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(shape.count(), n)));
        auto table = std::make_shared<Buffer<T>>(s.ctx, shape.count());
        auto offset = std::make_shared<Buffer<float>>(s.ctx, 4);
        return std::function<void()>(
            [&s, image, table, offset, shape, config] { computeSat(s.ctx, *image, shape, *table, *offset, config); });
      },
      wallClock);
}

// VSM moments fused into a Gaussian blur of sigma 2, stored as T (float, or cl_half for fp16 storage).
template <class T>
void addFusedBlur(Setup& s, const std::string& name, uint32_t size, double floorBytes) {
  add(s, name, size, floorBytes, [&s](uint32_t n) {
    auto depth = std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(size_t(n) * n, 1)));
    auto out = std::make_shared<Buffer<T>>(s.ctx, size_t(n) * n * 2);
    auto scratch = std::make_shared<Buffer<float>>(s.ctx, size_t(n) * n * 2);
    BlurConfig config;
    config.sigma = 2.0f;
    MomentsConfig moments;
    moments.storage = storageOf<T>();
    return std::function<void()>([&s, depth, out, scratch, n, config, moments] {
      blurMoments(s.ctx, *depth, moments, *out, *scratch, n, n, config);
    });
  });
}

void registerAll(Setup& s) {
  for (uint32_t size : {2048u, 4096u}) {
    const double texels = double(size) * size;
    add(s, "moments_vsm", size, texels * 12, [&s](uint32_t n) {
      auto depth =
          std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(size_t(n) * n, 1)));
      auto out = std::make_shared<Buffer<float>>(s.ctx, size_t(n) * n * 2);
      return std::function<void()>([&s, depth, out, n] { computeMoments(s.ctx, *depth, n, n, {}, *out); });
    });
    for (float sigma : {2.0f, 8.0f, 16.0f}) {
      add(s, fmt::format("blur_gauss_sigma{}", sigma), size, texels * 16, [&s, sigma](uint32_t n) {
        const ImageShape shape{n, n, 2};
        auto in =
            std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(shape.count(), 2)));
        auto out = std::make_shared<Buffer<float>>(s.ctx, shape.count());
        auto scratch = std::make_shared<Buffer<float>>(s.ctx, shape.count());
        BlurConfig config;
        config.sigma = sigma;
        return std::function<void()>(
            [&s, in, out, scratch, shape, config] { blur(s.ctx, *in, *out, *scratch, shape, config); });
      });
    }
    // The moments stage fused into the blur's row pass (what vsm runs): depth in, blurred moments out. Floor:
    // read the depth, write the row pass, read it back and write the moments (4 + 8 + 8 + 8 bytes a texel; 4
    // fewer when the column pass stores half, moment-storage=fp16).
    addFusedBlur<float>(s, "moments_vsm_fused_blur_sigma2", size, texels * 28);
    addFusedBlur<cl_half>(s, "moments_vsm_fused_blur_sigma2_fp16", size, texels * 24);
    SatConfig offsetGiven;  // the production path on this device (Auto), with a known offset
    offsetGiven.offset = std::array<float, 4>{0.5f, 0.5f, 0.0f, 0.0f};
    SatConfig tiledConfig = offsetGiven, linesConfig = offsetGiven;
    tiledConfig.algorithm = SatAlgorithm::Tiled;
    linesConfig.algorithm = SatAlgorithm::Lines;
    addSat<float>(s, "sat_tiled_fp32_offset_explicit", size, tiledConfig);
    addSat<float>(s, "sat_lines_fp32_offset_explicit", size, linesConfig);
    addSat<float>(s, "sat_auto_fp32_offset", size, offsetGiven);
    addSat<float>(s, "sat_auto_fp32_zeromean", size, {});
    addSat<uint32_t>(s, "sat_auto_fixed32", size, {});
    addSat<uint64_t>(s, "sat_auto_fixed64", size, {});
    if (s.ctx.info().fp64) addSat<double>(s, "sat_auto_fp64", size, {});
    SatConfig hensley = offsetGiven;
    hensley.algorithm = SatAlgorithm::Hensley;
    addSat<float>(s, "sat_hensley_fp32_offset", size, hensley);
#ifdef PENUMBRA_BENCH_BOOST_COMPUTE
    // Side by side on wall clock: Boost.Compute's launches bypass our profiler. Its 1-D scan of the same
    // 2 n^2 floats does less work than a SAT (one axis, no carries across rows).
    addSat<float>(s, "sat_auto_fp32_offset_wall", size, offsetGiven, /*wallClock=*/true);
    add(
        s, "boost_compute_inclusive_scan_wall", size, texels * 16,
        [&s](uint32_t n) {
          namespace bc = boost::compute;
          // Its own context and queue on our device: Boost.Compute on a wrapped foreign queue hung on PoCL.
          const bc::device device(s.ctx.device()(), true);
          auto queue = std::make_shared<bc::command_queue>(bc::context(device), device);
          const std::vector<float> host = ref::randomUnitImage(size_t(n) * n * 2, 3);
          auto data = std::make_shared<bc::vector<float>>(host.begin(), host.end(), *queue);
          auto out = std::make_shared<bc::vector<float>>(data->size(), queue->get_context());
          return std::function<void()>([queue, data, out] {
            bc::inclusive_scan(data->begin(), data->end(), out->begin(), *queue);
            queue->finish();
          });
        },
        /*wallClock=*/true);
#endif
    add(s, "pyramid_mips_float2", size, texels * (8 + 8.0 / 3), [&s](uint32_t n) {
      const ImageShape shape{n, n, 2};
      auto base =
          std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(shape.count(), 4)));
      auto mips = std::make_shared<Buffer<float>>(s.ctx, pyramidLayout(n, n, 1).texels * 2);
      return std::function<void()>([&s, base, mips, shape] { computeMomentMips(s.ctx, *base, shape, *mips); });
    });
    add(s, "pyramid_mips_half2", size, texels * (4 + 4.0 / 3), [&s](uint32_t n) {
      const ImageShape shape{n, n, 2};
      std::vector<cl_half> halves(shape.count(), 0x3800);  // 0.5 each: the values do not change the work
      auto base = std::make_shared<Buffer<cl_half>>(s.ctx, std::span<const cl_half>(halves));
      auto mips = std::make_shared<Buffer<cl_half>>(s.ctx, pyramidLayout(n, n, 1).texels * 2);
      return std::function<void()>([&s, base, mips, shape] { computeMomentMips(s.ctx, *base, shape, *mips); });
    });
    add(s, "pyramid_minmax", size, texels * (4 + 8 * 4.0 / 3), [&s](uint32_t n) {
      auto depth =
          std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(size_t(n) * n, 5)));
      auto out = std::make_shared<Buffer<cl_float2>>(s.ctx, pyramidLayout(n, n, 0).texels);
      return std::function<void()>([&s, depth, out, n] { computeMinMaxPyramid(s.ctx, *depth, n, n, *out); });
    });
    // Levels 1.. alone, what pcss and vssm build (level 0 stays the map): the device's default schedule (rows on
    // CPUs) beside the batched one.
    for (const auto& [name, schedule] : {std::pair{"pyramid_minmax_levels", PyramidSchedule::Auto},
                                         std::pair{"pyramid_minmax_levels_batched", PyramidSchedule::Batched}})
      add(s, name, size, texels * (4 + 8.0 / 3), [&s, schedule](uint32_t n) {
        auto depth =
            std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(size_t(n) * n, 5)));
        auto out = std::make_shared<Buffer<cl_float2>>(s.ctx, pyramidLayout(n, n, 1).texels);
        return std::function<void()>(
            [&s, depth, out, n, schedule] { computeMinMaxLevels(s.ctx, *depth, n, n, *out, {schedule}); });
      });
    add(s, "reduce_lloyd_k4", size, texels * 8, [&s](uint32_t n) {
      const size_t count = size_t(n) * n;
      auto x = std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(count, 6)));
      auto w = std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(ref::randomUnitImage(count, 7)));
      const std::vector<float> splits{0.25f, 0.5f, 0.75f};
      auto boundaries = std::make_shared<Buffer<float>>(s.ctx, std::span<const float>(splits));
      auto out = std::make_shared<Buffer<LloydStats>>(s.ctx, 4);
      return std::function<void()>(
          [&s, x, w, boundaries, out, count] { reduceLloydStats(s.ctx, *x, *w, count, *boundaries, 4, *out); });
    });
  }
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  try {
    benchmark::Initialize(&argc, argv);
    penumbra::Context ctx;
    const double bandwidth = penumbra::copyBandwidth(ctx);
    std::printf("device: %s\ncopy bandwidth: %.1f GB/s (floor = minimum bytes / this)\n", ctx.info().name.c_str(),
                bandwidth * 1e-9);
    penumbra::Setup setup{ctx, bandwidth};
    penumbra::registerAll(setup);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stages_bench: %s\n", e.what());
    return 1;
  }
}
