// Which edge rule (energies/shell/edge_rules.h) each boundary edge of a bending term takes, from a choice made
// once for a whole shell (a scene's `edgeRules`, a benchmark's options): the one place that orders the rules.
//
// Inputs: the bending term, its rest mesh, the vertices whose edges are clamped (`clampRotation`) and those whose
// edges carry an applied moment (each size N or empty), and the choice. Precedence, last wins: the free rule on
// every boundary edge; the page's free rule on moment-loaded edges (a moment-free edge would release the face
// that takes the applied moment); symmetry_plane on edges whose two endpoints lie on a plane; the clamp rule on
// clamped edges. Output: the term's edge rules set; the counts per kind.
#pragma once

#include "core/mesh.h"
#include "energies/shell/bending_term.h"
#include "energies/shell/edge_rules.h"

#include <Eigen/Core>

#include <vector>

namespace jetshell {

struct BoundaryRuleChoice {
  EdgeRule free = EdgeRule::SecondOrderFree;  // free edges: second_order_free or page_free
  EdgeRule clamp = EdgeRule::MirroredClamp;   // clamped edges: mirrored_clamp or reference_clamp
  struct Plane {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  // finite, nonzero (InputError otherwise)
  };
  std::vector<Plane> symmetryPlanes;
  /// A vertex lies on a plane when its distance is at most this times the mesh's bounding-box diagonal.
  double planeTolerance = 1e-9;
};

struct BoundaryRuleCounts {
  int free = 0, momentLoaded = 0, symmetry = 0, clamped = 0;  // edges given each rule (before later overrides)
};

/// Sets every boundary edge's rule of `bending` (see the file comment). InputError for a free rule that is not
/// free, a clamp rule that is not a clamp, or an invalid plane.
BoundaryRuleCounts applyBoundaryRules(BendingTerm& bending, const TriMesh& restMesh,
                                      const std::vector<char>& clampedVertices,
                                      const std::vector<char>& momentLoadedVertices, const BoundaryRuleChoice& choice);

}  // namespace jetshell
