#include "tools/output/checkpoint.h"

#include "core/input_file.h"
#include "core/mesh.h"
#include "tools/output/atomic_file.h"
#include "tools/output/run_checkpoint.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>

namespace jetshell {

namespace {
/// A checkpoint holds a few state vectors of 3N doubles (9 bytes each in CBOR): 2 GiB covers the largest scene.
constexpr std::int64_t kMaxCheckpointBytes = 1LL << 31;
}  // namespace

std::string checkpointPath(const std::string& directory) {
  return (std::filesystem::path(directory) / "checkpoint.cbor").string();
}

void writeCheckpoint(const std::string& directory, nlohmann::json state) {
  state[kCheckpointVersionKey] = kCheckpointVersion;
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(state);
  writeFileAtomically(checkpointPath(directory), [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

nlohmann::json readCheckpoint(const std::string& directory) {
  const std::string path = checkpointPath(directory);
  std::error_code error;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, error)))
    throw InputError(path + ": no checkpoint to resume from (run with --checkpoint-every N first)");
  // A regular file of bounded size (a FIFO or /dev/zero named checkpoint.cbor was read without end).
  return parseCheckpoint(readInputFile(path, kMaxCheckpointBytes, "checkpoint"), path);
}

std::string fingerprint(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

}  // namespace jetshell
