// Self-registering subcommands of the one `jetshell` program. Each tools/cmd_*.cpp adds itself with
//   static const RegisterSubcommand reg("name", [](CLI::App& app, int& exitCode) { ... });
// where the setup adds a CLI11 subcommand whose callback sets exitCode (see README: exit codes).
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace jetshell::cli {

/// Exit codes shared by every subcommand (documented in README.md).
enum ExitCode : int {
  kOk = 0,
  kFailed = 1,        // the command ran but its check failed (tolerance exceeded, solve not converged)
  kUsage = 2,         // bad command line
  kInputError = 3,    // invalid input file, scene or parameter
  kInterrupted = 130  // stopped by Ctrl-C after finishing the current frame
};

using SubcommandSetup = std::function<void(CLI::App& app, int& exitCode)>;

struct RegisteredSubcommand {
  std::string name;
  SubcommandSetup setup;
};

std::vector<RegisteredSubcommand>& subcommandRegistry();

/// The shared parent of all `jetshell bench <name>` benchmarks (created on first use). Benchmark files add
/// their own subcommand to it: `benchCommand(app)->add_subcommand("solver", ...)`.
inline CLI::App* benchCommand(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands({})) {
    if (sub->get_name() == "bench") return sub;
  }
  CLI::App* bench = app.add_subcommand("bench", "Benchmarks that print figures (and --json)");
  bench->require_subcommand(1);
  return bench;
}

struct RegisterSubcommand {
  RegisterSubcommand(std::string name, SubcommandSetup setup) {
    subcommandRegistry().push_back({std::move(name), std::move(setup)});
  }
};

}  // namespace jetshell::cli
