// Blur stage: separable Gaussian or box filter with clamp-to-edge over 1-, 2- or 4-channel float images.
// Small footprints run a direct weighted sum (tiles through local memory on GPUs, float16 runs on CPUs); large
// ones run box running sums whose cost does not depend on the radius (a Gaussian becomes three boxes, Wells
// 1986). Kernels: kernels/blur.cl.
#pragma once

#include <CL/opencl.hpp>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/stages/image_shape.h"
#include "host/stages/moments.h"

namespace penumbra {

enum class BlurFilter { Gaussian, Box };
enum class BlurMethod { Auto, Direct, RunningSums };
// How the direct plan's passes map onto work-items. Tiles: an item per output texel, each work-group staging its
// tile in local memory (GPUs). Runs: items sum runs of 16 consecutive floats of a row as one float16, several side by
// side (CPUs, whose OpenCL compilers vectorise explicit vectors better than across work-items). Both add each texel's
// taps in the same order: equal bit for bit on PoCL. Auto: Runs on CPU devices, Tiles elsewhere.
enum class BlurLayout { Auto, Tiles, Runs };

struct BlurConfig {
  BlurFilter filter = BlurFilter::Gaussian;
  float sigma = 1.0f;  // Gaussian standard deviation in texels (taps out to ceil(3 sigma))
  int radius = 1;      // box half-width in texels: 2 radius + 1 taps
  float scale = 1.0f;  // per-split footprint scale (a parallel split's zoom): multiplies sigma and radius
  BlurMethod method = BlurMethod::Auto;
  BlurLayout layout = BlurLayout::Auto;  // direct plans only
};

// What a configuration runs, computed on the host before anything is enqueued.
struct BlurPlan {
  bool direct = true;
  int radius = 0;              // direct: taps are [-radius, radius]
  std::vector<float> weights;  // direct: 2 radius + 1 normalised weights
  std::vector<int> boxRadii;   // running sums: one box per pass, applied along rows then columns
};

// Throws std::invalid_argument for non-finite or negative sizes, or a direct radius above
// BLUR_DIRECT_RADIUS_LIMIT.
BlurPlan planBlur(const BlurConfig& config);

// The direct plan's layout that `requested` runs on `device` for `shape` at `radius` (Tiles or Runs): Auto is Runs
// on CPU devices (DeviceInfo::cpuLayouts) whose local memory holds the runs row pass's four lines (up to 48 KiB at
// radius 128, 4 channels), Tiles otherwise. Either layout then stages as many lines as fit (blur_local.h).
BlurLayout resolveBlurLayout(BlurLayout requested, const DeviceInfo& device, const ImageShape& shape, int radius);

// Blurs `in` into `out` (which may be the same buffer) through `scratch`; all hold shape.count() floats.
// Launches "blur/blur_rows" + "blur/blur_columns" (tiles), "blur/blur_rows_runs" + "blur/blur_columns_runs" (runs),
// or "blur/blur_box_rows" + "blur/blur_box_columns" per box (on the runs layout, boxes up to
// BLUR_RUNS_MAX_BOX_RADIUS run as direct equal-weight runs passes instead: the same filter, faster on CPUs).
std::vector<cl::Event> blur(Context& ctx, const Buffer<float>& in, Buffer<float>& out, Buffer<float>& scratch,
                            const ImageShape& shape, const BlurConfig& config);

// The moments stage fused into the blur ("Fusable with ... the first blur pass", issue 4): blurs the moments
// of `depth` (width*height light depths; computeMoments' encoding, any kind but LVSM) into `out`
// (width*height*momentChannels floats) without writing the unblurred moments: the same values, bit for bit,
// as computeMoments then blur. Direct plans encode while staging the row pass ("blur/blur_rows_moments", or
// "blur/blur_rows_runs_moments");
// running sums read each texel twice, so they run computeMoments into `out` first, then blur it in place. ESM
// (MomentKind::Esm) with an exponent in log space (esmLogSpace) blurs its depths in log space instead
// ("blur/blur_log_rows" + "blur/blur_log_columns"; kernels/shared/moments.h moments_log_mix) after computeMoments
// into `out`, on direct plans only.
std::vector<cl::Event> blurMoments(Context& ctx, const Buffer<float>& depth, const MomentsConfig& moments,
                                   Buffer<float>& out, Buffer<float>& scratch, uint32_t width, uint32_t height,
                                   const BlurConfig& config);
// The same moments stored as half (moments.storage Float16): direct plans store half from their column pass
// (blur_columns or blur_columns_runs built with STORE_HALF), equal to the fp32 result rounded to nearest even; running
// sums blur in fp32 in `scratch` and pack ("moments/moments_pack_half"). `scratch` holds blurMomentsScratch floats.
std::vector<cl::Event> blurMoments(Context& ctx, const Buffer<float>& depth, const MomentsConfig& moments,
                                   Buffer<cl_half>& out, Buffer<float>& scratch, uint32_t width, uint32_t height,
                                   const BlurConfig& config);
// Floats of scratch blurMoments needs: the image (shape.count()), and for half output through running sums or ESM
// (its log-space passes) the fp32 moments too (at an aligned offset after it).
size_t blurMomentsScratch(Context& ctx, const ImageShape& shape, const BlurConfig& config, MomentStorage storage,
                          MomentKind kind);

}  // namespace penumbra
