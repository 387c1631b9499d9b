#include "tools/selftest/reference/tolerance.h"

#include "host/stages/sat.h"

namespace penumbra::ref {

double satTableTolerance(const ImageShape& shape, double epsilon, double magnitude) {
  const double ops = 2.0 * SAT_TILE + 2.0 * (shape.width + shape.height) / SAT_TILE + std::log2(shape.texels() + 1.0);
  return ops * epsilon * magnitude;
}

}  // namespace penumbra::ref
