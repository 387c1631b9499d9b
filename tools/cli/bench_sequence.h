// `penumbra bench SCENE --camera-path PATH --frames N`: every technique x setting x light over the frames of a camera
// path, each frame's reference traced once (Embree); per cell the median frame time, the mean accuracy over the frames
// and the temporal stability between consecutive frames (tools/eval/shimmer.h). Writes CSV rows of their own (one per
// cell, `shimmer` among the columns: tools/chart.py charts them per technique).
#pragma once

#include <vector>

#include "tools/cli/bench_jobs.h"

namespace penumbra::cli {

int runSequenceBench(const BenchOptions& options, const std::vector<BenchJob>& jobs);

}  // namespace penumbra::cli
