// A fit file turned into a fit problem: the scene resolved (tools/scene/scene_model.h), its shell system (static
// or dynamic, as the scene's analysis) with the scene's edge rules (tools/scene/scene_edge_rules.h, as
// `jetshell run` builds it), the material mapping of the fitted parameters, and every observation as observed
// coordinates at the distinct load levels (StaticFitProblem) or step times (DynamicFitProblem).
//
//   probe:  one coordinate per listed component, weight w
//   shape:  every coordinate of the actor's vertices, weight w / (3 N_actor) (w weighs the mean squared distance)
//   curve:  one coordinate per CSV row, weight w each
#pragma once

#include "solvers/shell_system.h"
#include "tools/fit/fit_file.h"
#include "tools/fit/dynamic_fit_problem.h"
#include "tools/fit/static_fit_problem.h"
#include "tools/scene/scene_model.h"

#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class FitSetup {
 public:
  /// Throws InputError naming the fit file's field for what can only be checked against the resolved scene.
  explicit FitSetup(const FitFile& file);
  FitSetup(const FitSetup&) = delete;
  FitSetup& operator=(const FitSetup&) = delete;

  const FitFile& file() const { return file_; }
  const SceneModel& model() const { return model_; }
  ShellSystem& system() { return *system_; }
  FitProblem& problem() { return *problem_; }
  std::vector<FitVariable> variables() const;
  /// Per observation (group), the label for reports ("/observations/0 probe tip z").
  const std::vector<std::string>& groupLabels() const { return labels_; }

 private:
  FitFile file_;
  SceneModel model_;
  std::unique_ptr<ShellSystem> system_;
  std::unique_ptr<FitProblem> problem_;
  std::vector<std::string> labels_;
};

}  // namespace jetshell
