// What `bench` measures: its options and its jobs (technique x parameter setting), shared by the single-view bench
// (bench.cpp) and the sequence bench over a camera path (bench_sequence.cpp).
#pragma once

#include <string>
#include <vector>

#include "host/eval/metrics.h"
#include "host/pipeline/renderer.h"
#include "host/scene/light.h"
#include "host/techniques/technique.h"
#include "tools/cli/technique_options.h"
#include "tools/cli/view_options.h"
#include "tools/eval/sweep.h"

namespace penumbra::cli {

struct BenchOptions {
  ViewOptions view;
  std::string techniques = "all", device, output = "out/bench.csv", json, reference;
  std::vector<std::string> sweeps;
  int runs = 5, warmup = 1, spp = 256;
  bool noReference = false, noMask = false, quiet = false, interleave = false;
  ParamValues params;      // fixed technique parameters, applied to every technique that has them
  std::string cameraPath;  // a sequence: the camera path (camera_path.h) as JSON, or @FILE
  int frames = 0;          // its frame count (0: one view, no sequence)
};

struct BenchJob {
  const TechniqueInfo* technique;
  Setting setting;
  Params params;
};

// Every job, its Params validated before anything runs (a bad value is a usage error, exit 2).
std::vector<BenchJob> planBenchJobs(const BenchOptions& options);

// One frame of `job` under `light`, as bench times it: the light's visibility alone (FrameOutputs::visibilityOnly),
// which is what the accuracy metrics read and all that the traced peer makes; no preview pass, no download of the
// G-buffer's channels. A frame `penumbra render` writes costs that much more (docs/performance.md).
RenderResult benchFrame(Renderer& renderer, const Camera& camera, const Light& light, const BenchJob& job);

// The comparison of one light's frame: one light compares visibility.Y within lit.Y as ever; several compare each
// light's layer, visibility.<layer>.Y within lit.<layer>.Y.
CompareSpec lightSpec(const CompareSpec& spec, const Light& light, size_t lightCount);

}  // namespace penumbra::cli
