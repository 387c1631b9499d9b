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

// chebyshevParams() as parsed (msm has bleeding-reduction alone: its min variance stays 0).
struct Chebyshev {
  float minVariance = 0, bleeding = 0;
  static Chebyshev from(const Params& params);  // reads whichever of the two the technique declares
  void apply(MomentShade& shade) const { shade.minVariance = minVariance, shade.bleeding = bleeding; }
  bool operator==(const Chebyshev&) const = default;
};

// momentFilterParams() as parsed.
struct MomentFilter {
  AutoRadius blur;
  BlurFilter filter = BlurFilter::Gaussian;
  bool trilinear = false;  // moment-filtering trilinear
  float filterBias = 0;
  static MomentFilter from(const Params& params, int mapSize);  // mapSize: the map's side (blur-radius-max auto's)
  bool operator==(const MomentFilter&) const = default;
};

// The blur of `filter` at this frame's `radius` (blur-radius resolved: a box of 2r+1 taps, or a Gaussian of the
// same variance r(r+1)/3; radius 0, no blur, has sigma 0), and the texels the blur reads from a texel at its largest (the light fit's margin; under
// auto, blur-radius-max's).
BlurConfig momentBlurConfig(const MomentFilter& filter, int radius);
float momentBlurReach(const MomentFilter& filter);

// The MomentShade fields common to every moment technique: sizes, normalisation over the map's
// [zNear, zFar], the biases of `settings` and filter-bias. The technique fills its own fields (min variance,
// exponents, ...).
MomentShade momentShade(const ShadowFrame& frame, const ShadowMap& map, const MapSettings& settings, float filterBias,
                        uint32_t channels);

// Per-pixel debug outputs of a moment visibility kernel, turned into EXR layers.
struct MomentDebug {
  Buffer<cl_float4> moments;  // filtered (decoded, for msm) moments at the receiver
  Buffer<cl_float2> stats;    // variance, filter width in texels
  void allocate(Context& ctx, size_t pixels);
  // "moments.M1".."moments.M<channels>", and "variance.Y" / "filterWidth.Y" when asked for.
  void addChannels(Context& ctx, Image& image, uint32_t channels, bool variance, bool width) const;
};

// The settings of a technique of the filtered-moments family (vsm, evsm2/4, esm, msm): the map, the filter and
// storage, and each technique's own values (zero where it has no such parameter).
struct MomentSettings {
  MapSettings map;
  MomentFilter filter;
  MomentStorage storage = MomentStorage::Float32;
  Chebyshev chebyshev;
  float evsmPositive = 0, evsmNegative = 0;  // evsm-positive, evsm-negative
  float msmBias = 0;                         // msm-bias
  // esm-exponent (auto: measured per frame), esm-exponent-quantile, -min, -max.
  bool esmAuto = false;
  double esmExponent = 0, esmQuantile = 0, esmMin = 0, esmMax = 0;
  static MomentSettings from(const Params& params, int mapSize);
  bool operator==(const MomentSettings&) const = default;
};

// A technique of the filtered-moments family: its moments, the kernel that shades with them, and which
// debug layers mean something for it.
struct MomentTechniqueSpec {
  MomentKind kind;
  std::string source, entry;  // "kernels/vsm.cl", "vsm_visibility"
  bool hasVariance = true;    // write "variance.Y"
  uint32_t debugMoments = 0;  // moment layers to write: 0 = every channel
  // Technique-specific MomentsConfig / MomentShade fields for this frame once its map is drawn (exponents, moment
  // bias; esm's auto exponent is measured on the map here).
  std::function<void(ShadowFrame&, const ShadowMap&, const MomentSettings&, MomentsConfig&, MomentShade&)> configure =
      {};
};

// shadow map -> moments -> blur -> mips -> visibility kernel, one instance per render.
class MomentTechnique final : public TechniqueOf<MomentSettings> {
 public:
  MomentTechnique(MomentTechniqueSpec spec, const MomentSettings& settings)
      : TechniqueOf(settings), spec_(std::move(spec)) {}
  void render(ShadowFrame& frame, Buffer<float>& visibility) override;
  void addDebugChannels(Context& ctx, Image& image) override;

 private:
  void filterMoments(Context& ctx, const MomentsConfig& config, const ImageShape& shape);
  template <class T>
  void filterMomentsInto(Context& ctx, const MomentsConfig& config, const ImageShape& shape, Buffer<T>& moments,
                         Buffer<T>& mips);

  MomentTechniqueSpec spec_;
  int blurRadius_ = 0;  // this frame's blur-radius (resolved under auto)
  ShadowMap map_;
  Buffer<float> moments_, scratch_, mips_;  // fp32 storage (empty with fp16)
  Buffer<cl_half> moments16_, mips16_;      // fp16 storage (empty with fp32)
  Buffer<PyramidLevel> mipLevels_;
  MomentDebug debug_;
  uint32_t channels_ = 2;
};

// A MomentTechnique factory for the registry: `spec` with each instance's settings parsed from its parameters.
std::function<std::unique_ptr<Technique>(const Params&, int)> momentTechniqueFactory(MomentTechniqueSpec spec);

}  // namespace penumbra
