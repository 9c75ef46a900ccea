#include "tools/fit/fit_setup.h"

#include "tools/fit/material_mapping.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_edge_rules.h"
#include "tools/scene/scene_evaluator.h"
#include "tools/scene/scene_problem.h"

#include <algorithm>
#include <cmath>

namespace jetshell {
namespace {

/// The nodal forces (at λ = 1) of the scene's load named `name` alone.
Eigen::VectorXd loadForces(const Scene& scene, const std::string& name) {
  Scene only = scene;
  for (LoadCondition& l : only.loads)
    if (l.name != name) l.force.setZero();
  return buildSceneModel(only).appliedForces;
}

}  // namespace

FitSetup::FitSetup(const FitFile& file) : file_(file), model_(buildSceneModel(file.scene)) {
  const ShellProblem problem = shellProblemFromScene(file_.scene, model_);
  const bool dynamic = file_.scene.analysis.type == AnalysisType::Dynamic;
  system_ = std::make_unique<ShellSystem>(problem, dynamic ? AnalysisKind::Dynamics : AnalysisKind::Statics);
  selectSceneEvaluator(file_.scene, *system_);
  addSceneEdgeRules(file_.scene, problem, *system_);  // the same boundary rules as `jetshell run`
  std::vector<std::string> names, labels;
  for (const FitParameterSpec& p : file_.parameters) {
    names.push_back(p.load.empty() ? p.name : namedLoadScale(p.load));
    labels.push_back(p.where + (p.load.empty() ? "/name" : "/load"));
    // A named load's scale: its nodal forces become a part of the load term with a parameter of its own.
    if (!p.load.empty() && system_->nodalForces) system_->nodalForces->addNamedPart(p.load, loadForces(file_.scene, p.load));
  }
  ParameterMapping mapping = materialMapping(file_.material, names, labels, system_->objective());

  std::vector<double> levels;
  for (const ObservationSpec& o : file_.observations) levels.insert(levels.end(), o.levels.begin(), o.levels.end());
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  auto levelIndex = [&](double l) {
    return static_cast<int>(std::lower_bound(levels.begin(), levels.end(), l) - levels.begin());
  };
  auto probeVertex = [&](const std::string& name) {
    for (const ResolvedProbe& p : model_.probes)
      if (p.name == name) return p.vertex;
    throw InputError("fit: probe '" + name + "' not resolved");
  };
  const char* axes = "xyz";
  std::vector<ObservedCoordinate> observed;
  for (std::size_t g = 0; g < file_.observations.size(); ++g) {
    const ObservationSpec& o = file_.observations[g];
    const int group = static_cast<int>(g);
    std::string label = o.where;
    if (o.kind == ObservationSpec::Kind::Shape) {
      label += " shape of " + o.actor;
      const int a = file_.scene.shellIndex(o.actor, o.where + "/actor");
      const ActorBlock& b = model_.actors[static_cast<std::size_t>(a)];
      const double w = o.weight / (3.0 * b.numVertices);
      for (int v = 0; v < b.numVertices; ++v)
        for (int c = 0; c < 3; ++c)
          observed.push_back({levelIndex(o.levels[0]), 3 * (b.firstVertex + v) + c, o.targetPositions(v, c), w, group});
    } else {
      const int vertex = probeVertex(o.probe);
      label += std::string(o.kind == ObservationSpec::Kind::Curve ? " curve of probe " : " probe ") + o.probe + " ";
      for (int c : o.components) label += axes[c];
      for (std::size_t k = 0; k < o.levels.size(); ++k)
        for (int c : o.components) {
          const int dof = 3 * vertex + c;
          observed.push_back({levelIndex(o.levels[k]), dof, model_.world.V(vertex, c) + o.displacements[k][c], o.weight, group});
        }
    }
    labels_.push_back(label);
  }
  if (dynamic) {
    // The dynamic path of `jetshell run`, with Newton run to the scene's residual tolerance in every step (the
    // time-discretization stopping rule, which ends Newton early by design, is off: the trajectory is then a
    // smooth function of the parameters and its sensitivities are exact).
    DynamicsOptions o = dynamicsOptionsFor(file_.scene);
    o.updateTolerance = 0.0;
    std::vector<int> steps;
    for (double t : levels) steps.push_back(static_cast<int>(std::lround(t / o.timeStep)));
    const SceneModel* model = &model_;
    problem_ = std::make_unique<DynamicFitProblem>(*system_, std::move(mapping), o,
                                                   [model](double t) { return model->loadFactorAtTime(t); }, steps,
                                                   std::move(observed));
    return;
  }
  // The statics path of `jetshell run`: increments up to 1 / loadSteps, the first a quarter of that.
  LoadSteppingOptions steps;
  steps.maxIncrement = 1.0 / file_.scene.analysis.loadSteps;
  steps.initialIncrement = 0.25 * steps.maxIncrement;
  steps.newton = newtonOptionsFor(file_.scene.solver, steps.newton.maxIterations, /*statics=*/true);
  // A solid moving along its keyframes bounds the increments, as on `jetshell run`'s path.
  steps = forMovingSolids(*system_, system_->restPositions(), steps);
  problem_ = std::make_unique<StaticFitProblem>(system_->objective(), loadFactorHooks(*system_), system_->restPositions(),
                                                std::move(mapping), levels, std::move(observed), steps);
}

std::vector<FitVariable> FitSetup::variables() const {
  std::vector<FitVariable> v;
  for (const FitParameterSpec& p : file_.parameters) v.push_back(p.variable);
  return v;
}

}  // namespace jetshell
