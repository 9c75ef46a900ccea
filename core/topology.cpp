#include "core/topology.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace jetshell {
namespace {

struct HalfEdge {
  std::int64_t key;  // (min vertex, max vertex) packed
  int face;
  int local;         // edge i of the face (opposite vertex i)
  bool forward;      // face traverses the edge from min to max
};

std::string faceString(const TriMesh& m, int f) {
  std::ostringstream s;
  s << "face " << f << " (" << m.F(f, 0) << ", " << m.F(f, 1) << ", " << m.F(f, 2) << ")";
  return s.str();
}

}  // namespace

void validateMesh(const TriMesh& mesh) {
  const int n = mesh.numVertices();
  if (n == 0) throw InputError("mesh: no vertices");
  if (mesh.numFaces() == 0) throw InputError("mesh: no faces");
  for (int v = 0; v < n; ++v) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(mesh.V(v, c))) {
        std::ostringstream s;
        s << "mesh: vertex " << v << " has a non-finite coordinate (" << mesh.V(v, 0) << ", " << mesh.V(v, 1)
          << ", " << mesh.V(v, 2) << ")";
        throw InputError(s.str());
      }
    }
  }
  for (int f = 0; f < mesh.numFaces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.F(f, c);
      if (v < 0 || v >= n) {
        std::ostringstream s;
        s << "mesh: " << faceString(mesh, f) << " has vertex index " << v << " out of range [0, " << n << ")";
        throw InputError(s.str());
      }
    }
    if (mesh.F(f, 0) == mesh.F(f, 1) || mesh.F(f, 1) == mesh.F(f, 2) || mesh.F(f, 0) == mesh.F(f, 2)) {
      throw InputError("mesh: " + faceString(mesh, f) + " repeats a vertex");
    }
    const Eigen::Vector3d x0 = mesh.V.row(mesh.F(f, 0)), x1 = mesh.V.row(mesh.F(f, 1)), x2 = mesh.V.row(mesh.F(f, 2));
    const double doubleArea = (x1 - x0).cross(x2 - x0).norm();
    const double scale = std::max({(x1 - x0).squaredNorm(), (x2 - x0).squaredNorm(), (x2 - x1).squaredNorm()});
    if (!(doubleArea > 1e-12 * scale) || scale == 0.0) {
      std::ostringstream s;
      s << "mesh: " << faceString(mesh, f) << " is degenerate (area " << 0.5 * doubleArea << ")";
      throw InputError(s.str());
    }
  }
}

Topology buildTopology(const TriMesh& mesh) {
  validateMesh(mesh);
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

  Topology t;
  t.faceEdges.resize(nf, 3);
  t.faceNeighbors.setConstant(nf, 3, -1);
  std::vector<std::array<int, 4>> edges;  // lo, hi, face0, face1
  edges.reserve(half.size() / 2 + 1);
  for (std::size_t k = 0; k < half.size();) {
    std::size_t end = k + 1;
    while (end < half.size() && half[end].key == half[k].key) ++end;
    const int lo = static_cast<int>(half[k].key >> 32), hi = static_cast<int>(half[k].key & 0xffffffff);
    if (end - k > 2) {
      std::ostringstream s;
      s << "mesh: non-manifold edge (" << lo << ", " << hi << ") is shared by " << (end - k) << " faces:";
      for (std::size_t j = k; j < end; ++j) s << ' ' << half[j].face;
      throw InputError(s.str());
    }
    const int e = static_cast<int>(edges.size());
    if (end - k == 2) {
      const HalfEdge& p = half[k];
      const HalfEdge& q = half[k + 1];
      if (p.forward == q.forward) {
        std::ostringstream s;
        s << "mesh: faces " << p.face << " and " << q.face << " are inconsistently oriented across edge (" << lo
          << ", " << hi << ")";
        throw InputError(s.str());
      }
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
