#include "core/mesh_io.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace jetshell {
namespace {

[[noreturn]] void fail(const std::string& name, int line, const std::string& what) {
  std::ostringstream s;
  s << name << ":" << line << ": " << what;
  throw InputError(s.str());
}

double parseCoordinate(const std::string& token, const std::string& name, int line) {
  const char* begin = token.c_str();
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(begin, &end);
  if (end == begin || *end != '\0') fail(name, line, "'" + token + "' is not a number");
  if (!std::isfinite(value) || errno == ERANGE) fail(name, line, "vertex coordinate '" + token + "' is not finite");
  return value;
}

/// A face corner "i", "i/t", "i//n" or "i/t/n"; returns the 1-based (or negative, relative) vertex index.
long parseCorner(const std::string& token, const std::string& name, int line) {
  const std::string head = token.substr(0, token.find('/'));
  const char* begin = head.c_str();
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(begin, &end, 10);
  if (end == begin || *end != '\0' || errno == ERANGE) fail(name, line, "face corner '" + token + "' is not an index");
  if (value == 0) fail(name, line, "face index 0 is invalid (OBJ indices start at 1)");
  return value;
}

struct PendingFace {
  std::array<long, 3> corner;  // as written: 1-based, or negative = relative
  int verticesBefore;          // vertices defined before this face (for relative indices)
  int line;
};

void checkOrientationAndManifold(const ObjMesh& m, const std::string& name) {
  struct Use {
    int face;
    bool forward;
  };
  std::unordered_map<std::uint64_t, std::vector<Use>> edges;
  const Faces& F = m.mesh.F;
  edges.reserve(static_cast<std::size_t>(F.rows()) * 2);
  for (int f = 0; f < F.rows(); ++f) {
    for (int i = 0; i < 3; ++i) {
      const int a = F(f, i), b = F(f, (i + 1) % 3);
      const std::uint64_t lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
      std::vector<Use>& uses = edges[(lo << 32) | hi];
      uses.push_back({f, a < b});
      if (uses.size() == 3) {
        std::ostringstream s;
        s << "non-manifold edge between vertices " << lo + 1 << " and " << hi + 1 << ": also used by the faces on lines "
          << m.faceLine[uses[0].face] << " and " << m.faceLine[uses[1].face];
        fail(name, m.faceLine[f], s.str());
      }
      if (uses.size() == 2 && uses[0].forward == uses[1].forward) {
        std::ostringstream s;
        s << "face orientation is inconsistent with the face on line " << m.faceLine[uses[0].face]
          << " (both traverse the edge between vertices " << a + 1 << " and " << b + 1 << " in the same direction)";
        fail(name, m.faceLine[f], s.str());
      }
    }
  }
}

}  // namespace

ObjMesh parseObj(std::istream& in, const std::string& name) {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<int> vertexLine;
  std::vector<PendingFace> faces;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream tokens(text);
    std::string keyword;
    if (!(tokens >> keyword) || keyword[0] == '#') continue;
    std::vector<std::string> args;
    for (std::string t; tokens >> t;) {
      if (t[0] == '#') break;
      args.push_back(t);
    }
    if (keyword == "v") {
      if (args.size() < 3 || args.size() > 4) fail(name, line, "a vertex needs 3 coordinates (x y z [w])");
      Eigen::Vector3d p;
      for (int c = 0; c < 3; ++c) p[c] = parseCoordinate(args[static_cast<std::size_t>(c)], name, line);
      vertices.push_back(p);
      vertexLine.push_back(line);
    } else if (keyword == "f") {
      if (args.size() < 3) fail(name, line, "a face needs at least 3 corners");
      std::vector<long> corners;
      for (const std::string& t : args) corners.push_back(parseCorner(t, name, line));
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)  // fan triangulation of polygons
        faces.push_back({{corners[0], corners[k], corners[k + 1]}, static_cast<int>(vertices.size()), line});
    } else if (keyword == "l" || keyword == "p") {
      fail(name, line, "'" + keyword + "' elements are not supported (a shell mesh has triangles only)");
    }
    // vt, vn, vp, g, o, s, usemtl, mtllib and unknown statements carry nothing a shell needs.
  }
  if (in.bad()) throw InputError(name + ": read error");

  ObjMesh out;
  const int n = static_cast<int>(vertices.size());
  if (n == 0) throw InputError(name + ": no vertices ('v' lines)");
  if (faces.empty()) throw InputError(name + ": no faces ('f' lines)");
  out.mesh.V.resize(n, 3);
  for (int v = 0; v < n; ++v) out.mesh.V.row(v) = vertices[static_cast<std::size_t>(v)].transpose();
  out.vertexLine = std::move(vertexLine);
  out.mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  out.faceLine.resize(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const PendingFace& p = faces[f];
    out.faceLine[f] = p.line;
    for (int c = 0; c < 3; ++c) {
      const long raw = p.corner[static_cast<std::size_t>(c)];
      const long index = raw > 0 ? raw - 1 : p.verticesBefore + raw;
      if (index < 0 || index >= n) {
        std::ostringstream s;
        s << "face index " << raw << " is out of range (the file has " << n << " vertices";
        if (raw < 0) s << ", " << p.verticesBefore << " before this line";
        s << ")";
        fail(name, p.line, s.str());
      }
      out.mesh.F(static_cast<Eigen::Index>(f), c) = static_cast<int>(index);
    }
    const auto row = out.mesh.F.row(static_cast<Eigen::Index>(f));
    if (row[0] == row[1] || row[1] == row[2] || row[0] == row[2]) fail(name, p.line, "face repeats a vertex");
    const Eigen::Vector3d x0 = out.mesh.V.row(row[0]), x1 = out.mesh.V.row(row[1]), x2 = out.mesh.V.row(row[2]);
    const double doubleArea = (x1 - x0).cross(x2 - x0).norm();
    const double scale = std::max({(x1 - x0).squaredNorm(), (x2 - x0).squaredNorm(), (x2 - x1).squaredNorm()});
    if (scale == 0.0 || !(doubleArea > 1e-12 * scale)) fail(name, p.line, "degenerate face (zero area)");
  }
  checkOrientationAndManifold(out, name);
  return out;
}

TriMesh readObj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open mesh file");
  return parseObj(in, path).mesh;
}

void writeObj(std::ostream& out, const Positions& V, const Faces& F) {
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (Eigen::Index v = 0; v < V.rows(); ++v) out << "v " << V(v, 0) << ' ' << V(v, 1) << ' ' << V(v, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    out << "f " << F(f, 0) + 1 << ' ' << F(f, 1) + 1 << ' ' << F(f, 2) + 1 << '\n';
}

}  // namespace jetshell
