// Edges, edge-to-face adjacency and the per-face four-triangle bending stencil of a manifold triangle mesh.
//
// Conventions: edge i of face f is the edge opposite vertex i, i.e. (F(f,(i+1)%3), F(f,(i+2)%3)).
// The bending stencil of face f is 6 vertex ids: F(f,0..2), then for i = 0..2 the vertex of the neighbour
// across edge i that is not on that edge, or -1 when edge i is on the boundary.
#pragma once

#include "core/mesh.h"

#include <array>
#include <vector>

namespace jetshell {

struct Topology {
  /// E×2 endpoint vertex ids, smaller id first.
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> edges;
  /// E×2 adjacent faces; column 1 is -1 on boundary edges. Column 0 is the face that has the edge's
  /// endpoints in the order (smaller, larger) or, for boundary edges, the only face.
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> edgeFaces;
  /// F×3: the edge opposite each vertex of each face.
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faceEdges;
  /// F×3: the neighbour face across edge i, or -1 on the boundary.
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faceNeighbors;
  /// F×6: the bending stencil (see the file comment).
  Eigen::Matrix<int, Eigen::Dynamic, 6, Eigen::RowMajor> bendingStencil;

  int numEdges() const { return static_cast<int>(edges.rows()); }
  bool isBoundaryEdge(int e) const { return edgeFaces(e, 1) < 0; }
};

/// Checks the mesh and builds its topology. Throws InputError naming the problem and the index for:
/// out-of-range or repeated vertex indices in a face, non-finite coordinates, degenerate (zero-area) faces,
/// non-manifold edges (three or more faces), inconsistently oriented neighbours, and empty meshes.
Topology buildTopology(const TriMesh& mesh);

/// The validation part of buildTopology alone.
void validateMesh(const TriMesh& mesh);

}  // namespace jetshell
