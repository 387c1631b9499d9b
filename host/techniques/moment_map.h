// The moment shadow map shared by vsm, evsm2/4, esm and msm: shadow map -> moments over the map's
// [zNear, zFar] (host/stages/moments.h) -> optional separable blur -> optional mip chain for trilinear
// lookups; then one visibility kernel with the MomentShade arguments (kernels/shared/moment_map.h) and the
// debug layers (filtered moments, variance, filter width). savsm builds on the same pieces with a SAT.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "host/cl/buffer.h"
#include "host/stages/blur.h"
#include "host/stages/image_shape.h"
#include "host/stages/moments.h"
#include "host/techniques/shadow_map.h"
#include "kernels/shared/moment_map.h"

namespace penumbra {

// blur-radius (auto by default: host/techniques/shadow_map.h autoRadiusParams; resolveAutoRadius per frame),
// blur-radius-quantile, blur-radius-max, blur-filter, moment-filtering and filter-bias: the techniques that blur and
// mip their moments.
std::vector<ParamSpec> momentFilterParams();
// esm's and evsm2's blur-radius-max (2, the fixed default before auto): a positive warp without the negative one lets
// the deeper receivers inside a wider kernel light the pixel (ESM's non-planar receiver failure, at contact lines).
void positiveWarpBlurMax(std::vector<ParamSpec>& params);
// filter-bias: receiver-plane bias over the filter footprint (every moment technique).
ParamSpec filterBiasParam();
// shadowMapParams(), momentFilterParams(), then `extra`: a blurred-moments technique's parameter list.
std::vector<ParamSpec> filteredMomentParams(const std::vector<ParamSpec>& extra);
// filteredMomentParams(extra) and moment-storage (fp32 or fp16): vsm, evsm2/4, esm, msm and psvsm.
std::vector<ParamSpec> momentMapParams(const std::vector<ParamSpec>& extra);
MomentStorage momentStorage(const Params& params);  // reads moment-storage
// bleeding-reduction: linstep amount, 0 = off (vsm, evsm2/4, msm, savsm).
ParamSpec bleedingParam();
// min-variance and bleeding-reduction: the Chebyshev techniques (vsm, evsm2/4, savsm).
std::vector<ParamSpec> chebyshevParams();
void setChebyshevShade(const Params& params, MomentShade& shade);  // reads chebyshevParams()

// The blur that momentFilterParams() ask for (a box of 2r+1 taps, or a Gaussian of the same variance
// r(r+1)/3; blur-radius resolved for the frame), the texels it reads from a texel (the light fit's margin; under auto,
// blur-radius-max's), and whether lookups are trilinear.
BlurConfig momentBlurConfig(const Params& params);
float momentBlurReach(const Params& params);
bool momentTrilinear(const Params& params);

// The MomentShade fields common to every moment technique: sizes, normalisation over the map's
// [zNear, zFar] and the biases. The technique fills its own fields (min variance, exponents, ...).
MomentShade momentShade(const ShadowFrame& frame, const ShadowMap& map, const Params& params, uint32_t channels);

// Per-pixel debug outputs of a moment visibility kernel, turned into EXR layers.
struct MomentDebug {
  Buffer<cl_float4> moments;  // filtered (decoded, for msm) moments at the receiver
  Buffer<cl_float2> stats;    // variance, filter width in texels
  void allocate(Context& ctx, size_t pixels);
  // "moments.M1".."moments.M<channels>", and "variance.Y" / "filterWidth.Y" when asked for.
  void addChannels(Context& ctx, Image& image, uint32_t channels, bool variance, bool width) const;
};

// A technique of the filtered-moments family: its moments, the kernel that shades with them, and which
// debug layers mean something for it.
struct MomentTechniqueSpec {
  MomentKind kind;
  std::string source, entry;  // "kernels/vsm.cl", "vsm_visibility"
  bool hasVariance = true;    // write "variance.Y"
  uint32_t debugMoments = 0;  // moment layers to write: 0 = every channel
  // Technique-specific MomentsConfig / MomentShade fields from the parameters (exponents, moment bias).
  std::function<void(const Params&, MomentsConfig&, MomentShade&)> configure = {};
  // The frame's parameters once its map is drawn (a parameter measured from the scene, like esm's auto exponent).
  std::function<Params(ShadowFrame&, const ShadowMap&, const Params&)> resolve = {};
};

// shadow map -> moments -> blur -> mips -> visibility kernel, one instance per render.
class MomentTechnique final : public Technique {
 public:
  MomentTechnique(MomentTechniqueSpec spec, const Params& params)
      : spec_(std::move(spec)), requested_(params), params_(params) {}
  void render(ShadowFrame& frame, Buffer<float>& visibility) override;
  void addDebugChannels(Context& ctx, Image& image) override;

 private:
  BlurConfig blurConfig() const;
  float blurReach() const;  // texels the blur reads from a texel: the margin the light fit keeps
  void filterMoments(Context& ctx, const MomentsConfig& config, const ImageShape& shape);
  template <class T>
  void filterMomentsInto(Context& ctx, const MomentsConfig& config, const ImageShape& shape, Buffer<T>& moments,
                         Buffer<T>& mips);

  MomentTechniqueSpec spec_;
  Params requested_;  // as given (blur-radius may be auto)
  Params params_;     // this frame's: blur-radius resolved
  ShadowMap map_;
  Buffer<float> moments_, scratch_, mips_;  // fp32 storage (empty with fp16)
  Buffer<cl_half> moments16_, mips16_;      // fp16 storage (empty with fp32)
  Buffer<PyramidLevel> mipLevels_;
  MomentDebug debug_;
  uint32_t channels_ = 2;
};

}  // namespace penumbra
