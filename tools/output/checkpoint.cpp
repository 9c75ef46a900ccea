#include "tools/output/checkpoint.h"

#include "core/mesh.h"
#include "tools/output/atomic_file.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace jetshell {

namespace {
constexpr int kCheckpointVersion = 1;
}

std::string checkpointPath(const std::string& directory) {
  return (std::filesystem::path(directory) / "checkpoint.cbor").string();
}

void writeCheckpoint(const std::string& directory, const nlohmann::json& state) {
  nlohmann::json j = state;
  j["jetshell_checkpoint"] = kCheckpointVersion;
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(j);
  writeFileAtomically(checkpointPath(directory), std::string(bytes.begin(), bytes.end()));
}

nlohmann::json readCheckpoint(const std::string& directory) {
  const std::string path = checkpointPath(directory);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": no checkpoint to resume from (run with --checkpoint-every N first)");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const nlohmann::json j = nlohmann::json::from_cbor(bytes, true, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("jetshell_checkpoint"))
    throw InputError(path + ": not a jetshell checkpoint");
  if (j["jetshell_checkpoint"] != kCheckpointVersion)
    throw InputError(path + ": checkpoint version " + j["jetshell_checkpoint"].dump() + " (this build reads " +
                     std::to_string(kCheckpointVersion) + ")");
  return j;
}

nlohmann::json toJsonArray(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

Eigen::VectorXd vectorFromJson(const nlohmann::json& j, const std::string& what) {
  if (!j.is_array()) throw InputError("checkpoint: " + what + " is not an array");
  Eigen::VectorXd v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t k = 0; k < j.size(); ++k) {
    if (!j[k].is_number()) throw InputError("checkpoint: " + what + " holds a non-number");
    v[static_cast<Eigen::Index>(k)] = j[k].get<double>();
  }
  return v;
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
