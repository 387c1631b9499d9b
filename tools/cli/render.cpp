// `penumbra render SCENE [options] -o out.exr` — placeholder wiring until the pipeline lands.
#include "tools/cli/commands.h"

namespace penumbra::cli {

Command addRenderCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("render", "Render a scene with a shadow technique");
  return {sub, [] { return 1; }};
}

}  // namespace penumbra::cli
