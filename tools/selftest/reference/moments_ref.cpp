// Naive double-precision moments, one texel at a time.
#include "tools/selftest/reference/moments_ref.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::ref {
namespace {

// Matrix of Peters & Klein's optimized quantization, applied as q_j = sum_i b_i * kEncode[i][j].
constexpr double kEncode[4][4] = {{-2.07224649, 13.7948857237, 0.105877704, 9.7924062118},
                                  {32.23703778, -59.4683975703, -1.9077466311, -33.7652110555},
                                  {-68.571074599, 82.0359750338, 9.3496555107, 47.9456096605},
                                  {39.3703274134, -35.364903257, -6.6543490743, -23.9728048165}};
constexpr double kDecode[4][4] = {{0.2227744146, 0.1549679261, 0.1451988946, 0.163127443},
                                  {0.0771972861, 0.1394629426, 0.2120202157, 0.2591432266},
                                  {0.7926986636, 0.7963415838, 0.7258694464, 0.6539092497},
                                  {0.0319417555, -0.1722823173, -0.2758014811, -0.3376131734}};
constexpr double kMsmOffset = 0.035955884801;

double clampExponent(double c, MomentStorage storage) {
  const double limit = storage == MomentStorage::Float16 ? 5.54 : 42.0;
  return std::isnan(c) ? 0.0 : std::clamp(c, 0.0, limit);
}

}  // namespace

double normalizeDepth(double depth, double depthNear, double depthFar) {
  if (!std::isfinite(depth)) return 1.0;
  return std::clamp((depth - depthNear) / (depthFar - depthNear), 0.0, 1.0);
}

void msmEncode(double d, double out[4]) {
  const double b[4] = {d, d * d, d * d * d, d * d * d * d};
  for (int j = 0; j < 4; ++j) {
    out[j] = 0.0;
    for (int i = 0; i < 4; ++i) out[j] += b[i] * kEncode[i][j];
  }
  out[0] += kMsmOffset;
}

void msmDecode(const double q[4], double out[4]) {
  const double shifted[4] = {q[0] - kMsmOffset, q[1], q[2], q[3]};
  for (int j = 0; j < 4; ++j) {
    out[j] = 0.0;
    for (int i = 0; i < 4; ++i) out[j] += shifted[i] * kDecode[i][j];
  }
}

std::vector<double> moments(const std::vector<float>& depth, const MomentsConfig& config) {
  const size_t n = depth.size();
  // Its own layout arithmetic, not the stage's: four moments for EVSM4 and MSM, one for ESM, two otherwise; one plane
  // per LVSM layer.
  const size_t channels = config.kind == MomentKind::Evsm4 || config.kind == MomentKind::Msm ? 4
                          : config.kind == MomentKind::Esm                                   ? 1
                                                                                             : 2;
  const size_t planes = config.kind == MomentKind::Lvsm ? config.layers.size() : 1;
  std::vector<double> out(n * channels * planes);
  const double cp = clampExponent(config.evsmPositive, config.storage);
  const double cn = clampExponent(config.evsmNegative, config.storage);
  for (size_t i = 0; i < n; ++i) {
    const double d = normalizeDepth(depth[i], config.depthNear, config.depthFar);
    double* o = &out[i * channels];
    switch (config.kind) {
      case MomentKind::Vsm:
        o[0] = d, o[1] = d * d;
        break;
      case MomentKind::Esm: {  // e^(c (d - 1)), or in log space the depth itself
        const double c =
            std::clamp(double(config.esmExponent), 0.0, config.storage == MomentStorage::Float16 ? 8.0 : 1000.0);
        o[0] = c >= 1.0 && c <= 80.0 ? std::exp(c * (d - 1.0)) : d;
        break;
      }
      case MomentKind::Evsm2:
      case MomentKind::Evsm4: {
        const double pos = std::exp(cp * (2 * d - 1)), neg = -std::exp(-cn * (2 * d - 1));
        o[0] = pos, o[1] = pos * pos;
        if (config.kind == MomentKind::Evsm4) o[2] = neg, o[3] = neg * neg;
        break;
      }
      case MomentKind::Lvsm:
        for (size_t l = 0; l < config.layers.size(); ++l) {
          const double p = config.layers[l].p, q = config.layers[l].q;
          const double w = d <= p ? 0.0 : d >= q ? 1.0 : (d - p) / (q - p);
          out[(l * n + i) * 2] = w, out[(l * n + i) * 2 + 1] = w * w;
        }
        break;
      case MomentKind::Msm:
        msmEncode(d, o);
        break;
    }
  }
  return out;
}

int unorm16(double x) {
  if (std::isnan(x)) return 0;
  return static_cast<int>(std::lround(std::min(1.0, std::max(0.0, x)) * 65535.0));
}

}  // namespace penumbra::ref
