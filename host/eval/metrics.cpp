// Error metrics of a visibility image against a reference: one pass for the sums and class counts, one
// nth_element for the nearest-rank 95th percentile. Sums in double so million-pixel images lose nothing.
#include "host/eval/metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {
namespace {

void checkSizes(std::span<const float> ours, std::span<const float> reference, std::span<const float> coverage) {
  if (ours.size() != reference.size())
    throw std::invalid_argument(
        fmt::format("error metrics: {} values vs {} in the reference", ours.size(), reference.size()));
  if (!coverage.empty() && coverage.size() != ours.size())
    throw std::invalid_argument(
        fmt::format("error metrics: coverage has {} values, images {}", coverage.size(), ours.size()));
}

bool covered(std::span<const float> coverage, size_t i) { return coverage.empty() || coverage[i] > 0.0f; }

// Nearest rank: the smallest value with at least `q` of the values at or below it.
double percentile(std::vector<double>& values, double q) {
  if (values.empty()) return 0.0;
  const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(values.size())));
  const size_t index = std::clamp<size_t>(rank, 1, values.size()) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index), values.end());
  return values[index];
}

}  // namespace

ErrorMetrics computeErrorMetrics(std::span<const float> ours, std::span<const float> reference,
                                 std::span<const float> coverage) {
  checkSizes(ours, reference, coverage);
  ErrorMetrics m;
  std::vector<double> absolute;
  absolute.reserve(ours.size());
  double sumAbs = 0, sumSq = 0, sum = 0;
  size_t off = 0, leak = 0, falseShadow = 0, umbraLight = 0;
  double penumbraAbs = 0;
  for (size_t i = 0; i < ours.size(); ++i) {
    if (!covered(coverage, i)) continue;
    const double a = ours[i], r = reference[i];
    if (!std::isfinite(a) || !std::isfinite(r)) {
      ++m.nonFinite;
      continue;
    }
    const double e = a - r;
    absolute.push_back(std::abs(e));
    sumAbs += std::abs(e), sumSq += e * e, sum += e;
    m.maxAbs = std::max(m.maxAbs, std::abs(e));
    off += std::abs(e) > kOffThreshold;
    leak += r < kLeakReference && a > kLeakOurs;
    falseShadow += r > kShadowReference && a < kShadowOurs;
    m.umbraPixels += r < kUmbraReference;
    umbraLight += r < kUmbraReference && a > kUmbraOurs;
    if (r > 0.0 && r < 1.0) ++m.penumbraPixels, penumbraAbs += std::abs(e);
  }
  m.pixels = absolute.size();
  if (m.pixels == 0) return m;
  const double n = static_cast<double>(m.pixels);
  m.mae = sumAbs / n;
  m.rmse = std::sqrt(sumSq / n);
  m.meanSigned = sum / n;
  m.off = static_cast<double>(off) / n;
  m.leak = static_cast<double>(leak) / n;
  m.falseShadow = static_cast<double>(falseShadow) / n;
  if (m.penumbraPixels > 0) m.penumbraMae = penumbraAbs / static_cast<double>(m.penumbraPixels);
  if (m.umbraPixels > 0) m.umbraLight = static_cast<double>(umbraLight) / static_cast<double>(m.umbraPixels);
  m.p95 = percentile(absolute, 0.95);
  return m;
}

std::vector<float> signedError(std::span<const float> ours, std::span<const float> reference,
                               std::span<const float> coverage) {
  checkSizes(ours, reference, coverage);
  std::vector<float> error(ours.size(), 0.0f);
  for (size_t i = 0; i < ours.size(); ++i)
    if (covered(coverage, i)) error[i] = ours[i] - reference[i];
  return error;
}

std::vector<std::string> exceededThresholds(const ErrorMetrics& metrics, const MetricThresholds& limits) {
  std::vector<std::string> failed;
  if (metrics.nonFinite > 0) failed.push_back(fmt::format("{} covered pixels are NaN or infinite", metrics.nonFinite));
  auto check = [&](const char* name, double value, const std::optional<double>& limit) {
    if (limit && !(value <= *limit)) failed.push_back(fmt::format("{} {:.6g} > {:.6g}", name, value, *limit));
  };
  check("mae", metrics.mae, limits.mae);
  check("rmse", metrics.rmse, limits.rmse);
  check("p95", metrics.p95, limits.p95);
  check("max", metrics.maxAbs, limits.maxAbs);
  check("off", metrics.off, limits.off);
  check("leak", metrics.leak, limits.leak);
  check("false-shadow", metrics.falseShadow, limits.falseShadow);
  check("umbra-light", metrics.umbraLight, limits.umbraLight);
  check("bias", std::abs(metrics.meanSigned), limits.bias);
  check("penumbra-mae", metrics.penumbraMae, limits.penumbraMae);
  return failed;
}

std::span<const float> coverageOf(const Image& ours, const Image& reference, const std::string& channel) {
  if (channel.empty()) return {};
  if (const ImageChannel* c = reference.find(channel)) return c->data;
  if (const ImageChannel* c = ours.find(channel)) return c->data;
  return {};
}

ErrorMetrics compareImages(const Image& ours, const Image& reference, const CompareSpec& spec) {
  if (ours.width() != reference.width() || ours.height() != reference.height())
    throw std::runtime_error(fmt::format("{} is {}x{} but {} is {}x{}", ours.source(), ours.width(), ours.height(),
                                         reference.source(), reference.width(), reference.height()));
  return computeErrorMetrics(ours.require(spec.channel).data, reference.require(spec.channel).data,
                             comparedPixels(ours, reference, spec));
}

bool hasMask(const Image& ours, const Image& reference, const CompareSpec& spec) {
  return !coverageOf(ours, reference, spec.mask).empty();
}

std::vector<float> comparedPixels(const Image& ours, const Image& reference, const CompareSpec& spec) {
  const std::span<const float> coverage = coverageOf(ours, reference, spec.coverage);
  const std::span<const float> mask = coverageOf(ours, reference, spec.mask);
  if (coverage.empty() && mask.empty()) return {};
  const size_t n = coverage.empty() ? mask.size() : coverage.size();
  if (!mask.empty() && mask.size() != n)
    throw std::runtime_error(
        fmt::format("{}: {} has {} values, coverage {}", reference.source(), spec.mask, mask.size(), n));
  std::vector<float> counted(n);
  for (size_t i = 0; i < n; ++i)
    counted[i] = (coverage.empty() || coverage[i] > 0.0f) && (mask.empty() || mask[i] > 0.0f) ? 1.0f : 0.0f;
  return counted;
}

}  // namespace penumbra
