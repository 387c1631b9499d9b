// The light map's parameterisation as technique parameters: `--warp none|lispsm` and `--lispsm-n` for the
// techniques that draw one map (sm, pcf) or one per split (pssm), and the fit every such technique calls.
// LiSPSM itself is host/views/lispsm.h (Wimmer et al. 2004).
#pragma once

#include <string>
#include <vector>

#include "host/views/lispsm.h"
#include "host/techniques/technique.h"

namespace penumbra {

// warp (none|lispsm; none unless `lispsmByDefault`), lispsm-n (world units, 0 = Wimmer's n_opt).
std::vector<ParamSpec> warpParams(bool lispsmByDefault = false);

// --warp and --lispsm-n as parsed; a technique without --warp has the default (declared false: uniform, no header
// entry).
struct WarpSettings {
  bool declared = false;  // the technique has --warp: "penumbra:warp" records it
  bool lispsm = false;    // --warp lispsm
  float n = 0.0f;         // --lispsm-n in world units; 0 = n_opt
  static WarpSettings from(const Params& params);
  bool operator==(const WarpSettings&) const = default;
};

// True when `params` declares "warp" and it is lispsm.
inline bool lispsmEnabled(const Params& params) { return WarpSettings::from(params).lispsm; }

// What the warped fit reads: the warp, and whether the map is fitted to the visible receivers (--fit).
struct WarpedFit {
  WarpSettings warp;
  bool fitReceivers = true;
  bool operator==(const WarpedFit&) const = default;
};

// The light view of a technique's single map of `size`^2 texels with `marginTexels` texels kept around what it
// covers (the filter's reach), per the "fit" parameter (whole scene, or the visible receivers). With --warp none
// (or without the parameter) exactly fitLightView; with lispsm, the LiSPSM view of the camera frustum between the
// nearest and farthest visible pixel (a G-buffer depth reduction), n from --lispsm-n or n_opt over that range.
// Records "penumbra:warp" ("none" or LispsmFit::describe()) in frame.attributes when the technique declares "warp".
// An orthographic camera has no eye point for the warp to follow: lispsm then falls back to the uniform map
// (LispsmFit::warped false, "lispsm: orthographic camera ..., uniform map" in the header).
LightView fitWarpedLightView(ShadowFrame& frame, const WarpedFit& fit, int size, float marginTexels);

// The same for an explicit camera depth range (one split: C_s .. C_{s+1}) and receiver box (nullptr: the whole
// scene); `fit` receives how the warp came out (untouched with --warp none). Records nothing.
LightView fitWarpedLightView(const ShadowFrame& frame, const WarpSettings& warp, int size, float marginTexels,
                             float nearDepth, float farDepth, const ReceiverBounds* receivers, LispsmFit* fit);

}  // namespace penumbra
