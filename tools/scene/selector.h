// Vertex selection for boundary conditions, loads and probes, by index or by geometry.
//
// The criteria set in one VertexSelector must all hold (an intersection); `nearest` then keeps, among the
// vertices that pass, the single one nearest to its point. A VertexSelection (a list of selectors) is the union
// of its selectors. Geometry is tested on the actor's reference positions in world coordinates.
#pragma once

#include "core/mesh.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace jetshell {

struct TriangularMeshShape;

struct VertexSelector {
  struct Box {
    Eigen::Vector3d min, max;
  };
  struct PlaneBand {  // |(x − point)·n̂| <= distance
    Eigen::Vector3d point, normal;
    double distance = 0.0;
  };
  bool all = false;                      // every vertex (combine with others to restrict)
  std::optional<std::vector<int>> indices;
  std::optional<std::string> group;      // a named vertex group of the shape (generators name their boundaries)
  std::optional<Box> box;
  std::optional<PlaneBand> plane;
  bool boundaryOnly = false;             // only vertices on a boundary edge
  std::optional<Eigen::Vector3d> nearest;

  /// True when no criterion is set (such a selector is an error: it would be unclear what it means).
  bool empty() const { return !all && !indices && !group && !box && !plane && !boundaryOnly && !nearest; }
};

using VertexSelection = std::vector<VertexSelector>;

/// What a selection is resolved against: one actor's reference positions (world frame), its shape (for
/// groups) and which of its vertices lie on the boundary.
struct SelectionContext {
  const Positions* worldPositions;
  const TriangularMeshShape* shape;
  const std::vector<char>* boundaryVertex;
};

/// The sorted, unique local vertex ids a selection picks. Throws InputError naming `where` (e.g.
/// "/actors/0/fixed/1/select") when a selector is empty or malformed, an index is out of range, a group is
/// unknown, or when nothing at all is selected.
std::vector<int> selectVertices(const VertexSelection& selection, const SelectionContext& context,
                                const std::string& where);

/// Validates the parameters of a selector (finite points, non-zero normal, box min <= max, distance >= 0)
/// without a mesh.
void validate(const VertexSelector& s, const std::string& where);

}  // namespace jetshell
