// The subcommands of the `penumbra` tool. Each lives in its own file, registers its options on the app and
// returns the function that runs it once the command line is parsed; main.cpp holds the table of them. CLI11 stays
// out of this header: only the files that add options include it.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace CLI {
class App;
}

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
Command addSelftestCommand(CLI::App& app);
Command addStatusCommand(CLI::App& app);

}  // namespace penumbra::cli
