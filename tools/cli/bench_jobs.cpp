// bench's job list: --techniques (all, names, or both; `reference`: the ray tracer) x the settings of every
// --sweep, with the fixed technique parameters; a sweep parameter a technique lacks is skipped for it (on stderr).
#include "tools/cli/bench_jobs.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "host/scene/light_names.h"
#include "tools/cli/bench_reference.h"

namespace penumbra::cli {
namespace {

// "all" (every technique of the registry), names, or both ("all,reference": the registry and the ray tracer).
std::vector<const TechniqueInfo*> techniqueList(const std::string& list) {
  std::vector<const TechniqueInfo*> out;
  for (size_t start = 0; start <= list.size();) {
    const size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    start = comma + 1;
    if (name.empty()) continue;
    if (name == "all") {
      for (const TechniqueInfo& info : techniques()) out.push_back(&info);
    } else if (name == referenceTechnique().name) {
      out.push_back(&referenceTechnique());
    } else {
      try {
        out.push_back(&findTechnique(name));
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(e.what()) + "; bench also runs the ray tracer as 'reference'");
      }
    }
  }
  if (out.empty()) throw std::invalid_argument("--techniques: empty list");
  return out;
}

}  // namespace

std::vector<BenchJob> planBenchJobs(const BenchOptions& options) {
  const std::vector<const TechniqueInfo*> list = techniqueList(options.techniques);
  std::vector<Sweep> sweeps;
  for (const std::string& text : options.sweeps) sweeps.push_back(parseSweep(text));
  checkSweeps(sweeps, list);
  for (const auto& [name, value] : options.params)
    if (std::none_of(list.begin(), list.end(), [&](const TechniqueInfo* t) { return t->hasParam(name); }))
      throw std::invalid_argument(fmt::format("--{}: no technique in the list has that parameter", name));
  std::vector<BenchJob> jobs;
  for (const TechniqueInfo* technique : list) {
    std::vector<std::string> skipped;
    for (Setting& setting : expandSweeps(*technique, sweeps, &skipped)) {
      ParamValues values = options.params;
      for (const std::string& name : setting.defaults) values.erase(name);
      for (const auto& [name, value] : setting.values) values[name] = value;
      Params params = techniqueParams(*technique, values, false);
      jobs.push_back({technique, std::move(setting), std::move(params)});
    }
    for (const std::string& name : skipped)
      fmt::print(stderr, "bench: --sweep {} skipped for {} (no such parameter)\n", name, technique->name);
  }
  return jobs;
}

RenderResult benchFrame(Renderer& renderer, const Camera& camera, const Light& light, const BenchJob& job) {
  return renderer.render(camera, {FrameLight{light, job.technique, job.params}}, FrameDownload::Image,
                         FrameOutputs::visibilityOnly());
}

CompareSpec lightSpec(const CompareSpec& spec, const Light& light, size_t lightCount) {
  if (lightCount == 1) return spec;
  CompareSpec out = spec;
  out.channel = lightChannel("visibility", lightLayer(light));
  if (!out.mask.empty()) out.mask = lightChannel("lit", lightLayer(light));
  return out;
}

}  // namespace penumbra::cli
