// The hinge stencils of a triangle mesh: one per interior edge, the four vertices of its two faces, for terms
// whose element is an edge and its two faces (dihedral-angle bending, edge-based springs).
//
// Hinge i of edge e (faces A = edgeFaces(e, 0), B = edgeFaces(e, 1)) is the stencil (a, b, c, d): (a, b) the
// edge in face A's vertex order, c the third vertex of A, d the third vertex of B. `corners` gives each face's
// vertices, in that face's own order, as slots 0..3 of the stencil. Boundary edges have no hinge.
#pragma once

#include "core/mesh.h"
#include "core/stencil.h"
#include "core/topology.h"

#include <array>
#include <vector>

namespace jetshell {

struct HingeStencils {
  StencilTable table{4, {}};                                  // per hinge: (a, b, c, d)
  std::vector<int> edge;                                      // per hinge: its edge
  std::vector<std::array<int, 2>> faces;                      // per hinge: faces A, B
  std::vector<std::array<std::array<int, 3>, 2>> corners;     // per hinge and face: its vertices as stencil slots
  int size() const { return table.size(); }
};

HingeStencils hingeStencils(const TriMesh& mesh, const Topology& topology);

}  // namespace jetshell
