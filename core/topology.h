// Edges, edge-to-face adjacency and the per-face four-triangle bending stencil of a manifold triangle mesh.
//
// Conventions: edge i of face f is the edge opposite vertex i, i.e. (F(f,(i+1)%3), F(f,(i+2)%3)).
// The bending stencil of face f is 6 vertex ids: F(f,0..2), then for i = 0..2 the vertex of the neighbour
// across edge i that is not on that edge, or -1 when edge i is on the boundary.
#pragma once

#include "core/mesh.h"

#include <array>
#include <functional>
#include <string>
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

/// How validation messages name faces and vertices: a message is `subject(f) + " " + what`, where `what` may
/// mention other faces through `other(g)`. The default names faces by 0-based index ("mesh: face 3 (0, 1, 2)",
/// "face 2 (0, 2, 3)"); the OBJ reader by file and line ("m.obj:12: face", "the face on line 9"), with vertices
/// numbered from 1.
struct MeshNaming {
  std::function<std::string(int face)> subject;
  std::function<std::string(int face)> other;
  int firstVertexNumber = 0;
};

/// Faces whose normals are further apart than this across a shared edge are folded flat onto each other: the
/// mid-edge normal of such an edge (the mean of the two normals, Kelvin-inverted) is undefined at 180° and
/// explodes as 1/cos(θ/2) before, so a rest mesh with such a fold has no usable rest curvature.
constexpr double kMaxRestFoldDegrees = 179.9;

/// Checks the mesh and builds its topology. Throws InputError naming the problem and the faces for: empty meshes,
/// more vertices or faces than inputLimits() allows, non-finite coordinates, out-of-range or repeated vertex
/// indices in a face, degenerate (zero-area) faces, a face repeated (same or reversed order), non-manifold edges
/// (three or more faces), inconsistently oriented neighbours, and neighbours folded flat onto each other
/// (normals more than kMaxRestFoldDegrees apart).
Topology buildTopology(const TriMesh& mesh);

/// The first vertex that no face uses, or -1 when every vertex belongs to a face. A shell's vertex without a face
/// has neither stiffness nor mass: loaded, it cannot be balanced (the shell system and scene shapes refuse it;
/// buildTopology does not, since an actor's faces index the vertices of all actors stacked).
int firstVertexWithoutFace(const TriMesh& mesh);

/// The mean length of the mesh's edges (each edge once), or 0 for a mesh without edges.
double meanEdgeLength(const TriMesh& mesh, const Topology& topology);

/// Face f's shape: twice its area, |(x1 − x0) × (x2 − x0)|, and its longest edge's squared length. Its height
/// over its longest edge is doubleArea / longestSquared (buildTopology refuses 1e-12 and less as degenerate; the
/// scene reader warns of slivers above that: tools/scene/sliver_faces.h).
struct FaceShape {
  double doubleArea = 0.0;
  double longestSquared = 0.0;
};
FaceShape faceShape(const TriMesh& mesh, int f);

/// The validation part of buildTopology alone, with the default naming or the caller's.
void validateMesh(const TriMesh& mesh);
void validateMesh(const TriMesh& mesh, const MeshNaming& naming);

}  // namespace jetshell
