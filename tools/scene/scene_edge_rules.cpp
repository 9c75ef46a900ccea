#include "tools/scene/scene_edge_rules.h"

#include "energies/shell/boundary_rules.h"

#include <algorithm>

namespace jetshell {

std::vector<char> clampedVerticesOf(const ShellProblem& problem) {
  std::vector<char> clamped = problem.clampedVertices;
  for (const ShellActorPart& a : problem.actors) {
    if (a.clampedVertices.empty()) continue;
    if (clamped.empty()) clamped.assign(a.clampedVertices.size(), 0);
    const std::size_t n = std::min(clamped.size(), a.clampedVertices.size());
    for (std::size_t v = 0; v < n; ++v) clamped[v] = static_cast<char>(clamped[v] | a.clampedVertices[v]);
  }
  if (std::find(clamped.begin(), clamped.end(), 1) == clamped.end()) clamped.clear();
  return clamped;
}

void addSceneEdgeRules(const Scene& scene, const ShellProblem& problem, ShellSystem& system) {
  if (!system.bending) return;
  BoundaryRuleChoice choice;
  choice.clamp = edgeRuleFromString(scene.edgeRules.clamp);
  choice.free = edgeRuleFromString(scene.edgeRules.free);
  for (const EdgeRuleSettings::SymmetryPlane& p : scene.edgeRules.symmetryPlanes)
    choice.symmetryPlanes.push_back({p.point, p.normal});
  choice.planeTolerance = 1e-6;
  const std::vector<char> clamped = clampedVerticesOf(problem);
  const std::vector<char> momentLoaded = momentLoadedVertices(problem);
  // Every actor's bending term and the bending stiffness damping (Rayleigh: β_R times the same stiffness, so the
  // same rules).
  for (const std::shared_ptr<BendingTerm>& bending : system.bendingTerms)
    applyBoundaryRules(*bending, system.mesh(), clamped, momentLoaded, choice);
}

}  // namespace jetshell
