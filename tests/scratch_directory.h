// A scratch directory for a test's files: <temp>/jetshell-tests-XXXXXX/<name>, created on first use. The root is
// this process's own (mkdtemp: a fresh name, mode 0700). That keeps suites running at the same time (ctest -j,
// several checkouts on one machine) out of each other's files, and no other user can take its name first. Before,
// tests shared fixed names under <temp> and one suite could empty another's directory while it ran. The process's
// directory is removed when the process exits, unless JETSHELL_KEEP_TEST_FILES is set (to look at a failed test's
// outputs).
#pragma once

#include "tools/output/directories.h"

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

namespace jetshell::test {

namespace detail {
/// This process's scratch root, made on first use.
struct ScratchRoot {
  std::unique_ptr<TemporaryDirectory> directory;
  const std::filesystem::path& created() {
    if (!directory) {
      directory = std::make_unique<TemporaryDirectory>("jetshell-tests-");
      if (std::getenv("JETSHELL_KEEP_TEST_FILES") != nullptr) directory->keep();
    }
    return directory->path();
  }
};
inline ScratchRoot scratchRoot;
}  // namespace detail

/// The directory `name` (one or more path components) under this process's scratch root, created.
inline std::filesystem::path scratchDirectory(const std::string& name) {
  const std::filesystem::path dir = detail::scratchRoot.created() / name;
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace jetshell::test
