#include "tools/output/directories.h"

#include "core/mesh.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <system_error>

namespace jetshell {

TemporaryDirectory::TemporaryDirectory(const std::string& prefix) {
  std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr)
    throw InputError(pattern + ": cannot create a temporary directory (" + std::strerror(errno) + ")");
  path_ = pattern;
}

TemporaryDirectory::~TemporaryDirectory() {
  std::error_code ignored;
  if (!kept_) std::filesystem::remove_all(path_, ignored);
}

void createOutputDirectory(const std::string& path, const std::string& option) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec) throw InputError(option + ": " + path + ": cannot create the directory (" + ec.message() + ")");
}

}  // namespace jetshell
