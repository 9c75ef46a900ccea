// The writers of tools/output/vtu.h (the readers are vtu_reader.cpp).
#include "tools/output/vtu.h"

#include "tools/output/atomic_file.h"

#include <charconv>
#include <ostream>

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
