// `vssm` pieces the tests and benchmarks share with the technique: its parameters, as parsed, and how they become the
// shading kernel's VssmParams.
#pragma once

#include <vector>

#include "host/techniques/params.h"
#include "host/techniques/vssm_maps.h"
#include "kernels/shared/vssm.h"

namespace penumbra {

// vssm-subdivision, vssm-m, vssm-n, vssm-levels, vssm-leaf-taps, vssm-lit-threshold, vssm-contact,
// vssm-max-radius, vssm-p-guard, vssm-min-variance, vssm-disk-strips, vssm-search, vssm-stacked, vssm-stacked-taps,
// vssm-stacked-trace, vssm-first-moment, vssm-tilt, vssm-hsm, vssm-sat-window,
// vssm-sat, vssm-sat-reduce, vssm-sat-penumbra, vssm-sat-quantile (the shadow-map parameters come on top).
std::vector<ParamSpec> vssmParamSpecs();

// vssmParamSpecs() as parsed.
struct VssmSettings {
  VssmMapConfig maps;   // vssm-sat, vssm-max-radius, vssm-levels, vssm-sat-reduce (1 under auto)
  int subdivision = 3;  // vssm-subdivision: none, uniform, adaptive, mixed
  uint32_t searchDivisions = 0, shadeDivisions = 0;  // vssm-m, vssm-n
  uint32_t leafTaps = 0, diskStrips = 0;
  double litThreshold = 0, contact = 0;  // fractions of the scene's radius (squared for the variance)
  float minVariance = 0, pGuard = 0;
  float stackedSpread = 0;   // vssm-stacked
  uint32_t stackedTaps = 0;  // vssm-stacked-taps
  bool stackedTrace = true;  // vssm-stacked-trace
  bool firstMoment = true;   // vssm-first-moment
  float tiltShare = 0;       // vssm-tilt
  bool castersHsm = true;    // vssm-hsm casters: the HSM of the casters alone
  bool castersWindow = true;      // vssm-sat-window casters: the moments and their SAT around the casters only
  uint32_t searchNarrowings = 0;  // vssm-search: 0 full, 2 adaptive
  bool satReduceAuto = false;     // vssm-sat-reduce auto (maps.satReduce is then chosen per frame)
  double satPenumbra = 0;         // vssm-sat-penumbra: SAT texels across the narrow end of the penumbrae under auto
  double satQuantile = 0;         // vssm-sat-quantile: that narrow end
  static VssmSettings from(const Params& params);
  bool operator==(const VssmSettings&) const = default;
};

// The kernel's parameters for maps built by `maps`; thresholds scale with the scene's bounding-sphere radius.
VssmParams vssmParams(const VssmSettings& settings, const VssmMaps& maps, float sceneRadius);

}  // namespace penumbra
