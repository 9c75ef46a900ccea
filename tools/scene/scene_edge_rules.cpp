#include "tools/scene/scene_edge_rules.h"

#include "validation/boundary_rule_term.h"

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
  const std::vector<char> clamped = clampedVerticesOf(problem);
  const EdgeRule clamp = edgeRuleFromString(scene.edgeRules.clamp);
  if (!clamped.empty()) system.bending->setEdgeRule(clamped, clamp);
  validation::BoundaryRules rules;
  rules.clampRule = rules.builtInClampRule = validation::toBoundaryRule(clamp);
  rules.freeRule = validation::parseBoundaryRule(scene.edgeRules.free);
  for (const EdgeRuleSettings::SymmetryPlane& p : scene.edgeRules.symmetryPlanes)
    rules.symmetryPlanes.push_back({p.point, p.normal});
  rules.planeTolerance = 1e-6;
  const ShellMaterialParams& m = system.material();
  if (auto term = validation::makeBoundaryRuleTerm(system.mesh(), system.topology(), system.reference(), m.bendingAlpha,
                                                   m.bendingBeta, clamped, rules))
    system.objective().addTerm(term);
}

}  // namespace jetshell
