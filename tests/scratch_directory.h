// A scratch directory for a test's files: <temp>/jetshell-tests-XXXXXX/<name>, created on first use. The root is
// this process's own (mkdtemp: a fresh name, mode 0700). That keeps suites running at the same time (ctest -j,
// several checkouts on one machine) out of each other's files, and no other user can take its name first. Before,
// tests shared fixed names under <temp> and one suite could empty another's directory while it ran. The process's
// directory is removed when the process exits, unless JETSHELL_KEEP_TEST_FILES is set (to look at a failed test's
// outputs).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <stdlib.h>

namespace jetshell::test {

namespace detail {
struct ScratchRoot {
  std::filesystem::path path;  // empty until the first scratch directory is asked for
  ScratchRoot() = default;
  const std::filesystem::path& created() {
    if (path.empty()) {
      std::string pattern = (std::filesystem::temp_directory_path() / "jetshell-tests-XXXXXX").string();
      if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create " + pattern);
      path = pattern;
    }
    return path;
  }
  ScratchRoot(const ScratchRoot&) = delete;
  ScratchRoot& operator=(const ScratchRoot&) = delete;
  ~ScratchRoot() {
    std::error_code ignored;
    if (!path.empty() && std::getenv("JETSHELL_KEEP_TEST_FILES") == nullptr)
      std::filesystem::remove_all(path, ignored);
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
