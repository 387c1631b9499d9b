// The subcommands of the `penumbra` tool. Each lives in its own file, registers its options on the app and
// returns the function that runs it once the command line is parsed.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::cli {

// An error that ends the command with an exit code of its own (main prints its one line, as for every error).
class CommandError : public std::runtime_error {
 public:
  CommandError(int code, const std::string& what) : std::runtime_error(what), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

struct Command {
  CLI::App* app;             // the subcommand
  std::function<int()> run;  // returns the process exit code
};

Command addDevicesCommand(CLI::App& app);
Command addRenderCommand(CLI::App& app);
Command addReferenceCommand(CLI::App& app);
Command addCompareCommand(CLI::App& app);
Command addBenchCommand(CLI::App& app);
Command addPlanCommand(CLI::App& app);
Command addRunCommand(CLI::App& app);
Command addStatusCommand(CLI::App& app);

// The registry: one line per command.
inline std::vector<Command> registerCommands(CLI::App& app) {
  return {addDevicesCommand(app), addRenderCommand(app), addReferenceCommand(app), addCompareCommand(app),
          addBenchCommand(app),   addPlanCommand(app),   addRunCommand(app),       addStatusCommand(app)};
}

}  // namespace penumbra::cli
