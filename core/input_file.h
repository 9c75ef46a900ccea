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
#include <istream>
#include <string>

namespace jetshell {

std::ifstream openInputFile(const std::string& path, std::int64_t maxBytes, const std::string& what);

/// Reads one line of a text input (without its '\n' or '\r\n') of at most maxLineBytes; false at the end of the
/// input. totalBytes counts what has been read so far; InputError "<name>:<number>: line is too long (at most N
/// bytes)" or "<name>:<number>: the file is too large (at most N bytes)" past either bound.
bool readBoundedLine(std::istream& in, std::string& line, std::int64_t maxLineBytes, const std::string& name,
                     int number, std::int64_t& totalBytes, std::int64_t maxTotalBytes);

/// The whole content of such a file.
std::string readInputFile(const std::string& path, std::int64_t maxBytes, const std::string& what);

}  // namespace jetshell
