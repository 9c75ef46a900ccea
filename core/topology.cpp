#include "core/topology.h"

#include "core/input_limits.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <sstream>

namespace jetshell {

FaceShape faceShape(const TriMesh& mesh, int f) {
  const Eigen::Vector3d x0 = mesh.V.row(mesh.F(f, 0)), x1 = mesh.V.row(mesh.F(f, 1)), x2 = mesh.V.row(mesh.F(f, 2));
  return {(x1 - x0).cross(x2 - x0).norm(),
          std::max({(x1 - x0).squaredNorm(), (x2 - x0).squaredNorm(), (x2 - x1).squaredNorm()})};
}

namespace {

struct HalfEdge {
  std::int64_t key;  // (min vertex, max vertex) packed
  int face;
  int local;         // edge i of the face (opposite vertex i)
  bool forward;      // face traverses the edge from min to max
};

/// Every face's three edges, sorted by edge (then face): the two sides of an interior edge are neighbours.
std::vector<HalfEdge> sortedHalfEdges(const TriMesh& mesh) {
  const int nf = mesh.numFaces();
  std::vector<HalfEdge> half;
  half.reserve(3 * static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      const int a = mesh.F(f, (i + 1) % 3), b = mesh.F(f, (i + 2) % 3);
      const std::int64_t lo = std::min(a, b), hi = std::max(a, b);
      half.push_back({(lo << 32) | hi, f, i, a < b});
    }
  }
  std::sort(half.begin(), half.end(), [](const HalfEdge& p, const HalfEdge& q) {
    return p.key != q.key ? p.key < q.key : p.face < q.face;
  });
  return half;
}

MeshNaming defaultNaming(const TriMesh& m) {
  auto name = [&m](int f) {
    std::ostringstream s;
    s << "face " << f << " (" << m.F(f, 0) << ", " << m.F(f, 1) << ", " << m.F(f, 2) << ")";
    return s.str();
  };
  return {[name](int f) { return "mesh: " + name(f); }, name, 0};
}

Eigen::Vector3d faceNormal(const TriMesh& m, int f) {
  const Eigen::Vector3d x0 = m.V.row(m.F(f, 0)), x1 = m.V.row(m.F(f, 1)), x2 = m.V.row(m.F(f, 2));
  return (x1 - x0).cross(x2 - x0).normalized();
}

/// A face's vertex ids rotated so that the smallest comes first (equal for the same triangle, not for its reverse).
std::array<int, 3> canonicalRotation(const TriMesh& m, int f) {
  int k = 0;
  for (int c = 1; c < 3; ++c)
    if (m.F(f, c) < m.F(f, k)) k = c;
  return {m.F(f, k), m.F(f, (k + 1) % 3), m.F(f, (k + 2) % 3)};
}

void checkRepeatedFaces(const TriMesh& mesh, const MeshNaming& naming) {
  std::vector<std::pair<std::array<int, 3>, int>> sets;  // sorted vertex ids, face
  sets.reserve(static_cast<std::size_t>(mesh.numFaces()));
  for (int f = 0; f < mesh.numFaces(); ++f) {
    std::array<int, 3> ids = {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    std::sort(ids.begin(), ids.end());
    sets.push_back({ids, f});
  }
  std::sort(sets.begin(), sets.end());
  for (std::size_t k = 1; k < sets.size(); ++k) {
    if (sets[k].first != sets[k - 1].first) continue;
    const int first = sets[k - 1].second, second = sets[k].second;
    const bool same = canonicalRotation(mesh, first) == canonicalRotation(mesh, second);
    throw InputError(naming.subject(second) + (same ? " duplicates " + naming.other(first)
                                                    : " is " + naming.other(first) +
                                                          " reversed (two faces on the same three vertices)"));
  }
}

void checkEdges(const TriMesh& mesh, const std::vector<HalfEdge>& half, const MeshNaming& naming) {
  const int base = naming.firstVertexNumber;
  for (std::size_t k = 0; k < half.size();) {
    std::size_t end = k + 1;
    while (end < half.size() && half[end].key == half[k].key) ++end;
    const std::int64_t lo = (half[k].key >> 32) + base, hi = (half[k].key & 0xffffffff) + base;
    if (end - k > 2) {
      std::ostringstream s;
      s << naming.subject(half[k + 2].face) << " uses the non-manifold edge between vertices " << lo << " and " << hi
        << ", also used by " << naming.other(half[k].face) << " and " << naming.other(half[k + 1].face)
        << " (an edge joins at most two faces)";
      throw InputError(s.str());
    }
    if (end - k == 2) {
      const HalfEdge& p = half[k];
      const HalfEdge& q = half[k + 1];
      if (p.forward == q.forward) {
        std::ostringstream s;
        s << naming.subject(q.face) << " is oriented against " << naming.other(p.face) << " (both run from vertex "
          << (p.forward ? lo : hi) << " to vertex " << (p.forward ? hi : lo)
          << " along their shared edge; neighbours must run it in opposite directions)";
        throw InputError(s.str());
      }
      const Eigen::Vector3d np = faceNormal(mesh, p.face), nq = faceNormal(mesh, q.face);
      const double degrees = std::atan2(np.cross(nq).norm(), np.dot(nq)) * 180.0 / 3.14159265358979323846;
      if (!(degrees <= kMaxRestFoldDegrees)) {
        std::ostringstream s;
        s << naming.subject(q.face) << " is folded flat onto " << naming.other(p.face)
          << " across the edge between vertices " << lo << " and " << hi << " (normals " << std::fixed
          << std::setprecision(3) << degrees << " degrees apart, at most " << std::setprecision(1)
          << kMaxRestFoldDegrees << ": the rest curvature is undefined there)";
        throw InputError(s.str());
      }
    }
    k = end;
  }
}

/// validateMesh; returns the sorted half-edges it checked (buildTopology pairs them).
std::vector<HalfEdge> checkedHalfEdges(const TriMesh& mesh, const MeshNaming& naming) {
  const int n = mesh.numVertices();
  if (n == 0) throw InputError("mesh: no vertices");
  if (mesh.numFaces() == 0) throw InputError("mesh: no faces");
  const InputLimits& limits = inputLimits();
  if (n > limits.maxVertices)
    throw InputError("mesh: " + std::to_string(n) + " vertices, too many (at most " +
                     std::to_string(limits.maxVertices) + ")");
  if (mesh.numFaces() > limits.maxFaces)
    throw InputError("mesh: " + std::to_string(mesh.numFaces()) + " faces, too many (at most " +
                     std::to_string(limits.maxFaces) + ")");
  for (int v = 0; v < n; ++v) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(mesh.V(v, c))) {
        std::ostringstream s;
        s << "mesh: vertex " << v + naming.firstVertexNumber << " has a non-finite coordinate (" << mesh.V(v, 0)
          << ", " << mesh.V(v, 1) << ", " << mesh.V(v, 2) << ")";
        throw InputError(s.str());
      }
    }
  }
  for (int f = 0; f < mesh.numFaces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.F(f, c);
      if (v < 0 || v >= n) {
        std::ostringstream s;
        s << naming.subject(f) << " has vertex index " << v << " out of range [0, " << n << ")";
        throw InputError(s.str());
      }
    }
    if (mesh.F(f, 0) == mesh.F(f, 1) || mesh.F(f, 1) == mesh.F(f, 2) || mesh.F(f, 0) == mesh.F(f, 2))
      throw InputError(naming.subject(f) + " repeats a vertex");
    const auto [doubleArea, scale] = faceShape(mesh, f);
    if (!std::isfinite(doubleArea) || !std::isfinite(scale))
      throw InputError(naming.subject(f) + " is too large to measure (its area overflows a double)");
    if (!(doubleArea > 1e-12 * scale) || scale == 0.0) {
      std::ostringstream s;
      s << naming.subject(f) << " is degenerate (area " << 0.5 * doubleArea << ")";
      throw InputError(s.str());
    }
  }
  checkRepeatedFaces(mesh, naming);
  std::vector<HalfEdge> half = sortedHalfEdges(mesh);
  checkEdges(mesh, half, naming);
  return half;
}

}  // namespace

int firstVertexWithoutFace(const TriMesh& mesh) {
  std::vector<char> used(static_cast<std::size_t>(mesh.numVertices()), 0);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.F(f, c);
      if (v >= 0 && v < mesh.numVertices()) used[static_cast<std::size_t>(v)] = 1;
    }
  for (std::size_t v = 0; v < used.size(); ++v)
    if (!used[v]) return static_cast<int>(v);
  return -1;
}

double meanEdgeLength(const TriMesh& mesh, const Topology& topology) {
  double sum = 0.0;
  for (int e = 0; e < topology.numEdges(); ++e)
    sum += (mesh.V.row(topology.edges(e, 0)) - mesh.V.row(topology.edges(e, 1))).norm();
  return topology.numEdges() > 0 ? sum / topology.numEdges() : 0.0;
}

void validateMesh(const TriMesh& mesh) { checkedHalfEdges(mesh, defaultNaming(mesh)); }

void validateMesh(const TriMesh& mesh, const MeshNaming& naming) { checkedHalfEdges(mesh, naming); }

Topology buildTopology(const TriMesh& mesh) {
  const std::vector<HalfEdge> half = checkedHalfEdges(mesh, defaultNaming(mesh));
  const int nf = mesh.numFaces();

  Topology t;
  t.faceEdges.resize(nf, 3);
  t.faceNeighbors.setConstant(nf, 3, -1);
  std::vector<std::array<int, 4>> edges;  // lo, hi, face0, face1
  edges.reserve(half.size() / 2 + 1);
  for (std::size_t k = 0; k < half.size();) {
    std::size_t end = k + 1;
    while (end < half.size() && half[end].key == half[k].key) ++end;
    const int lo = static_cast<int>(half[k].key >> 32), hi = static_cast<int>(half[k].key & 0xffffffff);
    const int e = static_cast<int>(edges.size());
    if (end - k == 2) {
      const HalfEdge& p = half[k];
      const HalfEdge& q = half[k + 1];
      const HalfEdge& first = p.forward ? p : q;
      const HalfEdge& second = p.forward ? q : p;
      edges.push_back({lo, hi, first.face, second.face});
      t.faceEdges(p.face, p.local) = e;
      t.faceEdges(q.face, q.local) = e;
      t.faceNeighbors(p.face, p.local) = q.face;
      t.faceNeighbors(q.face, q.local) = p.face;
    } else {
      edges.push_back({lo, hi, half[k].face, -1});
      t.faceEdges(half[k].face, half[k].local) = e;
    }
    k = end;
  }
  const int ne = static_cast<int>(edges.size());
  t.edges.resize(ne, 2);
  t.edgeFaces.resize(ne, 2);
  for (int e = 0; e < ne; ++e) {
    t.edges(e, 0) = edges[e][0];
    t.edges(e, 1) = edges[e][1];
    t.edgeFaces(e, 0) = edges[e][2];
    t.edgeFaces(e, 1) = edges[e][3];
  }
  t.bendingStencil.resize(nf, 6);
  for (int f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      t.bendingStencil(f, i) = mesh.F(f, i);
      const int g = t.faceNeighbors(f, i);
      int opposite = -1;
      if (g >= 0) {
        for (int j = 0; j < 3; ++j) {
          const int v = mesh.F(g, j);
          if (v != mesh.F(f, (i + 1) % 3) && v != mesh.F(f, (i + 2) % 3)) opposite = v;
        }
      }
      t.bendingStencil(f, 3 + i) = opposite;
    }
  }
  return t;
}

}  // namespace jetshell
