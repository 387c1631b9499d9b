// `penumbra`: the command-line tool. Subcommands live in their own files (devices.cpp, render.cpp, ...);
// this file parses the command line and maps exceptions to exit codes: 0 ok, 1 failure, 2 usage error,
// 69 no OpenCL device, a CommandError's own code. Library code reports bad option values as std::invalid_argument.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "host/cl/error.h"
#include "host/version.h"
#include "tools/cli/commands.h"

namespace {

// CLI11 answers an unknown first word with "A subcommand is required"; this names the word and the choices.
// Empty when argv[1] is an option or a known subcommand.
std::string unknownSubcommand(int argc, char** argv, const std::vector<penumbra::cli::Command>& commands) {
  if (argc < 2 || argv[1][0] == '-') return {};
  std::string names;
  for (const penumbra::cli::Command& command : commands) {
    if (command.app->get_name() == argv[1]) return {};
    names += (names.empty() ? "" : ", ") + command.app->get_name();
  }
  return fmt::format("unknown subcommand '{}' (one of {}; see --help)", argv[1], names);
}

// The registry: one line per command.
std::vector<penumbra::cli::Command> registerCommands(CLI::App& app) {
  using namespace penumbra::cli;
  return {addDevicesCommand(app), addRenderCommand(app), addReferenceCommand(app),
          addCompareCommand(app), addBenchCommand(app),  addPlanCommand(app),
          addRunCommand(app),     addStatusCommand(app), addSelftestCommand(app)};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"penumbra: filtered and soft shadows for glTF scenes, every stage an OpenCL kernel"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "penumbra " + std::string(penumbra::version()));
  const std::vector<penumbra::cli::Command> commands = registerCommands(app);
  if (const std::string unknown = unknownSubcommand(argc, argv, commands); !unknown.empty()) {
    fmt::print(stderr, "penumbra: {}\n", unknown);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  try {
    for (const penumbra::cli::Command& command : commands)
      if (command.app->parsed()) return command.run();
    return 2;
  } catch (const penumbra::cli::CommandError& e) {
    fmt::print(stderr, "penumbra: {}\n", e.what());
    return e.code();
  } catch (const std::invalid_argument& e) {  // a bad option value: a usage error
    fmt::print(stderr, "penumbra: {}\n", e.what());
    return 2;
  } catch (const penumbra::NoDeviceError& e) {
    fmt::print(stderr, "penumbra: {}\n", e.what());
    return penumbra::kExitNoDevice;
  } catch (const std::exception& e) {
    fmt::print(stderr, "penumbra: {}\n", e.what());
    return 1;
  }
}
