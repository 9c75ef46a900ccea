#include "core/input_file.h"

#include "core/mesh.h"

#include <sys/stat.h>

#include <sstream>

namespace jetshell {

std::ifstream openInputFile(const std::string& path, std::int64_t maxBytes, const std::string& what) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw InputError(path + ": cannot open " + what);
  if (!S_ISREG(info.st_mode))
    throw InputError(path + ": not a regular file (a directory, FIFO or device): cannot read it as a " + what);
  if (static_cast<std::int64_t>(info.st_size) > maxBytes) {
    std::ostringstream s;
    s << path << ": " << what << " of " << info.st_size << " bytes is too large (at most " << maxBytes << ")";
    throw InputError(s.str());
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open " + what);
  return in;
}

std::string readInputFile(const std::string& path, std::int64_t maxBytes, const std::string& what) {
  std::ifstream in = openInputFile(path, maxBytes, what);
  std::string out;
  char buffer[1 << 16];
  // Bounded even if the file grows after it was measured.
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    out.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (static_cast<std::int64_t>(out.size()) > maxBytes) {
      std::ostringstream s;
      s << path << ": " << what << " is too large (at most " << maxBytes << " bytes)";
      throw InputError(s.str());
    }
  }
  if (in.bad()) throw InputError(path + ": read error");
  return out;
}

}  // namespace jetshell
