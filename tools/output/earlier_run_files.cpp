#include "tools/output/earlier_run_files.h"

#include "core/input_file.h"
#include "core/mesh.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cctype>
#include <filesystem>
#include <string>
#include <vector>

namespace jetshell {
namespace {

namespace fs = std::filesystem;

/// A summary.json is a few kilobytes (its probes and warnings); past this it is not one.
constexpr std::int64_t kMostSummaryBytes = 16LL << 20;

bool allDigits(const std::string& s, std::size_t from, std::size_t to) {
  if (from >= to) return false;
  for (std::size_t i = from; i < to; ++i)
    if (!std::isdigit(static_cast<unsigned char>(s[i]))) return false;
  return true;
}

/// `name` itself, or its temporary during an atomic write (name + ".tmp" + a process id).
bool isOrTemporaryOf(const std::string& file, const std::string& name) {
  if (file == name) return true;
  const std::string prefix = name + ".tmp";
  return file.size() > prefix.size() && file.compare(0, prefix.size(), prefix) == 0 &&
         allDigits(file, prefix.size(), file.size());
}

/// frame_NNNNN.ext or volumes_NNNNN.ext (at least five digits), or its temporary.
bool isNumberedFrame(const std::string& file, const std::string& extension) {
  for (const std::string stem : {"frame_", "volumes_"}) {
    if (file.compare(0, stem.size(), stem) != 0) continue;
    const std::size_t dot = file.find('.', stem.size());
    if (dot == std::string::npos || dot - stem.size() < 5 || !allDigits(file, stem.size(), dot)) continue;
    if (isOrTemporaryOf(file.substr(dot + 1), extension)) return true;
  }
  return false;
}

/// Removes the entries of `folder` (not entered when it is a link or not a directory) that `isRunFile` names;
/// listed first, removed after.
template <typename IsRunFile>
int removeFrom(const fs::path& folder, IsRunFile isRunFile) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(folder, ec))) return 0;
  std::vector<fs::path> runFiles;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code statusError;
    const fs::file_status status = it->symlink_status(statusError);
    if (!statusError && !fs::is_directory(status) && isRunFile(it->path().filename().string()))
      runFiles.push_back(it->path());
  }
  if (ec) throw InputError(folder.string() + ": cannot list the output directory (" + ec.message() + ")");
  for (const fs::path& file : runFiles) {
    std::error_code removeError;
    fs::remove(file, removeError);
    if (removeError)
      throw InputError(file.string() + ": cannot remove this file of an earlier run (" + removeError.message() + ")");
  }
  return static_cast<int>(runFiles.size());
}

}  // namespace

int removeEarlierRunFiles(const std::string& directory) {
  static const std::array<std::string, 8> topLevel = {"summary.json", "frames.pvd",         "probes.csv",
                                                      "final.png",    "probes.png",         "contact_forces.png",
                                                      "volumes.vtu",  "checkpoint.cbor"};
  const fs::path root(directory);
  int removed = removeFrom(root, [](const std::string& file) {
    for (const std::string& name : topLevel)
      if (isOrTemporaryOf(file, name)) return true;
    return false;
  });
  removed += removeFrom(root / "frames", [](const std::string& file) { return isNumberedFrame(file, "vtu"); });
  removed += removeFrom(root / "obj", [](const std::string& file) {
    return isNumberedFrame(file, "obj") || isOrTemporaryOf(file, "volumes.obj");
  });
  return removed;
}

std::string unfinishedRunIn(const std::string& directory) {
  const fs::path root(directory);
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(root / "checkpoint.cbor", ec))) return "";
  const fs::path summary = root / "summary.json";
  if (!fs::exists(fs::symlink_status(summary, ec)))
    return "the checkpoint of a run that stopped before writing its summary.json";
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(readInputFile(summary.string(), kMostSummaryBytes, "summary"), nullptr, false);
  } catch (const InputError&) {
    return "the checkpoint of a run whose summary.json cannot be read";
  }
  if (!j.is_object() || !j.contains("termination") || !j["termination"].is_string())
    return "the checkpoint of a run whose summary.json states no termination";
  if (j["termination"].get<std::string>() == "interrupted") return "the checkpoint of an interrupted run";
  return "";
}

}  // namespace jetshell
