// Reading the files of tools/output/vtu.h: a .vtu frame of triangles with ASCII arrays, and the last time step
// of a .pvd collection. Both read files a user names (`jetshell render`), so every count is bounded by the scene
// limits (core/input_limits.h) and every fault is an InputError naming the file; tests/fuzz/vtu_fuzzer.cpp
// feeds them arbitrary bytes.
#include "core/input_file.h"
#include "core/input_limits.h"
#include "tools/output/vtu.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <utility>

namespace jetshell {

namespace {

/// The value of attribute `name` in `tag` (the text from '<' to before '>'), with the five XML entities that
/// PvdSeries writes decoded; "" when absent.
std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return "";
  const std::size_t start = at + key.size();
  const std::string raw = tag.substr(start, tag.find('"', start) - start);
  static const std::pair<const char*, char> entities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (std::size_t k = 0; k < raw.size();) {
    bool decoded = false;
    for (const auto& [entity, c] : entities)
      if (raw.compare(k, std::strlen(entity), entity) == 0) {
        out += c;
        k += std::strlen(entity);
        decoded = true;
        break;
      }
    if (!decoded) out += raw[k++];
  }
  return out;
}

/// A count attribute of a tag (NumberOfPoints, NumberOfCells: from 0 to the limit a scene's meshes have,
/// core/input_limits.h; NumberOfComponents: from 1 to 9): plain decimal digits, nothing before or after them.
long countAttribute(const std::string& tag, const std::string& name, const std::string& path, std::int64_t maximum,
                    std::int64_t minimum = 0) {
  const std::string text = attribute(tag, name);
  long value = -1;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end || value < minimum || value > maximum)
    throw InputError(path + ": " + name + "=\"" + text.substr(0, 32) + "\" is not an integer from " +
                     std::to_string(minimum) + " to " + std::to_string(maximum));
  return value;
}

/// The numbers of an ASCII array, at most `maximum` of them (no array of a valid frame holds more).
std::vector<double> numbers(const std::string& text, const std::string& path, const std::string& what,
                            std::size_t maximum) {
  std::vector<double> out;
  const char* p = text.c_str();
  const char* end = p + text.size();
  while (p < end) {
    while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (p == end) break;
    char* next = nullptr;
    const double v = std::strtod(p, &next);
    if (next == p) throw InputError(path + ": array " + what + " has a non-numeric entry");
    if (!std::isfinite(v)) throw InputError(path + ": array " + what + " has a non-finite entry (NaN or inf)");
    if (out.size() == maximum)
      throw InputError(path + ": array " + what + " has more than " + std::to_string(maximum) +
                       " values (9 per point or cell at most)");
    out.push_back(v);
    p = next;
  }
  return out;
}

/// The text of the tag that opens at `at` (from '<' to before its '>'); InputError when it has no '>'.
std::string tagAt(const std::string& xml, std::size_t at, const std::string& path) {
  const std::size_t close = xml.find('>', at);
  if (close == std::string::npos)
    throw InputError(path + ": the tag at byte " + std::to_string(at) + " has no closing '>'");
  return xml.substr(at, close - at);
}

/// Whether a section (Points, Cells, PointData, CellData) is open at positions that only grow: the last opening
/// and closing tags before the position, found by one forward scan over the file (a backward search from every
/// array made a file of many arrays quadratic: 9 MB took minutes).
class SectionTracker {
 public:
  SectionTracker(const std::string& xml, const char* name)
      : xml_(xml), open_(std::string("<") + name), close_(std::string("</") + name) {
    nextOpen_ = xml_.find(open_);
    nextClose_ = xml_.find(close_);
  }
  bool openAt(std::size_t at) {
    while (nextOpen_ < at) lastOpen_ = std::exchange(nextOpen_, xml_.find(open_, nextOpen_ + 1));
    while (nextClose_ < at) lastClose_ = std::exchange(nextClose_, xml_.find(close_, nextClose_ + 1));
    return lastOpen_ != std::string::npos && (lastClose_ == std::string::npos || lastClose_ < lastOpen_);
  }

 private:
  const std::string& xml_;
  std::string open_, close_;
  std::size_t nextOpen_, nextClose_, lastOpen_ = std::string::npos, lastClose_ = std::string::npos;
};

/// Arrays in one frame: writeVtu writes about ten.
constexpr int kMaxVtuArrays = 1024;
/// Files of one time step of a .pvd: a run writes one per shell actor and one for the volumes.
constexpr std::size_t kMaxPvdFiles = 4096;

}  // namespace

VtuFrame parseVtu(const std::string& xml, const std::string& path) {
  if (xml.find("type=\"UnstructuredGrid\"") == std::string::npos)
    throw InputError(path + ": not a VTK XML UnstructuredGrid (.vtu) file");
  if (xml.find("<AppendedData") != std::string::npos)
    throw InputError(path + ": appended (binary) data is not supported; save the file with ASCII data");
  const std::size_t piece = xml.find("<Piece");
  if (piece == std::string::npos) throw InputError(path + ": no <Piece>");
  const std::string pieceTag = tagAt(xml, piece, path);
  const long n = countAttribute(pieceTag, "NumberOfPoints", path, inputLimits().maxVertices);
  const long nf = countAttribute(pieceTag, "NumberOfCells", path, inputLimits().maxFaces);
  const std::size_t maxValues = 9 * static_cast<std::size_t>(std::max(n, nf));

  VtuFrame frame;
  std::vector<double> points, connectivity, offsets, types;
  SectionTracker inPoints(xml, "Points"), inCells(xml, "Cells"), inPointData(xml, "PointData"),
      inCellData(xml, "CellData");
  int arrays = 0;
  for (std::size_t at = xml.find("<DataArray", piece); at != std::string::npos; at = xml.find("<DataArray", at + 1)) {
    if (++arrays > kMaxVtuArrays)
      throw InputError(path + ": more than " + std::to_string(kMaxVtuArrays) + " <DataArray> elements");
    const std::string tag = tagAt(xml, at, path);
    const std::size_t close = at + tag.size();
    const std::size_t endArray = xml.find("</DataArray>", close);
    if (endArray == std::string::npos) throw InputError(path + ": unterminated <DataArray>");
    const std::string name = attribute(tag, "Name");
    if (attribute(tag, "format") != "ascii")
      throw InputError(path + ": array '" + name + "' is not ASCII; save the file with ASCII data");
    std::vector<double> values =
        numbers(xml.substr(close + 1, endArray - close - 1), path, "'" + name + "'", maxValues);
    int components = 1;
    if (!attribute(tag, "NumberOfComponents").empty())
      components = static_cast<int>(countAttribute(tag, "NumberOfComponents", path + ": array '" + name + "'", 9, 1));
    // The section an array belongs to is the first open one of these (each is asked, so each scan moves on).
    const bool isPoints = inPoints.openAt(at), isCells = inCells.openAt(at), isPointData = inPointData.openAt(at),
               isCellData = inCellData.openAt(at);
    if (isPoints) {
      points = std::move(values);
    } else if (isCells) {
      if (name == "connectivity") connectivity = std::move(values);
      else if (name == "offsets") offsets = std::move(values);
      else if (name == "types") types = std::move(values);
    } else if (isPointData) {
      frame.pointData[name] = {components, std::move(values)};
    } else if (isCellData) {
      frame.cellData[name] = {components, std::move(values)};
    }
  }
  if (static_cast<long>(points.size()) != 3 * n)
    throw InputError(path + ": <Points> does not hold NumberOfPoints × 3 values");
  if (static_cast<long>(types.size()) != nf || static_cast<long>(offsets.size()) != nf)
    throw InputError(path + ": <Cells> types/offsets do not match NumberOfCells");
  for (long t = 0; t < nf; ++t) {
    if (types[static_cast<std::size_t>(t)] != 5 || offsets[static_cast<std::size_t>(t)] != 3.0 * (t + 1))
      throw InputError(path + ": cell " + std::to_string(t) + " is not a triangle (only triangle meshes can be read)");
  }
  if (static_cast<long>(connectivity.size()) != 3 * nf) throw InputError(path + ": connectivity has the wrong size");
  frame.points.resize(n, 3);
  for (long k = 0; k < 3 * n; ++k) frame.points.data()[k] = points[static_cast<std::size_t>(k)];
  frame.triangles.resize(nf, 3);
  for (long k = 0; k < 3 * nf; ++k) {
    const double id = connectivity[static_cast<std::size_t>(k)];
    if (!(id >= 0 && id < n)) throw InputError(path + ": connectivity entry " + std::to_string(k) + " is out of range");
    if (id != std::floor(id))
      throw InputError(path + ": connectivity entry " + std::to_string(k) + " is not an integer");
    frame.triangles.data()[k] = static_cast<int>(id);
  }
  for (auto* data : {&frame.pointData, &frame.cellData})
    for (const auto& [name, a] : *data) {
      const long rows = data == &frame.pointData ? n : nf;
      if (static_cast<long>(a.values.size()) != rows * a.components)
        throw InputError(path + ": array '" + name + "' has the wrong number of values");
    }
  return frame;
}

VtuFrame readVtu(const std::string& path) {
  return parseVtu(readInputFile(path, inputLimits().maxObjBytes, "frame file"), path);
}

std::vector<std::string> pvdFrame(const std::string& xml, const std::string& path, long frame) {
  // The last step: its time first, then one pass that keeps only that step's files (a collection of millions of
  // entries is read without holding them). Frame k: the k-th run of equal times, in one pass that stops after it.
  const std::size_t last = xml.rfind("<DataSet");
  if (last == std::string::npos) throw InputError(path + ": no <DataSet> entries");
  const bool lastFrame = frame < 0;
  const std::string lastTime = lastFrame ? attribute(tagAt(xml, last, path), "timestep") : std::string();
  std::vector<std::string> files;
  std::string time;
  long index = -1;
  for (std::size_t at = xml.find("<DataSet"); at != std::string::npos; at = xml.find("<DataSet", at + 1)) {
    const std::string tag = tagAt(xml, at, path);
    const std::string t = attribute(tag, "timestep");
    if (lastFrame) {
      if (t != lastTime) continue;
    } else {
      if (index < 0 || t != time) ++index, time = t;
      if (index > frame) break;
      if (index < frame) continue;
    }
    const std::string file = attribute(tag, "file");
    if (file.empty())
      throw InputError(path + ": a <DataSet> of the " + (lastFrame ? std::string("last time step") :
                                                         "time step of frame " + std::to_string(frame)) +
                       " names no file");
    if (files.size() == kMaxPvdFiles)
      throw InputError(path + ": more than " + std::to_string(kMaxPvdFiles) + " files in one time step");
    files.push_back(file);
  }
  if (files.empty())
    throw InputError(path + ": no frame " + std::to_string(frame) + ": the series has " + std::to_string(index + 1) +
                     " frame" + (index == 0 ? "" : "s") + " (0 to " + std::to_string(index) + ")");
  return files;
}

std::vector<std::string> readPvdFrame(const std::string& path, long frame) {
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  std::vector<std::string> files =
      pvdFrame(readInputFile(path, inputLimits().maxJsonBytes, "frame collection"), path, frame);
  for (std::string& file : files) file = (base / file).string();
  return files;
}

}  // namespace jetshell
