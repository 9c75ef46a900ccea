#include "tools/output/atomic_file.h"

#include "core/mesh.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace jetshell {

namespace {

/// A temporary file that is removed when this goes out of scope (a failed write, a writer that throws, a failed
/// rename), unless it was renamed into place.
struct RemovedUnlessRenamed {
  const std::string& name;
  bool renamed = false;
  ~RemovedUnlessRenamed() {
    if (!renamed) std::remove(name.c_str());
  }
};

}  // namespace

void checkOutputFile(const std::string& path) {
  if (path.empty()) throw InputError("an output file name must not be empty");
  // The rename would replace whatever the path names: a device such as /dev/null (as root), a FIFO, a link.
  struct stat info {};
  if (::lstat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode))
    throw InputError(path + ": not a regular file (a directory, device, FIFO or link): will not replace it");
  const std::string directory = std::filesystem::path(path).parent_path().string();
  const std::string where = directory.empty() ? "." : directory;
  if (::stat(where.c_str(), &info) != 0 || !S_ISDIR(info.st_mode))
    throw InputError(path + ": cannot write (no directory '" + where + "')");
}

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  checkOutputFile(path);
  struct stat info {};
  // The pid keeps concurrent runs writing into one directory from sharing a temporary file; it is created
  // afresh (a file or link already at its name is removed first, never written through).
  const std::string temporary = path + ".tmp" + std::to_string(::getpid());
  if (::lstat(temporary.c_str(), &info) == 0) std::remove(temporary.c_str());
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0644);
  if (fd < 0) throw InputError(path + ": cannot write (" + std::strerror(errno) + ")");
  ::close(fd);
  RemovedUnlessRenamed cleanup{temporary};  // every way out below but the rename leaves no temporary file
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot write (" + std::strerror(errno) + ")");
    write(out);
    out.close();  // closed here, not by the destructor, so that a failed close is seen
    if (out.fail()) throw InputError(path + ": write failed (disk full?)");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
    throw InputError(path + ": cannot replace (" + std::strerror(errno) + ")");
  cleanup.renamed = true;
}

void writeFileAtomically(const std::string& path, const std::string& content) {
  writeFileAtomically(path, [&](std::ostream& out) { out << content; });
}

}  // namespace jetshell
