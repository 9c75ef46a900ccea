// A scratch directory for a test's files: <temp>/jetshell-tests-<process id>/<name>, created on first use. The
// process id keeps suites that run at the same time (ctest -j, several checkouts on one machine) out of each
// other's files; before, tests shared fixed names under <temp> and one suite could empty another's directory
// while it ran. The process's directory is removed when the process exits, unless JETSHELL_KEEP_TEST_FILES is set
// (to look at a failed test's outputs).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include <unistd.h>

namespace jetshell::test {

namespace detail {
struct ScratchRoot {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("jetshell-tests-" + std::to_string(::getpid()));
  ScratchRoot() = default;
  ScratchRoot(const ScratchRoot&) = delete;
  ScratchRoot& operator=(const ScratchRoot&) = delete;
  ~ScratchRoot() {
    std::error_code ignored;
    if (std::getenv("JETSHELL_KEEP_TEST_FILES") == nullptr) std::filesystem::remove_all(path, ignored);
  }
};
inline ScratchRoot scratchRoot;
}  // namespace detail

/// The directory `name` (one or more path components) under this process's scratch root, created.
inline std::filesystem::path scratchDirectory(const std::string& name) {
  const std::filesystem::path dir = detail::scratchRoot.path / name;
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace jetshell::test
