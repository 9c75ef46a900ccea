#include "tools/scene/scene_edge_rules.h"

#include "energies/shell/boundary_rules.h"

#include <algorithm>

namespace jetshell {

std::vector<char> clampedVerticesOf(const ShellProblem& problem) {
  std::vector<char> clamped = problem.clampedVertices;
  const std::size_t n = static_cast<std::size_t>(problem.mesh.numVertices());
  for (const ShellActorPart& a : problem.actors) {
    if (a.clampedVertices.empty()) continue;
    if (clamped.empty()) clamped.assign(n, 0);
    for (std::size_t v = 0; v < a.clampedVertices.size(); ++v) {
      const std::size_t stacked = static_cast<std::size_t>(a.firstVertex) + v;
      if (stacked < n) clamped[stacked] = static_cast<char>(clamped[stacked] | a.clampedVertices[v]);
    }
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
  // An actor's own term takes the actor's block of the masks, on its own mesh.
  for (std::size_t k = 0; k < system.bendingTerms.size(); ++k) {
    const ShellSystem::TermBlock& b = system.bendingBlocks[k];
    const int count = b.mesh->numVertices();
    applyBoundaryRules(*system.bendingTerms[k], *b.mesh, vertexBlock(clamped, b.firstVertex, count),
                       vertexBlock(momentLoaded, b.firstVertex, count), choice);
  }
}

}  // namespace jetshell
