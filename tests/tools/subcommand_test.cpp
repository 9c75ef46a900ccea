#include "tools/subcommand.h"

#include <catch2/catch.hpp>

#include <sstream>
#include <stdexcept>

using namespace jetshell;
using namespace jetshell::cli;

namespace {

/// A subcommand "ok" that sets exit code 0 when run.
RegisteredSubcommand okCommand() {
  return {"ok", [](CLI::App& app, int& exitCode) {
            app.add_subcommand("ok", "")->callback([&exitCode] { exitCode = kOk; });
          }};
}

int run(std::vector<RegisteredSubcommand> registry, std::vector<const char*> args, std::string& err) {
  args.insert(args.begin(), "jetshell");
  std::ostringstream e;
  const int code = runCommandLine(std::move(registry), static_cast<int>(args.size()), args.data(), e);
  err = e.str();
  return code;
}

}  // namespace

TEST_CASE("command line: exceptions thrown while a subcommand is set up reach the one handler", "[cli]") {
  std::string err;
  const RegisteredSubcommand badInput{"bad", [](CLI::App&, int&) { throw InputError("bad set-up input"); }};
  CHECK(run({okCommand(), badInput}, {"ok"}, err) == kInputError);
  CHECK(err == "jetshell: error: bad set-up input\n");
  const RegisteredSubcommand broken{"broken", [](CLI::App&, int&) { throw std::logic_error("set-up bug"); }};
  CHECK(run({okCommand(), broken}, {"ok"}, err) == kFailed);
  CHECK(err == "jetshell: internal error: set-up bug\n");
  const RegisteredSubcommand hungry{"hungry", [](CLI::App&, int&) { throw std::bad_alloc(); }};
  CHECK(run({okCommand(), hungry}, {"ok"}, err) == kInputError);
  CHECK_THAT(err, Catch::StartsWith("jetshell: error: out of memory"));
}

TEST_CASE("command line: exit codes of running, usage errors and input errors", "[cli]") {
  std::string err;
  CHECK(run({okCommand()}, {"ok"}, err) == kOk);
  CHECK(run({okCommand()}, {"nonsense"}, err) == kUsage);
  const RegisteredSubcommand throwing{"throwing", [](CLI::App& app, int&) {
                                        app.add_subcommand("throwing", "")->callback([] { throw InputError("x: bad"); });
                                      }};
  CHECK(run({throwing}, {"throwing"}, err) == kInputError);
  CHECK(err == "jetshell: error: x: bad\n");
}
