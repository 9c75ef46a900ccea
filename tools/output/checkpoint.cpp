#include "tools/output/checkpoint.h"

#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/mesh.h"
#include "tools/output/atomic_file.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>

namespace jetshell {

namespace {
constexpr int kCheckpointVersion = 1;
/// A checkpoint holds a few state vectors of 3N doubles (9 bytes each in CBOR): 2 GiB covers the largest scene.
constexpr std::int64_t kMaxCheckpointBytes = 1LL << 31;

/// Builds the document of a CBOR stream as nlohmann's own DOM builder does, but refuses nesting deeper than the
/// scene reader allows: the CBOR parser recurses once per level, and 2 MB of nested arrays overflowed the stack.
class BoundedDepthCbor final : public nlohmann::json_sax<nlohmann::json> {
 public:
  BoundedDepthCbor(nlohmann::json& result, int maxDepth) : dom_(result, false), maxDepth_(maxDepth) {}
  bool null() override { return dom_.null(); }
  bool boolean(bool v) override { return dom_.boolean(v); }
  bool number_integer(number_integer_t v) override { return dom_.number_integer(v); }
  bool number_unsigned(number_unsigned_t v) override { return dom_.number_unsigned(v); }
  bool number_float(number_float_t v, const string_t& text) override { return dom_.number_float(v, text); }
  bool string(string_t& v) override { return dom_.string(v); }
  bool binary(binary_t& v) override { return dom_.binary(v); }
  bool start_object(std::size_t n) override { return ++depth_ <= maxDepth_ && dom_.start_object(n); }
  bool key(string_t& v) override { return dom_.key(v); }
  bool end_object() override {
    --depth_;
    return dom_.end_object();
  }
  bool start_array(std::size_t n) override { return ++depth_ <= maxDepth_ && dom_.start_array(n); }
  bool end_array() override {
    --depth_;
    return dom_.end_array();
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  nlohmann::detail::json_sax_dom_parser<nlohmann::json> dom_;
  int depth_ = 0;
  const int maxDepth_;
};
}  // namespace

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
  std::error_code error;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, error)))
    throw InputError(path + ": no checkpoint to resume from (run with --checkpoint-every N first)");
  // A regular file of bounded size (a FIFO or /dev/zero named checkpoint.cbor was read without end).
  const std::string bytes = readInputFile(path, kMaxCheckpointBytes, "checkpoint");
  nlohmann::json j;
  BoundedDepthCbor builder(j, inputLimits().maxJsonDepth);
  bool parsed = false;
  try {
    parsed = nlohmann::json::sax_parse(bytes, &builder, nlohmann::json::input_format_t::cbor, true);
  } catch (const nlohmann::json::exception&) {  // a declared length beyond any container's size
  }
  if (!parsed || !j.is_object() || !j.contains("jetshell_checkpoint"))
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
