#include "core/mesh_io.h"

#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/topology.h"

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

/// Reads a decimal integer at `*p` and moves past it; false when there is none (or it overflows).
bool readIndex(const char** p, long* value) {
  char* end = nullptr;
  errno = 0;
  *value = std::strtol(*p, &end, 10);
  const bool ok = end != *p && errno != ERANGE;
  *p = end;
  return ok;
}

/// A face corner "i", "i/t", "i//n" or "i/t/n" with integer parts; returns the 1-based (or negative, relative)
/// vertex index. The texture and normal indices are not used, but a corner of any other form is refused.
long parseCorner(const std::string& token, const std::string& name, int line) {
  const char* p = token.c_str();
  long vertex = 0, unused = 0;
  bool ok = readIndex(&p, &vertex);
  if (ok && *p == '/') {
    ++p;
    if (*p != '/') ok = readIndex(&p, &unused);  // i/t or i/t/n
    if (ok && *p == '/') {
      ++p;
      ok = readIndex(&p, &unused);  // the normal index
    }
  }
  if (!ok || *p != '\0') fail(name, line, "face corner '" + token + "' is not an index (i, i/t, i//n or i/t/n)");
  if (vertex == 0) fail(name, line, "face index 0 is invalid (OBJ indices start at 1)");
  return vertex;
}

struct PendingFace {
  std::array<long, 3> corner;  // as written: 1-based, or negative = relative
  int verticesBefore;          // vertices defined before this face (for relative indices)
  int line;
};

/// Text lines hold printable characters, tabs and (in names and comments) UTF-8; other control bytes mean the
/// file is not text.
void requireText(const std::string& text, const std::string& name, int line) {
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 && c != '\t' && c != '\v' && c != '\f') {
      std::ostringstream s;
      s << "binary data (byte 0x" << std::hex << std::setw(2) << std::setfill('0') << static_cast<int>(c)
        << "): not an OBJ text file";
      fail(name, line, s.str());
    }
  }
}

}  // namespace

ObjMesh parseObj(std::istream& in, const std::string& name) {
  const InputLimits& limits = inputLimits();
  std::vector<Eigen::Vector3d> vertices;
  std::vector<int> vertexLine;
  std::vector<PendingFace> faces;
  std::string text;
  int line = 0;
  std::int64_t totalBytes = 0;
  while (readBoundedLine(in, text, limits.maxObjLineBytes, name, line + 1, totalBytes, limits.maxObjBytes)) {
    ++line;
    if (line == 1 && text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // UTF-8 byte-order mark
    requireText(text, name, line);
    std::istringstream tokens(text);
    std::string keyword;
    if (!(tokens >> keyword) || keyword[0] == '#') continue;
    std::vector<std::string> args;
    for (std::string t; tokens >> t;) {
      if (t[0] == '#') break;
      args.push_back(t);
    }
    if (keyword == "v") {
      // x y z, x y z w, or with a vertex colour: x y z r g b (some exporters write x y z w r g b).
      if (args.size() < 3 || args.size() > 7 || args.size() == 5)
        fail(name, line, "a vertex needs 3 coordinates (x y z, optionally w or a colour r g b)");
      Eigen::Vector3d p;
      for (int c = 0; c < 3; ++c) p[c] = parseCoordinate(args[static_cast<std::size_t>(c)], name, line);
      for (std::size_t c = 3; c < args.size(); ++c) parseCoordinate(args[c], name, line);
      if (static_cast<std::int64_t>(vertices.size()) >= limits.maxVertices) {
        std::ostringstream s;
        s << "too many vertices (at most " << limits.maxVertices << ")";
        fail(name, line, s.str());
      }
      vertices.push_back(p);
      vertexLine.push_back(line);
    } else if (keyword == "f") {
      if (args.size() < 3) fail(name, line, "a face needs at least 3 corners");
      std::vector<long> corners;
      for (const std::string& t : args) corners.push_back(parseCorner(t, name, line));
      if (static_cast<std::int64_t>(faces.size() + corners.size() - 2) > limits.maxFaces) {
        std::ostringstream s;
        s << "too many faces (at most " << limits.maxFaces << " triangles)";
        fail(name, line, s.str());
      }
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
  }
  const std::vector<int>& faceLine = out.faceLine;
  MeshNaming naming;
  naming.subject = [&](int f) { return name + ":" + std::to_string(faceLine[static_cast<std::size_t>(f)]) + ": face"; };
  naming.other = [&](int f) { return "the face on line " + std::to_string(faceLine[static_cast<std::size_t>(f)]); };
  naming.firstVertexNumber = 1;
  validateMesh(out.mesh, naming);
  return out;
}

TriMesh readObj(const std::string& path) {
  std::ifstream in = openInputFile(path, inputLimits().maxObjBytes, "mesh file");
  return parseObj(in, path).mesh;
}

void writeObj(std::ostream& out, const Positions& V, const Faces& F) {
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (Eigen::Index v = 0; v < V.rows(); ++v) out << "v " << V(v, 0) << ' ' << V(v, 1) << ' ' << V(v, 2) << '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    out << "f " << F(f, 0) + 1 << ' ' << F(f, 1) + 1 << ' ' << F(f, 2) + 1 << '\n';
}

}  // namespace jetshell
