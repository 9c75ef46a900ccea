#include "core/hinge_stencil.h"

namespace jetshell {

HingeStencils hingeStencils(const TriMesh& mesh, const Topology& topology) {
  HingeStencils h;
  for (int e = 0; e < topology.numEdges(); ++e) {
    const int fa = topology.edgeFaces(e, 0), fb = topology.edgeFaces(e, 1);
    if (fb < 0) continue;
    const int p = topology.edges(e, 0), q = topology.edges(e, 1);
    int ids[4] = {-1, -1, -1, -1};
    for (int k = 0; k < 3; ++k) {
      const int u = mesh.F(fa, k), v = mesh.F(fa, (k + 1) % 3);
      if ((u == p && v == q) || (u == q && v == p)) {
        ids[0] = u;
        ids[1] = v;
        ids[2] = mesh.F(fa, (k + 2) % 3);
      }
    }
    for (int k = 0; k < 3; ++k)
      if (mesh.F(fb, k) != p && mesh.F(fb, k) != q) ids[3] = mesh.F(fb, k);
    h.table.ids.insert(h.table.ids.end(), ids, ids + 4);
    h.edge.push_back(e);
    h.faces.push_back({fa, fb});
    std::array<std::array<int, 3>, 2> corner{};
    for (int s = 0; s < 2; ++s)
      for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 4; ++l)
          if (ids[l] == mesh.F(s == 0 ? fa : fb, k)) corner[static_cast<std::size_t>(s)][static_cast<std::size_t>(k)] = l;
    h.corners.push_back(corner);
  }
  return h;
}

}  // namespace jetshell
