// The rows `penumbra bench` writes: one per technique x setting x light x pass, then a "total" row carrying the
// accuracy metrics, as CSV (one header line, RFC 4180 quoting) or JSON ({"meta": ..., "rows": [...]}). Plain C++.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "host/eval/metrics.h"

namespace penumbra {

inline constexpr const char* kTotalPass = "total";

struct BenchRow {
  std::string scene, technique, setting, parameters;  // setting: the swept values ("map-size=1024") or "default"
  std::string pass;                                   // "stage/kernel", or kTotalPass
  int calls = 0;
  double ms = 0;                        // median device time over the runs
  uint64_t bytes = 0;                   // least bytes moved (0: no hint)
  std::optional<double> floorMs;        // bytes / copy bandwidth
  std::optional<ErrorMetrics> metrics;  // total rows, when a reference was compared
  std::string light;                    // the light's layer (light_names.h lightLayer): rows per light of the frame
  // Total rows: host wall time of a frame, from the render call to its results on the host: the median over the timed
  // runs (steady frames), and the setting's first frame (warm-up or not), which also pays the program builds and
  // buffer allocations a steady frame reuses.
  std::optional<double> wallMs, firstWallMs;
};

struct BenchMeta {
  std::string device;
  double copyBytesPerSecond = 0;  // measured clEnqueueCopyBuffer bandwidth (read + write bytes per second)
  int width = 0, height = 0, runs = 0, warmup = 0;
  std::string reference;  // the reference EXR compared against ("" when none)
  bool masked = false;    // metrics restricted to the reference's lit.Y mask
};

// The CSV's columns, in order (the chart and table scripts read them by name; "light", then "penumbra_mae",
// "penumbra_pixels", "bytes_per_pixel", "wall_ms" and "first_wall_ms" came last, after "parameters", so older readers
// by position keep working).
const std::vector<std::string>& benchCsvColumns();

// Quotes a field when it holds a comma, a quote or a line break (quotes doubled).
std::string csvField(const std::string& text);

// The bytes `row` moves per pixel of the frame (its floor over width x height); nothing without a bytes hint.
std::optional<double> bytesPerPixel(const BenchMeta& meta, const BenchRow& row);

void writeBenchCsv(std::ostream& out, const BenchMeta& meta, const std::vector<BenchRow>& rows);
nlohmann::json benchJson(const BenchMeta& meta, const std::vector<BenchRow>& rows);

}  // namespace penumbra
