// Blur stage host wrapper: plans the passes (direct weights or box radii), picks the direct plan's layout for the
// device (tiles or runs), then records them. Gaussians of large sigma use the three-box approximation of Wells (1986)
// with Kovesi's choice of widths.
#include "host/stages/blur.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "host/cl/kernel.h"
#include "host/stages/blur_local.h"
#include "host/stages/moments.h"
#include "kernels/shared/blur.h"

namespace penumbra {
namespace {

constexpr int kGaussianBoxes = 3;  // three boxes match a Gaussian's variance to within one texel width

// Widths of n boxes whose variances sum to sigma^2 as closely as odd widths allow.
std::vector<int> gaussianBoxRadii(double sigma) {
  const int n = kGaussianBoxes;
  int lower = static_cast<int>(std::floor(std::sqrt(12.0 * sigma * sigma / n + 1.0)));
  if (lower % 2 == 0) --lower;
  const double m = (12.0 * sigma * sigma - n * lower * lower - 4.0 * n * lower - 3.0 * n) / (-4.0 * lower - 4.0);
  const int smaller = static_cast<int>(std::lround(m));
  std::vector<int> radii;
  for (int i = 0; i < n; ++i) radii.push_back(((i < smaller ? lower : lower + 2) - 1) / 2);
  return radii;
}

std::vector<float> gaussianWeights(double sigma, int radius) {
  std::vector<double> w(2 * radius + 1);
  double total = 0.0;
  for (int k = -radius; k <= radius; ++k) total += w[k + radius] = std::exp(-0.5 * k * k / (sigma * sigma));
  std::vector<float> out;
  for (double v : w) out.push_back(static_cast<float>(v / total));
  return out;
}

// The direct plan's row pass in either layout (blur_rows* or blur_rows_runs*, same arguments): launch shape from the
// local-memory plan (one work-group row per staged line).
void launchRows(Kernel& rows, const ImageShape& shape, const BlurLocalPlan& local, uint64_t bytes,
                std::vector<cl::Event>& events) {
  rows.moves(bytes);
  const size_t lines = size_t(local.rowLines);
  if (local.runs)
    events.push_back(
        rows.launch(Range((shape.width + BLUR_RUNS_SEGMENT - 1) / BLUR_RUNS_SEGMENT, shape.height), Range(1, lines)));
  else
    events.push_back(rows.launch(Range(shape.width, shape.height), Range(BLUR_ROW_TILE, lines)));
}

std::string withOptions(const std::string& options, const std::string& more) {
  return more.empty() ? options : fmt::format("{} {}", options, more);
}

// The direct row pass over an fp32 image (blur_rows or blur_rows_runs): `plan`'s taps from `in` into `out`.
void launchRowPass(Context& ctx, const std::string& options, const Buffer<float>& in, Buffer<float>& out,
                   const ImageShape& shape, const BlurPlan& plan, const Buffer<float>& weights,
                   const BlurLocalPlan& local, std::vector<cl::Event>& events) {
  Kernel rows(ctx, "kernels/blur.cl", local.runs ? "blur_rows_runs" : "blur_rows", "blur",
              withOptions(options, local.rowOptions()));
  rows.args(in, out, shape.width, shape.height, plan.radius, weights, LocalMem{local.rowBytes});
  launchRows(rows, shape, local, 2 * shape.count() * sizeof(float), events);  // floor: read and write the image once
}

// The direct plan's column pass, storing `out` as T (float, or cl_half with STORE_HALF in `options`): runs, tiles of
// the plan's rows, or (no tile fits) taps from global memory.
template <class T>
void launchColumns(Context& ctx, const std::string& options, const Buffer<float>& in, Buffer<T>& out,
                   const ImageShape& shape, const BlurPlan& plan, const Buffer<float>& weights,
                   const BlurLocalPlan& local, std::vector<cl::Event>& events) {
  const int r = plan.radius;
  const uint64_t bytes = shape.count() * (sizeof(float) + sizeof(T));
  if (local.runs) {
    Kernel columns(ctx, "kernels/blur.cl", "blur_columns_runs", "blur", options);
    columns.args(in, out, shape.width, shape.height, r, weights);
    const size_t blocks = (shape.count() / shape.height + BLUR_RUNS_COLUMN_BLOCK - 1) / BLUR_RUNS_COLUMN_BLOCK;
    const size_t strips = (shape.height + BLUR_RUNS_COLUMN_STRIP - 1) / BLUR_RUNS_COLUMN_STRIP;
    events.push_back(columns.moves(bytes).launch(Range(blocks, strips), Range(1, 1)));
  } else if (local.columnRows == 0) {
    Kernel columns(ctx, "kernels/blur.cl", "blur_columns_global", "blur", options);
    columns.args(in, out, shape.width, shape.height, r, weights);
    events.push_back(columns.moves(bytes).launch(Range(shape.width, shape.height), Range(BLUR_COLUMN_TILE, BLUR_ROWS)));
  } else {
    Kernel columns(ctx, "kernels/blur.cl", "blur_columns", "blur", options);
    columns.args(in, out, shape.width, shape.height, r, weights, local.columnRows, LocalMem{local.columnBytes});
    const size_t groupsY = (shape.height + local.columnRows - 1) / local.columnRows;
    events.push_back(
        columns.moves(bytes).launch(Range(shape.width, groupsY * BLUR_ROWS), Range(BLUR_COLUMN_TILE, BLUR_ROWS)));
  }
}

// The local-memory plan of a direct pass pair on `ctx`'s device (the layout resolved from `requested`).
BlurLocalPlan localPlan(Context& ctx, BlurLayout requested, const ImageShape& shape, int radius) {
  const bool runs = resolveBlurLayout(requested, ctx.info(), shape, radius) == BlurLayout::Runs;
  return planBlurLocal(runs, ctx.info().localMemBytes, shape, radius);
}

std::string blurOptions(const ImageShape& shape) { return fmt::format("-DBLUR_CHANNELS={}", shape.channels); }

template <class T>
void checkBlurBuffers(const ImageShape& shape, const Buffer<T>& out, const Buffer<float>& scratch,
                      size_t scratchCount) {
  checkShape(shape, "blur");
  checkBufferSize(out.size(), shape.count(), "blur", "output");
  checkBufferSize(scratch.size(), scratchCount, "blur", "scratch");
}

}  // namespace

BlurLayout resolveBlurLayout(BlurLayout requested, const DeviceInfo& device, const ImageShape& shape, int radius) {
  if (requested != BlurLayout::Auto) return requested;
  const uint64_t lines = uint64_t(BLUR_RUNS_ROWS) * (BLUR_RUNS_SEGMENT + 2 * radius) * sizeof(float) * shape.channels;
  const bool fits = lines <= device.localMemBytes;  // all the runs lines: otherwise tiles, which stage less
  return device.cpuLayouts() && fits ? BlurLayout::Runs : BlurLayout::Tiles;
}

BlurPlan planBlur(const BlurConfig& config) {
  const double scale = config.scale;
  if (!std::isfinite(scale) || scale < 0.0) throw std::invalid_argument(fmt::format("blur: scale {}", scale));
  BlurPlan plan;
  if (config.filter == BlurFilter::Gaussian) {
    const double sigma = double(config.sigma) * scale;
    if (!std::isfinite(sigma) || sigma < 0.0) throw std::invalid_argument(fmt::format("blur: sigma {}", sigma));
    plan.radius = static_cast<int>(std::ceil(3.0 * sigma));
    plan.direct = config.method == BlurMethod::Direct ||
                  (config.method == BlurMethod::Auto && plan.radius <= BLUR_MAX_DIRECT_RADIUS);
    if (plan.radius == 0)
      plan.weights = {1.0f};
    else if (plan.direct)
      plan.weights = gaussianWeights(sigma, plan.radius);
    else
      plan.boxRadii = gaussianBoxRadii(sigma);
  } else {
    if (config.radius < 0) throw std::invalid_argument(fmt::format("blur: box radius {}", config.radius));
    plan.radius = static_cast<int>(std::lround(config.radius * scale));
    plan.direct = config.method == BlurMethod::Direct ||
                  (config.method == BlurMethod::Auto && plan.radius <= BLUR_MAX_DIRECT_RADIUS);
    if (plan.direct)
      plan.weights.assign(2 * plan.radius + 1, 1.0f / float(2 * plan.radius + 1));
    else
      plan.boxRadii = {plan.radius};
  }
  plan.direct = plan.direct || plan.radius == 0;
  if (plan.direct && plan.radius > BLUR_DIRECT_RADIUS_LIMIT)
    throw std::invalid_argument(
        fmt::format("blur: direct radius {} above {}; use running sums", plan.radius, BLUR_DIRECT_RADIUS_LIMIT));
  if (plan.direct) plan.boxRadii.clear();
  return plan;
}

std::vector<cl::Event> blur(Context& ctx, const Buffer<float>& in, Buffer<float>& out, Buffer<float>& scratch,
                            const ImageShape& shape, const BlurConfig& config) {
  checkBlurBuffers(shape, out, scratch, shape.count());
  checkBufferSize(in.size(), shape.count(), "blur", "input");
  const BlurPlan plan = planBlur(config);
  if (shape.texels() == 0) return {};
  const std::string options = blurOptions(shape);
  const uint32_t w = shape.width, h = shape.height;
  std::vector<cl::Event> events;
  const uint64_t passBytes = 2 * shape.count() * sizeof(float);  // floor of every pass: read and write the image once

  if (plan.direct) {
    const BlurLocalPlan local = localPlan(ctx, config.layout, shape, plan.radius);
    Buffer<float> weights = Buffer<float>::copyOf(ctx, plan.weights);
    launchRowPass(ctx, options, in, scratch, shape, plan, weights, local, events);
    launchColumns(ctx, options, scratch, out, shape, plan, weights, local, events);
    return events;
  }

  // Running sums ping-pong in -> scratch -> out -> scratch ... so that the last pass writes `out`. Where the runs
  // layout runs and no box is wider than BLUR_RUNS_MAX_BOX_RADIUS, each box pass takes direct taps of equal weight
  // instead: the same box filter to fp32 rounding (so the same result as the running sums on other devices), faster
  // there than a running sum's serial chain.
  const int widest = *std::max_element(plan.boxRadii.begin(), plan.boxRadii.end());
  const bool directBoxes = widest <= BLUR_RUNS_MAX_BOX_RADIUS &&
                           resolveBlurLayout(config.layout, ctx.info(), shape, widest) == BlurLayout::Runs;
  std::optional<Kernel> rows, columns;  // the running-sum kernels, when they run
  if (!directBoxes) {
    rows.emplace(ctx, "kernels/blur.cl", "blur_box_rows", "blur", options);
    columns.emplace(ctx, "kernels/blur.cl", "blur_box_columns", "blur", options);
  }
  const size_t passes = 2 * plan.boxRadii.size();
  const Buffer<float>* src = &in;
  for (size_t pass = 0; pass < passes; ++pass) {
    Buffer<float>* dst = (passes - pass) % 2 == 1 ? &out : &scratch;
    const int r = plan.boxRadii[pass % plan.boxRadii.size()];
    const int segment = std::max(BLUR_SEGMENT, 2 * r + 1);
    if (directBoxes) {
      BlurPlan box;
      box.radius = r;
      box.weights.assign(2 * r + 1, 1.0f / float(2 * r + 1));
      Buffer<float> weights = Buffer<float>::copyOf(ctx, box.weights);
      const BlurLocalPlan local = planBlurLocal(true, ctx.info().localMemBytes, shape, r);
      if (pass < plan.boxRadii.size())
        launchRowPass(ctx, options, *src, *dst, shape, box, weights, local, events);
      else
        launchColumns(ctx, options, *src, *dst, shape, box, weights, local, events);
    } else if (pass < plan.boxRadii.size()) {
      rows->args(*src, *dst, w, h, r, segment);
      events.push_back(rows->moves(passBytes).launch(Range((w + segment - 1) / segment, h), Range(1, 64)));
    } else {
      columns->args(*src, *dst, w, h, r, segment);
      events.push_back(columns->moves(passBytes).launch(Range(w, (h + segment - 1) / segment), Range(64, 1)));
    }
    src = dst;
  }
  return events;
}

namespace {

// ESM's moments blurred in log space (kernels/blur.cl blur_log_*): the depths encoded in fp32 into `encoded`, a row
// pass into `rows`, a column pass into `out` in its storage (`out` may be `encoded`).
template <class T>
std::vector<cl::Event> blurLogPasses(Context& ctx, const Buffer<float>& depth, const MomentsConfig& moments,
                                     Buffer<float>& encoded, Buffer<float>& rows, Buffer<T>& out,
                                     const ImageShape& shape, const BlurPlan& plan) {
  std::vector<cl::Event> events{computeMoments(ctx, depth, shape.width, shape.height, moments, encoded)};
  const std::string options = fmt::format("{} -DBLUR_LOG_RADIUS={}", blurOptions(shape), plan.radius);
  Buffer<float> weights = Buffer<float>::copyOf(ctx, plan.weights);
  const float exponent = esmClampExponent(moments.esmExponent, moments.storage);
  const Range global((shape.width + BLUR_RUN_FLOATS - 1) / BLUR_RUN_FLOATS, shape.height), local(1, 8);
  Kernel rowPass(ctx, "kernels/blur.cl", "blur_log_rows", "blur", options);
  events.push_back(rowPass.args(encoded, rows, shape.width, shape.height, weights, exponent)
                       .moves(shape.count() * 2 * sizeof(float))  // floor: read and write the image once
                       .launch(global, local));
  Kernel columnPass(ctx, "kernels/blur.cl", "blur_log_columns", "blur",
                    withOptions(options, storageOptions(storageOf<T>())));
  events.push_back(columnPass.args(rows, out, shape.width, shape.height, weights, exponent)
                       .moves(shape.count() * (sizeof(float) + sizeof(T)))
                       .launch(global, local));
  return events;
}

// ESM's blur in log space (esmLogSpace) through `out` itself (fp32) or, for half output, through two fp32 images in
// the scratch. Direct plans only: running sums would need e^(c d), which overflows at the exponents log space is for.
template <class T>
std::vector<cl::Event> blurLogEsmInto(Context& ctx, const Buffer<float>& depth, const MomentsConfig& moments,
                                      Buffer<T>& out, Buffer<float>& scratch, const ImageShape& shape,
                                      const BlurPlan& plan) {
  if (!plan.direct)
    throw std::invalid_argument(
        fmt::format("blur: ESM's log-space blur (exponents outside [{}, {}]) takes direct "
                    "taps, not running sums (radius at most {} under BlurMethod::Auto)",
                    MOMENTS_ESM_LINEAR_MIN_EXPONENT, MOMENTS_ESM_LINEAR_EXPONENT, BLUR_MAX_DIRECT_RADIUS));
  if constexpr (storageOf<T>() == MomentStorage::Float16) {
    Buffer<float> pass = scratch.region(ctx, 0, shape.count());
    Buffer<float> image = scratch.region(ctx, Buffer<float>::alignedCount(ctx, shape.count()), shape.count());
    return blurLogPasses(ctx, depth, moments, image, pass, out, shape, plan);
  } else {
    return blurLogPasses(ctx, depth, moments, out, scratch, out, shape, plan);
  }
}

// blurMoments into `out` of element type T (the storage: float or cl_half).
template <class T>
std::vector<cl::Event> blurMomentsInto(Context& ctx, const Buffer<float>& depth, const MomentsConfig& moments,
                                       Buffer<T>& out, Buffer<float>& scratch, uint32_t width, uint32_t height,
                                       const BlurConfig& config) {
  constexpr MomentStorage storage = storageOf<T>();
  const ImageShape shape{width, height, momentChannels(moments.kind)};
  const MomentsParams params = momentsParams(moments, width, height);
  checkBlurBuffers(shape, out, scratch, blurMomentsScratch(ctx, shape, config, storage, moments.kind));
  checkBufferSize(depth.size(), size_t(width) * height, "blur", "depth");
  const BlurPlan plan = planBlur(config);
  if (shape.texels() == 0) return {};
  if (moments.kind == MomentKind::Esm && params.esmLogSpace)
    return blurLogEsmInto(ctx, depth, moments, out, scratch, shape, plan);
  const int kind = momentsKindId(moments.kind);
  if (!plan.direct) {  // running sums read each texel twice: encode once, then blur in place
    if constexpr (storage == MomentStorage::Float32) {
      std::vector<cl::Event> events{computeMoments(ctx, depth, width, height, moments, out)};
      for (cl::Event& e : blur(ctx, out, out, scratch, shape, config)) events.push_back(std::move(e));
      return events;
    } else {  // ... in fp32 beside the scratch, then store as half
      Buffer<float> image = scratch.region(ctx, Buffer<float>::alignedCount(ctx, shape.count()), shape.count());
      Buffer<float> pass = scratch.region(ctx, 0, shape.count());
      std::vector<cl::Event> events{computeMoments(ctx, depth, width, height, moments, image)};
      for (cl::Event& e : blur(ctx, image, image, pass, shape, config)) events.push_back(std::move(e));
      events.push_back(packMomentsHalf(ctx, image, shape.count(), out));
      return events;
    }
  }
  const std::string options = fmt::format("{} -DBLUR_MOMENTS={}", blurOptions(shape), kind);
  Buffer<float> weights = Buffer<float>::copyOf(ctx, plan.weights);
  std::vector<cl::Event> events;
  const BlurLocalPlan local = localPlan(ctx, config.layout, shape, plan.radius);
  Kernel rows(ctx, "kernels/blur.cl", local.runs ? "blur_rows_runs_moments" : "blur_rows_moments", "blur",
              withOptions(options, local.rowOptions()));
  rows.args(depth, scratch, width, height, plan.radius, weights, LocalMem{local.rowBytes}, params);
  // Floor: read the depth map, write the row-blurred moments.
  launchRows(rows, shape, local, shape.texels() * sizeof(float) + shape.count() * sizeof(float), events);
  launchColumns(ctx, fmt::format("{} {}", options, storageOptions(storage)), scratch, out, shape, plan, weights, local,
                events);
  return events;
}

}  // namespace

size_t blurMomentsScratch(Context& ctx, const ImageShape& shape, const BlurConfig& config, MomentStorage storage,
                          MomentKind kind) {
  if (storage == MomentStorage::Float16 && (kind == MomentKind::Esm || !planBlur(config).direct))
    return Buffer<float>::alignedCount(ctx, shape.count()) + shape.count();
  return shape.count();
}

std::vector<cl::Event> blurMoments(Context& ctx, const Buffer<float>& depth, const MomentsConfig& moments,
                                   Buffer<float>& out, Buffer<float>& scratch, uint32_t width, uint32_t height,
                                   const BlurConfig& config) {
  return blurMomentsInto(ctx, depth, moments, out, scratch, width, height, config);
}

std::vector<cl::Event> blurMoments(Context& ctx, const Buffer<float>& depth, const MomentsConfig& moments,
                                   Buffer<cl_half>& out, Buffer<float>& scratch, uint32_t width, uint32_t height,
                                   const BlurConfig& config) {
  checkHalfMoments(moments, "blur");
  return blurMomentsInto(ctx, depth, moments, out, scratch, width, height, config);
}

}  // namespace penumbra
