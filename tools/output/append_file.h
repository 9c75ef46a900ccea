// A text file that grows by appending, complete after every append: the cost of each append is the size of what
// is added, not of the whole file (probes.csv and frames.pvd grow by one record per frame; rewriting them whole
// made a run's I/O grow with the square of its frame count).
//
// The file is created atomically holding head + tail. Each append writes text + tail over the old tail with one
// positioned write, so a run that is killed (or stopped by Ctrl-C) between appends leaves a complete, valid file
// (for frames.pvd the tail is the closing XML tags; for probes.csv it is empty).
#pragma once

#include <cstdint>
#include <string>

namespace jetshell {

class AppendOnlyFile {
 public:
  AppendOnlyFile() = default;
  AppendOnlyFile(const AppendOnlyFile&) = delete;
  AppendOnlyFile& operator=(const AppendOnlyFile&) = delete;
  ~AppendOnlyFile();

  /// Creates (or replaces) path atomically with head + tail and opens it for appending. Throws InputError naming
  /// the path when it cannot.
  void create(const std::string& path, const std::string& head, const std::string& tail);
  /// Opens an existing file written by create()/append() and cuts it back to `size` bytes (the size recorded at
  /// a checkpoint, tail included), ending it with tail again. Throws InputError when it is missing or shorter,
  /// or when its bytes just before `size - tail.size()` are not `lastWritten` (what was appended last before the
  /// checkpoint: a file replaced or edited since is not cut or continued).
  void reopen(const std::string& path, std::uint64_t size, const std::string& tail,
              const std::string& lastWritten = "");
  /// Inserts text before the tail. Throws InputError naming the path on a failed write (disk full).
  void append(const std::string& text);

  bool isOpen() const { return fd_ >= 0; }
  /// The file's size in bytes, tail included.
  std::uint64_t size() const { return size_; }
  const std::string& path() const { return path_; }

 private:
  void close();
  std::string path_, tail_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

}  // namespace jetshell
