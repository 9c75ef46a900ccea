// Opening an input file (a mesh, a scene) safely: only regular files of bounded size are read, so a FIFO, a
// device such as /dev/zero or a directory given as the file is an error instead of a hang or an endless read.
//
// Input: a path, the largest accepted size in bytes, and what the file is ("mesh file", "scene file") for the
// messages. Output: an open stream at the file's start, or InputError naming the path:
//   "<path>: cannot open <what>", "<path>: not a regular file (a directory, FIFO or device): cannot read it as
//   a <what>", "<path>: <what> of N bytes is too large (at most M)".
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace jetshell {

std::ifstream openInputFile(const std::string& path, std::int64_t maxBytes, const std::string& what);

/// The whole content of such a file.
std::string readInputFile(const std::string& path, std::int64_t maxBytes, const std::string& what);

}  // namespace jetshell
