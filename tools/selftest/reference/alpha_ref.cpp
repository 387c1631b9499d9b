// Alpha reference: texel indices as exact integers (long long) of the coordinate scaled by the texture size, wrapped
// per glTF's definitions (REPEAT modulo n, MIRRORED_REPEAT mirrored every n, CLAMP_TO_EDGE to [0, n - 1]).
#include "tools/selftest/reference/alpha_ref.h"

#include <algorithm>
#include <cmath>

namespace penumbra::ref {
namespace {

long long wrap(long long i, long long n, int mode) {
  if (mode == ALPHA_WRAP_CLAMP) return std::clamp(i, 0LL, n - 1);
  if (mode == ALPHA_WRAP_REPEAT) return ((i % n) + n) % n;
  const long long k = ((i % (2 * n)) + 2 * n) % (2 * n);
  return k < n ? k : 2 * n - 1 - k;
}

}  // namespace

double alphaCutoff(const Material& m) { return m.mayDiscard() ? m.alphaCutoff : 0.0; }

double alphaCoverage(const Material& m, const std::vector<AlphaTexture>& textures, const std::vector<uint8_t>& texels,
                     double u, double v) {
  if (!m.mayDiscard()) return 1.0;
  if (m.alphaTexture < 0) return m.baseAlpha;
  const AlphaTexture& t = textures.at(static_cast<size_t>(m.alphaTexture));
  // KHR_texture_transform: T R S with the rotation rows (cos, sin), (-sin, cos).
  const double c = std::cos(double{m.uvTransform.rotation}), s = std::sin(double{m.uvTransform.rotation});
  const double su = m.uvTransform.scale.x * u, sv = m.uvTransform.scale.y * v;
  double tu = c * su + s * sv + m.uvTransform.offset.x, tv = -s * su + c * sv + m.uvTransform.offset.y;
  if (!std::isfinite(tu)) tu = 0;
  if (!std::isfinite(tv)) tv = 0;
  const long long w = t.width, h = t.height;
  const auto at = [&](long long x, long long y) {
    return static_cast<double>(texels.at(t.offset + static_cast<uint64_t>(wrap(y, h, m.wrapT) * w + wrap(x, w, m.wrapS))));
  };
  double value;
  if (m.filter == ALPHA_FILTER_NEAREST) {
    value = at(static_cast<long long>(std::floor(tu * w)), static_cast<long long>(std::floor(tv * h)));
  } else {
    const double x = tu * w - 0.5, y = tv * h - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
    const auto ix = static_cast<long long>(x0), iy = static_cast<long long>(y0);
    value = (1 - fy) * ((1 - fx) * at(ix, iy) + fx * at(ix + 1, iy)) +
            fy * ((1 - fx) * at(ix, iy + 1) + fx * at(ix + 1, iy + 1));
  }
  return m.baseAlpha * value / 255.0;
}

}  // namespace penumbra::ref
