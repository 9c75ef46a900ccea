// Atomic file writes: the content goes to a temporary file in the same directory, which is then renamed over the
// target, so a reader (or a run stopped half-way) only ever sees the old file or the complete new one.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

namespace jetshell {

/// Writes `path` atomically with `write`. Throws InputError naming the path when it cannot be written (missing
/// directory, no permission, disk full) or when it names something other than a regular file (a device, a FIFO,
/// a directory, a symbolic link), which the rename would replace.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// The checks writeFileAtomically makes before it writes, for a command to make before it starts its work: throws
/// InputError naming the path when it names something other than a regular file or its directory does not exist.
void checkOutputFile(const std::string& path);

/// The same for a ready string.
void writeFileAtomically(const std::string& path, const std::string& content);

}  // namespace jetshell
