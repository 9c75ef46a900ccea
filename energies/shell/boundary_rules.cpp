#include "energies/shell/boundary_rules.h"

#include <cmath>
#include <string>

namespace jetshell {

BoundaryRuleCounts applyBoundaryRules(BendingTerm& bending, const TriMesh& mesh, const std::vector<char>& clamped,
                                      const std::vector<char>& momentLoaded, const BoundaryRuleChoice& choice) {
  if (choice.free != EdgeRule::SecondOrderFree && choice.free != EdgeRule::PageFree)
    throw InputError(std::string("free edge rule: '") + edgeRuleName(choice.free) +
                     "' is not one of second_order_free, page_free");
  if (choice.clamp != EdgeRule::MirroredClamp && choice.clamp != EdgeRule::ReferenceClamp)
    throw InputError(std::string("clamp edge rule: '") + edgeRuleName(choice.clamp) +
                     "' is not one of mirrored_clamp, reference_clamp");
  const int n = mesh.numVertices();
  BoundaryRuleCounts counts;
  counts.free = bending.setEdgeRule(std::vector<char>(static_cast<std::size_t>(n), 1), choice.free);
  if (!momentLoaded.empty()) counts.momentLoaded = bending.setEdgeRule(momentLoaded, EdgeRule::PageFree);
  const double size = n > 0 ? (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm() : 0.0;
  for (const BoundaryRuleChoice::Plane& p : choice.symmetryPlanes) {
    if (!(p.point.allFinite() && p.normal.allFinite() && p.normal.norm() > 0.0))
      throw InputError("symmetry plane: point and normal must be finite, the normal nonzero");
    const Eigen::Vector3d u = p.normal.normalized();
    std::vector<char> onPlane(static_cast<std::size_t>(n), 0);
    for (int v = 0; v < n; ++v) {
      const double distance = (Eigen::Vector3d(mesh.V.row(v).transpose()) - p.point).dot(u);
      onPlane[v] = std::abs(distance) <= choice.planeTolerance * size;
    }
    counts.symmetry += bending.setEdgeRule(onPlane, EdgeRule::SymmetryPlane, u);
  }
  if (!clamped.empty()) counts.clamped = bending.setEdgeRule(clamped, choice.clamp);
  return counts;
}

}  // namespace jetshell
