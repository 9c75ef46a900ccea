// jetshell: the command-line front end. Subcommands register themselves (tools/subcommand.h).
#include "tools/subcommand.h"

namespace jetshell::cli {

std::vector<RegisteredSubcommand>& subcommandRegistry() {
  static std::vector<RegisteredSubcommand> registry;
  return registry;
}

}  // namespace jetshell::cli

int main(int argc, char** argv) {
  using namespace jetshell::cli;
  return runCommandLine(subcommandRegistry(), argc, argv);
}
