#include "tools/output/append_file.h"

#include "core/mesh.h"
#include "tools/output/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace jetshell {

AppendOnlyFile::~AppendOnlyFile() { close(); }

void AppendOnlyFile::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void AppendOnlyFile::create(const std::string& path, const std::string& head, const std::string& tail) {
  close();
  writeFileAtomically(path, head + tail);
  path_ = path;
  tail_ = tail;
  size_ = head.size() + tail.size();
  fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) throw InputError(path + ": cannot open for appending (" + std::strerror(errno) + ")");
}

void AppendOnlyFile::reopen(const std::string& path, std::uint64_t size, const std::string& tail,
                            const std::string& lastWritten) {
  close();
  path_ = path;
  tail_ = tail;
  // Not through a symbolic link, and only a regular file: the file is cut back and written in place, so a link
  // in an output directory (one unpacked from elsewhere) would have cut and written whatever it points to.
  fd_ = ::open(path.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (fd_ < 0 && errno == ELOOP)
    throw InputError(path + ": a symbolic link: a resumed run writes only the files it wrote itself");
  if (fd_ < 0) throw InputError(path + ": cannot reopen (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
    close();
    throw InputError(path + ": not a regular file (a directory, FIFO or device): cannot continue it");
  }
  if (static_cast<std::uint64_t>(st.st_size) < size || size < tail.size())
    throw InputError(path + ": shorter than at the checkpoint (" + std::to_string(size) + " bytes)");
  if (!lastWritten.empty()) {
    const std::uint64_t end = size - tail.size();
    std::string found(lastWritten.size(), '\0');
    const bool read = end >= lastWritten.size() &&
                      ::pread(fd_, found.data(), found.size(), static_cast<off_t>(end - lastWritten.size())) ==
                          static_cast<ssize_t>(found.size());
    if (!read || found != lastWritten) {
      close();
      throw InputError(path + ": does not end as at the checkpoint (changed since it was written): not continued");
    }
  }
  // Whatever was appended after the checkpoint goes; the tail is written back at the cut.
  const std::uint64_t cut = size - tail.size();
  if (::ftruncate(fd_, static_cast<off_t>(cut)) != 0 ||
      ::pwrite(fd_, tail.data(), tail.size(), static_cast<off_t>(cut)) != static_cast<ssize_t>(tail.size()))
    throw InputError(path + ": cannot cut back to the checkpoint (" + std::strerror(errno) + ")");
  size_ = size;
}

void AppendOnlyFile::append(const std::string& text) {
  if (fd_ < 0) throw std::logic_error("AppendOnlyFile::append before create");
  if (text.empty()) return;
  const std::string block = text + tail_;
  const std::uint64_t offset = size_ - tail_.size();
  std::size_t done = 0;
  while (done < block.size()) {
    const ssize_t n = ::pwrite(fd_, block.data() + done, block.size() - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string reason = std::strerror(errno);
      // Put the old end back so the file stays as it was before this append.
      if (::pwrite(fd_, tail_.data(), tail_.size(), static_cast<off_t>(offset)) == static_cast<ssize_t>(tail_.size()))
        static_cast<void>(::ftruncate(fd_, static_cast<off_t>(size_)));
      throw InputError(path_ + ": write failed (" + reason + ")");
    }
    done += static_cast<std::size_t>(n);
  }
  size_ = offset + block.size();
}

}  // namespace jetshell
