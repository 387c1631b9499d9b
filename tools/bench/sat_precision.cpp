// Regenerates the table of docs/sat-precision.md: for each SAT storage mode (host/stages/sat.h), image size and
// box width, the largest error of box means read through sat_box_mean against a double-precision table
// (tools/selftest/reference/sat_ref.h). Prints the markdown table on stdout; 4096^2 takes about a minute on PoCL.
// Usage: sat_precision [--device SPEC] (default: PENUMBRA_DEVICE, else auto).
#include <fmt/format.h>

#include <CL/opencl.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/cl/kernel.h"
#include "host/stages/sat.h"
#include "tools/selftest/kernels/probes.h"
#include "tools/selftest/reference/sat_ref.h"

namespace penumbra {
namespace {

// A box in texel coordinates, as the sat_test_box kernel reads it.
struct Box {
  float lox, loy, hix, hiy;
};

// The largest error of box means read through sat_box_mean, against a
// double table, for VSM-like moments (d, d^2) of a noisy depth ramp, per mode, image size and box width.
template <class T>
double worstBoxMeanError(Context& ctx, const std::vector<float>& image, const ImageShape& shape,
                         const std::vector<double>& exact, int boxWidth, bool zeroMean, int fractionBits = -1) {
  Buffer<float> in(ctx, std::span<const float>(image)), offset(ctx, 4);
  Buffer<T> table(ctx, shape.count());
  SatConfig config;
  config.algorithm = SatAlgorithm::Tiled;  // the production (GPU) path
  config.zeroMean = zeroMean;
  config.fractionBits = fractionBits;
  computeSat(ctx, in, shape, table, offset, config);
  const SatTableDesc desc = satDesc(shape, satMode<T>(), fractionBits);
  std::mt19937 rng(boxWidth);
  std::vector<Box> boxes;
  for (int i = 0; i < 4000; ++i) {
    const float x = float(rng() % (shape.width - boxWidth + 1)), y = float(rng() % (shape.height - boxWidth + 1));
    boxes.push_back({x, y, x + boxWidth, y + boxWidth});
  }
  Buffer<cl_float4> boxBuffer(ctx, boxes.size());
  boxBuffer.upload(ctx, std::span<const cl_float4>(reinterpret_cast<const cl_float4*>(boxes.data()), boxes.size()));
  Buffer<float> sums(ctx, boxes.size() * 2), means(ctx, boxes.size() * 2);
  Kernel(ctx, "tools/selftest/kernels/sat_probe.cl", "sat_test_box", "sat", satBuildOptions(desc))
      .args(table, desc, offset, boxBuffer, uint32_t(boxes.size()), sums, means)
      .launch(boxes.size(), 64);
  const std::vector<float> got = means.download(ctx);
  double worst = 0.0;
  auto at = [&](int x, int y, int ch) {
    return x == 0 || y == 0 ? 0.0 : exact[((y - 1) * size_t(shape.width) + x - 1) * 2 + ch];
  };
  for (size_t b = 0; b < boxes.size(); ++b)
    for (int ch = 0; ch < 2; ++ch) {
      const int x0 = int(boxes[b].lox), y0 = int(boxes[b].loy), x1 = x0 + boxWidth, y1 = y0 + boxWidth;
      const double mean = (at(x1, y1, ch) - at(x0, y1, ch) - at(x1, y0, ch) + at(x0, y0, ch)) / (boxWidth * boxWidth);
      worst = std::max(worst, std::abs(got[b * 2 + ch] - mean));
    }
  return worst;
}

int report(Context& ctx) {
  const int widths[] = {3, 15, 63, 255};
  const int bits32 = satFractionBits(SAT_MODE_FIXED32, 255.0 * 255.0, 1.0);  // exact up to the widest box
  std::string table = fmt::format(
      "| size | box | fp32 raw | fp32 zero-mean | fixed32 ({} frac. bits) | "
      "fixed64 (32 frac. bits) | fp64 |\n|---|---|---|---|---|---|---|\n",
      bits32);
  for (uint32_t size : {256u, 1024u, 2048u, 4096u}) {
    const ImageShape shape{size, size, 2};
    std::mt19937 rng(size);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    std::vector<float> image(shape.count());
    for (uint32_t y = 0; y < size; ++y)
      for (uint32_t x = 0; x < size; ++x) {
        const float d = std::clamp(0.2f + 0.6f * float(x + y) / float(2 * size) + noise(rng), 0.0f, 1.0f);
        image[(size_t(y) * size + x) * 2] = d, image[(size_t(y) * size + x) * 2 + 1] = d * d;
      }
    const std::vector<double> exact = ref::satDouble(image, shape);
    for (int width : widths) {
      if (width > int(size)) continue;
      table += fmt::format("| {}² | {} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {:.1e} |\n", size, width,
                           worstBoxMeanError<float>(ctx, image, shape, exact, width, false),
                           worstBoxMeanError<float>(ctx, image, shape, exact, width, true),
                           worstBoxMeanError<uint32_t>(ctx, image, shape, exact, width, false, bits32),
                           worstBoxMeanError<uint64_t>(ctx, image, shape, exact, width, false),
                           worstBoxMeanError<double>(ctx, image, shape, exact, width, false));
    }
  }
  std::printf("%s", table.c_str());
  return 0;
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  std::string device = std::getenv("PENUMBRA_DEVICE") ? std::getenv("PENUMBRA_DEVICE") : "auto";
  if (argc == 3 && std::string(argv[1]) == "--device") device = argv[2];
  else if (argc != 1) {
    std::fprintf(stderr, "usage: sat_precision [--device SPEC]\n");
    return 2;
  }
  try {
    penumbra::Context ctx(device);
    penumbra::withProbeKernels(ctx);
    return penumbra::report(ctx);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sat_precision: %s\n", e.what());
    return 1;
  }
}
