// The directories a command writes into: a private temporary one (TemporaryDirectory), or one the user names
// (createOutputDirectory).
//
// A temporary directory is created by mkdtemp under the system's temporary directory (a fresh name that no one
// else could have taken first, mode 0700) and removed with its contents when the object goes. A predictable name
// there (a process id, a fixed word) can be created first by another user: as a link into someone's files that
// the clean-up would then empty, or as a directory they can write into while the run does.
#pragma once

#include <filesystem>
#include <string>

namespace jetshell {

class TemporaryDirectory {
 public:
  /// Creates <temp>/<prefix>XXXXXX; throws InputError naming the pattern when it cannot.
  explicit TemporaryDirectory(const std::string& prefix);
  ~TemporaryDirectory();
  TemporaryDirectory(const TemporaryDirectory&) = delete;
  TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// Leaves the directory on disk when the object goes (to look at what a failed run left).
  void keep() { kept_ = true; }

 private:
  std::filesystem::path path_;
  bool kept_ = false;
};

/// Creates the directory `path` (and its parents) for a command's outputs; throws InputError naming `option` and
/// the path when it cannot (a file in the way, no permission), instead of the file system's own exception.
void createOutputDirectory(const std::string& path, const std::string& option);

}  // namespace jetshell
