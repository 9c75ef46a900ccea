#include "tools/output/vtu.h"

#include "core/input_file.h"
#include "core/input_limits.h"

#include "tools/output/atomic_file.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

namespace jetshell {

std::string formatDouble(double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

namespace {

void writeArray(std::ostream& out, const std::string& name, const VtuFrame::Array& a) {
  out << "        <DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"" << a.components
      << "\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < a.values.size(); ++k)
    out << (k % static_cast<std::size_t>(a.components) == 0 ? "          " : " ") << formatDouble(a.values[k])
        << ((k + 1) % static_cast<std::size_t>(a.components) == 0 ? "\n" : "");
  out << "        </DataArray>\n";
}

const char* activeVector(const std::map<std::string, VtuFrame::Array>& arrays) {
  if (arrays.count("displacement")) return " Vectors=\"displacement\"";
  if (arrays.count("velocity")) return " Vectors=\"velocity\"";
  return "";
}

}  // namespace

void writeVtu(std::ostream& out, const VtuFrame& f) {
  const Eigen::Index n = f.points.rows(), nf = f.triangles.rows();
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << nf << "\">\n";
  out << "      <PointData" << activeVector(f.pointData) << ">\n";
  for (const auto& [name, a] : f.pointData) writeArray(out, name, a);
  out << "      </PointData>\n      <CellData" << activeVector(f.cellData) << ">\n";
  for (const auto& [name, a] : f.cellData) writeArray(out, name, a);
  out << "      </CellData>\n      <Points>\n"
      << "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Eigen::Index v = 0; v < n; ++v)
    out << "          " << formatDouble(f.points(v, 0)) << ' ' << formatDouble(f.points(v, 1)) << ' '
        << formatDouble(f.points(v, 2)) << '\n';
  out << "        </DataArray>\n      </Points>\n      <Cells>\n"
      << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (Eigen::Index t = 0; t < nf; ++t)
    out << "          " << f.triangles(t, 0) << ' ' << f.triangles(t, 1) << ' ' << f.triangles(t, 2) << '\n';
  out << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (Eigen::Index t = 0; t < nf; ++t) out << (t % 16 == 0 ? "          " : " ") << 3 * (t + 1) << (t % 16 == 15 || t + 1 == nf ? "\n" : "");
  out << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (Eigen::Index t = 0; t < nf; ++t) out << (t % 32 == 0 ? "          " : " ") << 5 << (t % 32 == 31 || t + 1 == nf ? "\n" : "");
  out << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
}

namespace {

std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return "";
  const std::size_t start = at + key.size();
  return tag.substr(start, tag.find('"', start) - start);
}

/// A count attribute of a tag (NumberOfPoints, NumberOfCells): an integer from 0 to `maximum`, the limit a scene's
/// meshes have (core/input_limits.h).
long countAttribute(const std::string& tag, const std::string& name, const std::string& path, std::int64_t maximum) {
  const std::string text = attribute(tag, name);
  long value = -1;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || stop != end || value < 0 || value > maximum)
    throw InputError(path + ": " + name + "=\"" + text.substr(0, 32) + "\" is not an integer from 0 to " +
                     std::to_string(maximum));
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

}  // namespace

VtuFrame readVtu(const std::string& path) {
  const std::string xml = readInputFile(path, inputLimits().maxObjBytes, "frame file");
  if (xml.find("type=\"UnstructuredGrid\"") == std::string::npos)
    throw InputError(path + ": not a VTK XML UnstructuredGrid (.vtu) file");
  if (xml.find("<AppendedData") != std::string::npos)
    throw InputError(path + ": appended (binary) data is not supported; save the file with ASCII data");
  const std::size_t piece = xml.find("<Piece");
  if (piece == std::string::npos) throw InputError(path + ": no <Piece>");
  const std::string pieceTag = xml.substr(piece, xml.find('>', piece) - piece);
  const long n = countAttribute(pieceTag, "NumberOfPoints", path, inputLimits().maxVertices);
  const long nf = countAttribute(pieceTag, "NumberOfCells", path, inputLimits().maxFaces);
  const std::size_t maxValues = 9 * static_cast<std::size_t>(std::max(n, nf));

  VtuFrame frame;
  std::vector<double> points, connectivity, offsets, types;
  for (std::size_t at = xml.find("<DataArray", piece); at != std::string::npos; at = xml.find("<DataArray", at + 1)) {
    const std::size_t close = xml.find('>', at);
    const std::string tag = xml.substr(at, close - at);
    const std::size_t endArray = xml.find("</DataArray>", close);
    if (endArray == std::string::npos) throw InputError(path + ": unterminated <DataArray>");
    const std::string name = attribute(tag, "Name");
    if (attribute(tag, "format") != "ascii")
      throw InputError(path + ": array '" + name + "' is not ASCII; save the file with ASCII data");
    std::vector<double> values =
        numbers(xml.substr(close + 1, endArray - close - 1), path, "'" + name + "'", maxValues);
    // The section an array belongs to is the innermost one opened before it.
    auto openedBefore = [&](const char* section) {
      const std::size_t open = xml.rfind(std::string("<") + section, at);
      const std::size_t shut = xml.rfind(std::string("</") + section, at);
      return open != std::string::npos && (shut == std::string::npos || shut < open);
    };
    const std::string componentsText = attribute(tag, "NumberOfComponents");
    int components = 1;
    if (!componentsText.empty()) {
      char* endNumber = nullptr;
      const long c = std::strtol(componentsText.c_str(), &endNumber, 10);
      if (*endNumber != '\0' || c < 1 || c > 9)
        throw InputError(path + ": array '" + name + "': NumberOfComponents=\"" + componentsText.substr(0, 32) +
                         "\" is not an integer from 1 to 9");
      components = static_cast<int>(c);
    }
    if (openedBefore("Points")) {
      points = std::move(values);
    } else if (openedBefore("Cells")) {
      if (name == "connectivity") connectivity = std::move(values);
      else if (name == "offsets") offsets = std::move(values);
      else if (name == "types") types = std::move(values);
    } else if (openedBefore("PointData")) {
      frame.pointData[name] = {components, std::move(values)};
    } else if (openedBefore("CellData")) {
      frame.cellData[name] = {components, std::move(values)};
    }
  }
  if (static_cast<long>(points.size()) != 3 * n) throw InputError(path + ": <Points> does not hold NumberOfPoints × 3 values");
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

std::string PvdSeries::head() {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
}

namespace {

/// Text as an XML attribute value: the five special characters escaped.
std::string xmlAttribute(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::string PvdSeries::entry(double time, const std::string& file, int part, const std::string& name) {
  return "    <DataSet timestep=\"" + formatDouble(time) + "\" group=\"\" part=\"" + std::to_string(part) + "\"" +
         (name.empty() ? std::string() : " name=\"" + xmlAttribute(name) + "\"") + " file=\"" + xmlAttribute(file) +
         "\"/>\n";
}

std::string PvdSeries::tail() { return "  </Collection>\n</VTKFile>\n"; }

void PvdSeries::write(const std::string& path) const {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << head();
    for (const Entry& e : entries_) out << entry(e.time, e.file, e.part, e.name);
    out << tail();
  });
}

}  // namespace jetshell
