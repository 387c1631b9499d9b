// The blur's local-memory plan: how many lines the direct passes stage per work-group (kernels/blur.cl), derived
// from the device's local memory so that every radius up to BLUR_DIRECT_RADIUS_LIMIT and every channel count runs
// on any device, down to a column pass that stages nothing. Numbers and the small-device test: docs/portability.md.
#pragma once

#include <cstdint>
#include <string>

#include "host/stages/image_shape.h"

namespace penumbra {

// Preferred local memory of one blur_columns work-group: a 32 KiB tile leaves room for two work-groups per
// multiprocessor on 48 KiB and 64 KiB devices. Smaller devices tile within what they have.
constexpr uint64_t kBlurColumnTileBudget = 32 * 1024;

struct BlurLocalPlan {
  bool runs = false;  // the runs layout (blur_*_runs) rather than tiles
  // Image rows per row-pass work-group, each staging one line in local memory: tiles BLUR_ROWS .. 1 lines of
  // BLUR_ROW_TILE + 2r texels (blur_rows*, built with -DBLUR_ROW_LINES), runs BLUR_RUNS_ROWS .. 1 lines of
  // BLUR_RUNS_SEGMENT + 2r texels (blur_rows_runs*, -DBLUR_RUNS_LINES): halved until they fit the device.
  int rowLines = 0;
  // Tiles only: output rows per blur_columns work-group, 64 .. 1, staging (rows + 2r) x BLUR_COLUMN_TILE texels
  // within kBlurColumnTileBudget (or, where not even one row fits that, within the device's local memory); 0 when
  // one row does not fit the device: blur_columns_global reads its taps from global memory (no local memory; the
  // same sums in the same order).
  int columnRows = 0;
  size_t rowBytes = 0;     // the row pass's __local argument
  size_t columnBytes = 0;  // blur_columns' __local argument (0 for blur_columns_global)

  // Build options of the row pass: the line count where it is not the kernels' default (one program otherwise).
  std::string rowOptions() const;
};

// The plan of a direct blur of `shape` at `radius` on the resolved layout (`runs`) under `localBytes` of local
// memory. Throws std::invalid_argument when not even one row-pass line fits (a device below 5 KiB at radius 128, 4
// channels, on tiles; OpenCL's full profile guarantees 32 KiB).
BlurLocalPlan planBlurLocal(bool runs, uint64_t localBytes, const ImageShape& shape, int radius);

}  // namespace penumbra
