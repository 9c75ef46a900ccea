#include "tools/scene/scene_evaluator.h"

namespace jetshell {

void selectSceneEvaluator(const Scene& scene, ShellSystem& system) {
  const bool staged = scene.solver.evaluator == "staged";
  for (const std::shared_ptr<MembraneTerm>& t : system.membraneTerms) t->setStaged(staged);
}

}  // namespace jetshell
