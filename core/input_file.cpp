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

bool readBoundedLine(std::istream& in, std::string& line, std::int64_t maxLineBytes, const std::string& name,
                     int number, std::int64_t& totalBytes, std::int64_t maxTotalBytes) {
  auto fail = [&](const std::string& what, std::int64_t bound) {
    std::ostringstream s;
    s << name << ":" << number << ": " << what << " (at most " << bound << " bytes)";
    throw InputError(s.str());
  };
  line.clear();
  std::streambuf* buffer = in.rdbuf();
  bool any = false;
  for (;;) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      break;
    }
    any = true;
    if (++totalBytes > maxTotalBytes) fail("the file is too large", maxTotalBytes);
    if (c == '\n') break;
    if (static_cast<std::int64_t>(line.size()) >= maxLineBytes) fail("line is too long", maxLineBytes);
    line.push_back(static_cast<char>(c));
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return any;
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
