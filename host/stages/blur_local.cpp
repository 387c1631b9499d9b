// The blur's local-memory plan (blur_local.h): line counts halved from the kernels' defaults until the staged lines
// fit, and the column pass's fallback to taps read from global memory.
#include "host/stages/blur_local.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "kernels/shared/blur.h"

namespace penumbra {
namespace {

// The most lines of `lineTexels` texels of `texelBytes` bytes, halving from `lines`, that fit `budget`; 0 if none.
int linesThatFit(int lines, size_t lineTexels, size_t texelBytes, uint64_t budget) {
  while (lines > 0 && uint64_t(lines) * lineTexels * texelBytes > budget) lines /= 2;
  return lines;
}

// Output rows of a blur_columns tile, halving from 64 while its (rows + 2r) x BLUR_COLUMN_TILE staged texels exceed
// `budget`; 0 if not even one row fits.
int columnRowsThatFit(int radius, size_t texelBytes, uint64_t budget) {
  int rows = 64;
  while (rows > 0 && uint64_t(rows + 2 * radius) * BLUR_COLUMN_TILE * texelBytes > budget) rows /= 2;
  return rows;
}

}  // namespace

std::string BlurLocalPlan::rowOptions() const {
  if (runs) return rowLines == BLUR_RUNS_ROWS ? std::string() : fmt::format("-DBLUR_RUNS_LINES={}", rowLines);
  return rowLines == BLUR_ROWS ? std::string() : fmt::format("-DBLUR_ROW_LINES={}", rowLines);
}

BlurLocalPlan planBlurLocal(bool runs, uint64_t localBytes, const ImageShape& shape, int radius) {
  BlurLocalPlan plan;
  plan.runs = runs;
  const size_t texelBytes = sizeof(float) * shape.channels;
  const size_t line = size_t(runs ? BLUR_RUNS_SEGMENT : BLUR_ROW_TILE) + 2 * size_t(radius);
  plan.rowLines = linesThatFit(runs ? BLUR_RUNS_ROWS : BLUR_ROWS, line, texelBytes, localBytes);
  if (plan.rowLines == 0)
    throw std::invalid_argument(
        fmt::format("blur: one line of {} texels of {} bytes (radius {}) exceeds the {} bytes "
                    "of local memory of this device",
                    line, texelBytes, radius, localBytes));
  plan.rowBytes = size_t(plan.rowLines) * line * texelBytes;
  if (!runs) {
    // Column tiles within the preferred budget, else within all of the device's; none fits: global taps.
    int rows = columnRowsThatFit(radius, texelBytes, std::min(kBlurColumnTileBudget, localBytes));
    if (rows == 0) rows = columnRowsThatFit(radius, texelBytes, localBytes);
    plan.columnRows = rows;
    plan.columnBytes = rows > 0 ? size_t(rows + 2 * radius) * BLUR_COLUMN_TILE * texelBytes : 0;
  }
  return plan;
}

}  // namespace penumbra
