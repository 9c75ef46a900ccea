// jetshell: the command-line front end. Subcommands register themselves (tools/subcommand.h).
#include "core/mesh.h"
#include "tools/subcommand.h"

#include <algorithm>
#include <new>
#include <iostream>

namespace jetshell::cli {

std::vector<RegisteredSubcommand>& subcommandRegistry() {
  static std::vector<RegisteredSubcommand> registry;
  return registry;
}

}  // namespace jetshell::cli

int main(int argc, char** argv) {
  using namespace jetshell::cli;
  CLI::App app{"jetshell: Kirchhoff–Love thin shells with forward-mode automatic differentiation"};
  app.require_subcommand(1);
  int exitCode = kOk;
  auto& registry = subcommandRegistry();
  std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const RegisteredSubcommand& s : registry) s.setup(app, exitCode);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kUsage;
  } catch (const jetshell::InputError& e) {
    std::cerr << "jetshell: error: " << e.what() << "\n";
    return kInputError;
  } catch (const std::bad_alloc&) {
    // Every input size is bounded (core/input_limits.h), but the bounds allow more than a small machine holds.
    std::cerr << "jetshell: error: out of memory: the input needs more memory than is available (use a coarser "
                 "mesh, fewer steps or a larger machine)\n";
    return kInputError;
  } catch (const std::exception& e) {
    std::cerr << "jetshell: internal error: " << e.what() << "\n";
    return kFailed;
  }
  return exitCode;
}
