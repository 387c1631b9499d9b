// CSV and JSON of bench rows: the same columns in both, empty (CSV) or null (JSON) where a value does not apply.
#include "tools/eval/bench_report.h"

#include <fmt/format.h>

namespace penumbra {
namespace {

// One row as (column, value) pairs; nullopt where the value does not apply.
using Cells = std::vector<std::pair<std::string, std::optional<nlohmann::json>>>;

Cells cells(const BenchMeta& meta, const BenchRow& r) {
  const auto metric = [&](double ErrorMetrics::*field) -> std::optional<nlohmann::json> {
    if (!r.metrics) return std::nullopt;
    return (*r.metrics).*field;
  };
  std::optional<nlohmann::json> pixels, penumbraPixels;
  if (r.metrics) pixels = r.metrics->pixels, penumbraPixels = r.metrics->penumbraPixels;
  std::optional<nlohmann::json> bytes, floor, perPixel;
  if (r.bytes > 0) bytes = r.bytes;
  if (const std::optional<double> b = bytesPerPixel(meta, r)) perPixel = *b;
  if (r.floorMs) floor = *r.floorMs;
  return {{"scene", r.scene},
          {"technique", r.technique},
          {"setting", r.setting},
          {"pass", r.pass},
          {"calls", r.calls},
          {"ms", r.ms},
          {"bytes", bytes},
          {"floor_ms", floor},
          {"mae", metric(&ErrorMetrics::mae)},
          {"rmse", metric(&ErrorMetrics::rmse)},
          {"p95", metric(&ErrorMetrics::p95)},
          {"max", metric(&ErrorMetrics::maxAbs)},
          {"off", metric(&ErrorMetrics::off)},
          {"leak", metric(&ErrorMetrics::leak)},
          {"false_shadow", metric(&ErrorMetrics::falseShadow)},
          {"umbra_light", metric(&ErrorMetrics::umbraLight)},
          {"mean_signed", metric(&ErrorMetrics::meanSigned)},
          {"pixels", pixels},
          {"width", meta.width},
          {"height", meta.height},
          {"runs", meta.runs},
          {"copy_gbps", meta.copyBytesPerSecond * 1e-9},
          {"device", meta.device},
          {"parameters", r.parameters},
          {"light", r.light},
          {"penumbra_mae", metric(&ErrorMetrics::penumbraMae)},
          {"penumbra_pixels", penumbraPixels},
          {"bytes_per_pixel", perPixel},
          {"wall_ms", r.wallMs ? std::optional<nlohmann::json>(*r.wallMs) : std::nullopt},
          {"first_wall_ms", r.firstWallMs ? std::optional<nlohmann::json>(*r.firstWallMs) : std::nullopt}};
}

std::string csvText(const nlohmann::json& value) {
  if (value.is_string()) return csvField(value.get<std::string>());
  if (value.is_number_float()) return fmt::format("{:.9g}", value.get<double>());
  return value.dump();
}

}  // namespace

std::optional<double> bytesPerPixel(const BenchMeta& meta, const BenchRow& row) {
  if (row.bytes == 0 || meta.width <= 0 || meta.height <= 0) return std::nullopt;
  return static_cast<double>(row.bytes) / (static_cast<double>(meta.width) * meta.height);
}

const std::vector<std::string>& benchCsvColumns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> names;
    for (const auto& [name, value] : cells(BenchMeta{}, BenchRow{})) names.push_back(name);
    return names;
  }();
  return columns;
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void writeBenchCsv(std::ostream& out, const BenchMeta& meta, const std::vector<BenchRow>& rows) {
  const std::vector<std::string>& columns = benchCsvColumns();
  for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
  out << "\n";
  for (const BenchRow& row : rows) {
    const Cells c = cells(meta, row);
    for (size_t i = 0; i < c.size(); ++i) out << (i ? "," : "") << (c[i].second ? csvText(*c[i].second) : "");
    out << "\n";
  }
}

nlohmann::json benchJson(const BenchMeta& meta, const std::vector<BenchRow>& rows) {
  nlohmann::json list = nlohmann::json::array();
  for (const BenchRow& row : rows) {
    nlohmann::json object = nlohmann::json::object();
    for (auto& [name, value] : cells(meta, row)) object[name] = value ? *value : nlohmann::json();
    list.push_back(std::move(object));
  }
  return {{"meta",
           {{"device", meta.device},
            {"copy_bandwidth_gbps", meta.copyBytesPerSecond * 1e-9},
            {"width", meta.width},
            {"height", meta.height},
            {"runs", meta.runs},
            {"warmup", meta.warmup},
            {"reference", meta.reference},
            {"masked", meta.masked}}},
          {"rows", std::move(list)}};
}

}  // namespace penumbra
