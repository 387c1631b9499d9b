// `penumbra render SCENE [options] -o out.exr`: renders a scene with one technique entirely in OpenCL
// kernels, writes the EXR (all channels + provenance) and a PNG preview, and prints per-pass device times.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "host/cl/context.h"
#include "host/io/exr.h"
#include "host/io/png.h"
#include "host/pipeline/renderer.h"
#include "host/pipeline/views.h"
#include "host/scene/framing.h"
#include "host/scene/load.h"
#include "host/techniques/technique.h"
#include "tools/cli/commands.h"
#include "tools/cli/timings.h"

namespace penumbra::cli {
namespace {

struct RenderOptions {
  std::string scene, technique = "pcss", camera, size, light, device, output = "out/render.exr", png;
  bool quiet = false;
  std::map<std::string, std::string> params;  // technique parameters given on the command line
};

// Every technique's parameters as --NAME options (declared once even when several techniques share them).
void addTechniqueOptions(CLI::App* sub, RenderOptions& options) {
  std::set<std::string> declared;
  for (const TechniqueInfo& info : techniques())
    for (const ParamSpec& spec : info.params) {
      if (!declared.insert(spec.name).second) continue;
      std::string help = spec.help + (spec.choices.empty() ? fmt::format(" [default {}]", spec.defaultValue)
                                                           : fmt::format(" ({})", fmt::join(spec.choices, "|")));
      sub->add_option_function<std::string>(
             "--" + spec.name, [&options, name = spec.name](const std::string& v) { options.params[name] = v; }, help)
          ->group("Technique parameters");
    }
}

Params techniqueParams(const TechniqueInfo& info, const RenderOptions& options) {
  Params params(info.params);
  for (const auto& [name, value] : options.params) {
    bool known =
        std::any_of(info.params.begin(), info.params.end(), [&](const ParamSpec& s) { return s.name == name; });
    if (!known) throw std::invalid_argument(fmt::format("--{} does not apply to technique '{}'", name, info.name));
    params.set(name, value);
  }
  return params;
}

int run(const RenderOptions& options) {
  const TechniqueInfo& technique = findTechnique(options.technique);
  const Params params = techniqueParams(technique, options);
  Scene scene = loadScene(options.scene);
  const Bounds bounds = scene.bounds();
  Camera camera = options.camera.empty() ? (scene.cameras.empty() ? framingCamera(bounds) : scene.cameras.front())
                                         : parseCamera(options.camera);
  if (!options.size.empty()) parseSize(options.size, camera.width, camera.height);
  const Light light = options.light.empty() ? (scene.lights.empty() ? framingLight(bounds) : scene.lights.front())
                                            : parseLight(options.light);

  Context ctx(options.device);
  Renderer renderer(ctx, scene);
  RenderResult result = renderer.render(camera, light, technique, params);
  result.image.attributes()["penumbra:scene"] = options.scene;

  const std::filesystem::path exr = options.output;
  if (exr.has_parent_path()) std::filesystem::create_directories(exr.parent_path());
  writeExr(exr, result.image);
  const std::filesystem::path png =
      options.png.empty() ? std::filesystem::path(exr).replace_extension(".png") : std::filesystem::path(options.png);
  writePngPreview(png, result.image);
  if (!options.quiet) {
    fmt::print("{} on {}: {}x{}, {} triangles, technique {} ({})\n", options.scene, ctx.info().name, camera.width,
               camera.height, scene.triangleCount(), technique.name, params.describe());
    fmt::print("{}", formatTimings(result.passes));
    fmt::print("wrote {} and {}\n", exr.string(), png.string());
  }
  return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("render", "Render a scene with a shadow technique");
  auto options = std::make_shared<RenderOptions>();
  sub->add_option("scene", options->scene, "Scene: a .gltf/.glb model, a .json scene file, or builtin:NAME")
      ->required();
  std::string names;
  for (const TechniqueInfo& info : techniques()) names += (names.empty() ? "" : ", ") + info.name;
  sub->add_option("-t,--technique", options->technique, "Shadow technique: " + names)->capture_default_str();
  sub->add_option("--camera", options->camera, "EX,EY,EZ:TX,TY,TZ[:FOVY_DEG] (default: the scene's or a framing view)");
  sub->add_option("--size", options->size, "Image size WxH (default: the scene's or 1280x720)");
  sub->add_option("--light", options->light,
                  "spot:PX,PY,PZ:TX,TY,TZ:FOV_DEG[:RADIUS] or dir:DX,DY,DZ[:ANGULAR_RADIUS_DEG]");
  sub->add_option("--device", options->device, "OpenCL device: auto, cpu, gpu, a name substring, or P:D")
      ->envname("PENUMBRA_DEVICE");
  sub->add_option("-o,--output", options->output, "Output EXR")->capture_default_str();
  sub->add_option("--png", options->png, "PNG preview (default: the EXR path with .png)");
  sub->add_flag("-q,--quiet", options->quiet, "Print nothing on success");
  addTechniqueOptions(sub, *options);
  return {sub, [options] { return run(*options); }};
}

}  // namespace penumbra::cli
