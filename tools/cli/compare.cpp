// `penumbra compare ours.exr ref.exr`: accuracy of one channel (visibility.Y, or with --light NAME one light's
// visibility.NAME.Y within lit.NAME.Y) against a reference over the covered pixels (host/eval/metrics.h), an optional
// signed error image (EXR + false-colour PNG), a table or JSON on stdout. Exit codes as idiff's: 0 within every
// threshold given, 1 not (or a NaN pixel), 2 usage, 4 file error.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include <CLI/CLI.hpp>

#include "host/eval/metrics.h"
#include "host/io/exr.h"
#include "host/io/png.h"
#include "host/scene/light_names.h"
#include "tools/cli/commands.h"

namespace penumbra::cli {
namespace {

constexpr int kExitOutside = 1;
constexpr int kExitFile = 4;

struct CompareOptions {
  std::string ours, reference, errorImage, errorPng, light;
  CompareSpec spec;
  MetricThresholds limits;
  double errorRange = 0.5;
  bool json = false;
  bool masked = false;  // the mask channel was found (set by run)
  bool coverageGiven = false;  // --coverage on the command line: a name neither image has is an error, not "all"
};

// The reference's own noise (its "stderr.Y") over the compared pixels, when it has one.
struct ReferenceNoise {
  double mean = 0, rms = 0;
};
std::optional<ReferenceNoise> referenceNoise(const Image& ours, const Image& ref, const CompareSpec& spec) {
  const ImageChannel* noise = ref.find("stderr.Y");
  if (noise == nullptr) return std::nullopt;
  const std::vector<float> coverage = comparedPixels(ours, ref, spec);
  double sum = 0, sumSq = 0, n = 0;
  for (size_t i = 0; i < noise->data.size(); ++i)
    if ((coverage.empty() || coverage[i] > 0.0f) && std::isfinite(noise->data[i]))
      sum += noise->data[i], sumSq += double{noise->data[i]} * noise->data[i], n += 1;
  if (n == 0) return ReferenceNoise{};
  return ReferenceNoise{sum / n, std::sqrt(sumSq / n)};
}

// The layers of the lights an image holds: NAME of every "visibility.NAME.Y".
std::vector<std::string> lightLayers(const Image& image) {
  std::vector<std::string> layers;
  const std::string prefix = "visibility.", suffix = ".Y";
  for (const std::string& name : image.channelNames())
    if (name.size() > prefix.size() + suffix.size() && name.starts_with(prefix) && name.ends_with(suffix))
      layers.push_back(name.substr(prefix.size(), name.size() - prefix.size() - suffix.size()));
  return layers;
}

// --light NAME: compare visibility.NAME.Y within lit.NAME.Y (unless --no-mask). Throws naming the image that lacks
// the light and the lights it has.
void selectLight(CompareOptions& options, const Image& ours, const Image& ref) {
  for (const auto& [image, path] : {std::pair{&ours, &options.ours}, std::pair{&ref, &options.reference}}) {
    const std::vector<std::string> layers = lightLayers(*image);
    if (std::find(layers.begin(), layers.end(), options.light) == layers.end())
      throw std::runtime_error(fmt::format("--light {}: {} has no light \"{}\" (its lights: {})", options.light, *path,
                                           options.light,
                                           layers.empty() ? "none" : fmt::format("{}", fmt::join(layers, ", "))));
  }
  options.spec.channel = lightChannel("visibility", options.light);
  if (!options.spec.mask.empty()) options.spec.mask = lightChannel("lit", options.light);
}

void writeErrorImage(const CompareOptions& options, const Image& ours, const Image& ref) {
  const std::vector<float> coverage = comparedPixels(ours, ref, options.spec);
  Image error(ref.width(), ref.height());
  error.add("error.Y",
            signedError(ours.require(options.spec.channel).data, ref.require(options.spec.channel).data, coverage));
  if (!coverage.empty()) error.add("A", std::vector<float>(coverage.begin(), coverage.end()));
  error.attributes()["penumbra:compare"] =
      fmt::format("{} - {} ({})", ours.source(), ref.source(), options.spec.channel);
  const std::filesystem::path exr = options.errorImage;
  if (exr.has_parent_path()) std::filesystem::create_directories(exr.parent_path());
  writeExr(exr, error);
  const std::filesystem::path png = options.errorPng.empty() ? std::filesystem::path(exr).replace_extension(".png")
                                                             : std::filesystem::path(options.errorPng);
  writePngFalseColour(png, error.width(), error.height(), error.require("error.Y").data,
                      static_cast<float>(-options.errorRange), static_cast<float>(options.errorRange));
}

// name, value, limit: the rows of the table and the keys of the JSON, in one place.
struct Row {
  const char* name;
  double value;
  const std::optional<double>& limit;
};
std::vector<Row> rows(const ErrorMetrics& m, const MetricThresholds& l) {
  return {{"mae", m.mae, l.mae},
          {"rmse", m.rmse, l.rmse},
          {"p95", m.p95, l.p95},
          {"max", m.maxAbs, l.maxAbs},
          {"off", m.off, l.off},
          {"leak", m.leak, l.leak},
          {"false_shadow", m.falseShadow, l.falseShadow},
          {"umbra_light", m.umbraLight, l.umbraLight},
          {"mean_signed", m.meanSigned, l.bias},
          {"penumbra_mae", m.penumbraMae, l.penumbraMae}};
}

void printJson(const CompareOptions& o, const Image& ref, const ErrorMetrics& m,
               const std::optional<ReferenceNoise>& noise, const std::vector<std::string>& failed) {
  nlohmann::json metrics = nlohmann::json::object(), limits = nlohmann::json::object();
  for (const Row& row : rows(m, o.limits)) {
    metrics[row.name] = row.value;
    if (row.limit) limits[row.name == std::string("mean_signed") ? "bias" : row.name] = *row.limit;
  }
  nlohmann::json out = {{"ours", o.ours},        {"reference", o.reference},  {"channel", o.spec.channel},
                        {"width", ref.width()},  {"height", ref.height()},    {"mask", o.masked ? o.spec.mask : ""},
                        {"pixels", m.pixels},    {"non_finite", m.nonFinite}, {"umbra_pixels", m.umbraPixels},
                        {"penumbra_pixels", m.penumbraPixels},
                        {"metrics", metrics},    {"thresholds", limits},      {"failed", failed},
                        {"pass", failed.empty()}};
  if (noise) out["reference_stderr"] = {{"mean", noise->mean}, {"rms", noise->rms}};
  fmt::print("{}\n", out.dump(2));
}

void printTable(const CompareOptions& o, const Image& ref, const ErrorMetrics& m,
                const std::optional<ReferenceNoise>& noise, const std::vector<std::string>& failed) {
  fmt::print("{} vs {}: {} over {} covered{} pixels of {}x{}", o.ours, o.reference, o.spec.channel, m.pixels,
             o.masked ? fmt::format(" and {}", o.spec.mask) : "", ref.width(), ref.height());
  fmt::print("{}\n", m.nonFinite > 0 ? fmt::format(" ({} NaN or infinite, left out)", m.nonFinite) : "");
  fmt::print("  {:<14} {:>12} {:>12}\n", "metric", "value", "limit");
  for (const Row& row : rows(m, o.limits))
    fmt::print(
        "  {:<14} {:>12.6f} {:>12}\n", row.name, row.value,
        row.limit ? fmt::format("{}{:.6g}", row.name == std::string("mean_signed") ? "|x| " : "", *row.limit) : "-");
  if (noise) fmt::print("  reference standard error: mean {:.3g}, rms {:.3g}\n", noise->mean, noise->rms);
  fmt::print("{}\n", failed.empty() ? std::string("PASS") : "FAIL: " + fmt::format("{}", fmt::join(failed, "; ")));
}

int run(CompareOptions options) {
  bool& masked = options.masked;
  Image ours, ref;
  ErrorMetrics metrics;
  std::optional<ReferenceNoise> noise;
  try {  // every failure from here on is about a file: unreadable, mismatched, lacking the channel, unwritable
    ours = readExr(options.ours);
    ref = readExr(options.reference);
    if (!options.light.empty()) selectLight(options, ours, ref);
    if (options.coverageGiven && !ours.find(options.spec.coverage) && !ref.find(options.spec.coverage))
      throw std::runtime_error(fmt::format("--coverage {}: neither image has that channel (the reference's: {})",
                                           options.spec.coverage, fmt::join(ref.channelNames(), ", ")));
    metrics = compareImages(ours, ref, options.spec);
    noise = referenceNoise(ours, ref, options.spec);
    masked = hasMask(ours, ref, options.spec);
    if (!options.errorImage.empty()) writeErrorImage(options, ours, ref);
  } catch (const std::exception& e) {
    fmt::print(stderr, "penumbra compare: {}\n", e.what());
    return kExitFile;
  }
  const std::vector<std::string> failed = exceededThresholds(metrics, options.limits);
  if (options.json)
    printJson(options, ref, metrics, noise, failed);
  else
    printTable(options, ref, metrics, noise, failed);
  return failed.empty() ? 0 : kExitOutside;
}

// A finite, non-negative number (CLI11's NonNegativeNumber lets NaN through).
const CLI::Validator kLimit(
    [](std::string& text) {
      double value = 0;
      if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || value < 0)
        return std::string("must be a finite number >= 0, got ") + text;
      return std::string();
    },
    "LIMIT>=0");

void addThreshold(CLI::App* sub, const std::string& name, std::optional<double>& limit, const std::string& help) {
  sub->add_option_function<double>(
         "--max-" + name, [&limit](const double& v) { limit = v; }, help)
      ->check(kLimit)
      ->group("Thresholds (exit 1 when exceeded)");
}

}  // namespace

Command addCompareCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("compare", "Error metrics of a render against a reference (exit 0/1/2/4)");
  auto o = std::make_shared<CompareOptions>();
  sub->add_option("ours", o->ours, "Our EXR (penumbra render)")->required();
  sub->add_option("reference", o->reference, "The reference EXR (penumbra reference)")->required();
  sub->add_flag("--json", o->json, "Print JSON instead of a table");
  auto* channel = sub->add_option("--channel", o->spec.channel, "Channel compared")->capture_default_str();
  sub->add_option("--light", o->light,
                  "A light's layer: compares visibility.NAME.Y within the reference's lit.NAME.Y (exit 4, listing "
                  "the lights there are, when an image lacks it)")
      ->excludes(channel);
  sub->add_option("--coverage", o->spec.coverage,
                  "Coverage channel, > 0 where a pixel counts (the reference's, else ours; neither: all pixels)")
      ->capture_default_str();
  sub->add_option("--mask", o->spec.mask,
                  "Mask channel, > 0 where the point can receive direct light (the reference's lit.Y): metrics "
                  "count covered pixels inside it")
      ->capture_default_str();
  sub->add_flag_callback(
      "--no-mask", [o] { o->spec.mask.clear(); }, "Count every covered pixel, ignoring the mask");
  sub->add_option("--error-image", o->errorImage, "Write the signed error ours - reference (error.Y) to this EXR");
  sub->add_option("--error-png", o->errorPng, "False-colour PNG of the error (default: the error EXR with .png)");
  sub->add_option("--error-range", o->errorRange, "The PNG maps error -R..R onto viridis")
      ->check(kLimit & CLI::PositiveNumber)
      ->capture_default_str();
  addThreshold(sub, "mae", o->limits.mae, "Mean absolute error");
  addThreshold(sub, "rmse", o->limits.rmse, "Root mean square error");
  addThreshold(sub, "p95", o->limits.p95, "95th percentile of the absolute error");
  addThreshold(sub, "max", o->limits.maxAbs, "Largest absolute error");
  addThreshold(sub, "off", o->limits.off, "Fraction of pixels off by more than 0.1");
  addThreshold(sub, "leak", o->limits.leak, "Fraction leaking light: reference < 0.05, ours > 0.5");
  addThreshold(sub, "false-shadow", o->limits.falseShadow, "Fraction falsely shadowed: reference > 0.95, ours < 0.5");
  addThreshold(sub, "umbra-light", o->limits.umbraLight,
               "Of the umbra pixels (reference < 0.02), the fraction where ours > 0.1");
  addThreshold(sub, "bias", o->limits.bias, "Absolute mean signed error");
  addThreshold(sub, "penumbra-mae", o->limits.penumbraMae,
               "Mean absolute error over the penumbra pixels (reference strictly between 0 and 1)");
  return {sub, [o, sub] {
            o->coverageGiven = sub->count("--coverage") > 0;
            return run(*o);
          }};
}

}  // namespace penumbra::cli
