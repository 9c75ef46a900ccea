// Self-registering subcommands of the one `jetshell` program. Each tools/cmd_*.cpp adds itself with
//   static const RegisterSubcommand registerName("name", [](CLI::App& app, int& exitCode) { ... });
// where the setup adds a CLI11 subcommand whose callback sets exitCode (see README: exit codes). Each registrar
// has a name of its own: CI compiles the files in unity batches (scripts/test.sh), where two `reg` would collide.
#pragma once

#include "core/mesh.h"
#include "tools/output/atomic_file.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
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

/// A check for a real-valued option: a finite number > 0 (or >= 0 with allowZero), at most `maximum`.
/// CLI::PositiveNumber lets NaN through (NaN <= 0 is false) and accepts inf.
inline CLI::Validator finiteNumber(double maximum = std::numeric_limits<double>::max(), bool allowZero = false) {
  return CLI::Validator(
      [maximum, allowZero](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (std::isfinite(v) && (allowZero ? v >= 0.0 : v > 0.0) && v <= maximum) return "";
        std::ostringstream s;
        s << text << ": must be a finite number " << (allowZero ? ">= 0" : "> 0");
        if (maximum < std::numeric_limits<double>::max()) s << " and at most " << maximum;
        return s.str();
      },
      allowZero ? "NONNEGATIVE" : "POSITIVE");
}

/// A check for a real-valued option: a finite number in [minimum, maximum]. CLI::Range lets NaN through.
inline CLI::Validator finiteRange(double minimum, double maximum) {
  return CLI::Validator(
      [minimum, maximum](std::string& text) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (std::isfinite(v) && v >= minimum && v <= maximum) return "";
        std::ostringstream s;
        s << text << ": must be a finite number in [" << minimum << ", " << maximum << "]";
        return s.str();
      },
      "FLOAT in range");
}

/// A check for an option naming a file the command writes (--json, --png): refused before any work when it names
/// a directory, device, FIFO or link, or its directory does not exist (writeFileAtomically's own checks).
inline CLI::Validator outputFile() {
  return CLI::Validator(
      [](std::string& path) -> std::string {
        try {
          checkOutputFile(path);
        } catch (const InputError& e) {
          return e.what();
        }
        return "";
      },
      "FILE");
}

/// The same check for a command that first creates the directory the file may go in (validate's --plots, stress's
/// --out): it calls this after making the directory and before its work. Throws InputError naming `option`.
inline void checkOutputOption(const std::string& path, const std::string& option) {
  if (path.empty()) return;
  try {
    checkOutputFile(path);
  } catch (const InputError& e) {
    throw InputError(option + ": " + e.what());
  }
}

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

/// Sets up every subcommand of `registry` on one CLI11 app, parses argv and runs the chosen one. Every exception,
/// from set-up as well as from running, reaches one handler here: bad command line → kUsage, InputError →
/// kInputError, out of memory → kInputError, anything else → kFailed, each with one line on `err`.
inline int runCommandLine(std::vector<RegisteredSubcommand> registry, int argc, const char* const* argv,
                          std::ostream& err = std::cerr) {
  try {
    CLI::App app{"jetshell: Kirchhoff–Love thin shells with forward-mode automatic differentiation"};
    app.require_subcommand(1);
    int exitCode = kOk;
    std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    for (const RegisteredSubcommand& s : registry) s.setup(app, exitCode);
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      const int code = app.exit(e, std::cout, err);
      return code == 0 ? kOk : kUsage;
    }
    return exitCode;
  } catch (const InputError& e) {
    err << "jetshell: error: " << e.what() << "\n";
    return kInputError;
  } catch (const std::bad_alloc&) {
    // Every input size is bounded (core/input_limits.h), but the bounds allow more than a small machine holds.
    err << "jetshell: error: out of memory: the input needs more memory than is available (use a coarser mesh, "
           "fewer steps or a larger machine)\n";
    return kInputError;
  } catch (const std::exception& e) {
    err << "jetshell: internal error: " << e.what() << "\n";
    return kFailed;
  } catch (...) {
    err << "jetshell: internal error: unknown exception\n";
    return kFailed;
  }
}

struct RegisterSubcommand {
  RegisterSubcommand(std::string name, SubcommandSetup setup) {
    subcommandRegistry().push_back({std::move(name), std::move(setup)});
  }
};

}  // namespace jetshell::cli
