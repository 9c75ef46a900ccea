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
  // One bending term over the whole mesh, or one per actor ("bending/<actor>") when their materials differ; and
  // the bending stiffness damping (Rayleigh: β_R times the same stiffness, so the same rules).
  for (const std::string& name : system.objective().activeTermNames()) {
    if (name != "bending" && name != "bending_damping" && name.rfind("bending/", 0) != 0) continue;
    if (auto bending = std::dynamic_pointer_cast<BendingTerm>(system.objective().term(name)))
      applyBoundaryRules(*bending, system.mesh(), clamped, {}, choice);
  }
}

}  // namespace jetshell
