// `jetshell bench contact`: the T-shirt on a plane (examples/tshirt_on_plane.json by default), run for a number
// of 60 Hz steps. Prints steps per second, Newton iterations per step, and where a step's time goes: the
// point-cloud broad phase, the contact terms (their evaluation plus stencil updates and pattern rebuilds), the
// other terms, the linear solves (factorization + solve) and the rest (line-search bookkeeping, the Newton
// loop, the stepping). Wall time: run it on a quiet machine and quote `uptime`'s load beside the figures.
#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"
#include "tools/scene/scene_problem.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <set>
#include <string>

namespace jetshell::cli {
namespace {

struct ContactBenchOptions {
  std::string scene = "examples/tshirt_on_plane.json";
  int steps = 60;
  int threads = 0;
  std::string json;
};

int runContactBench(const ContactBenchOptions& o) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  const Scene scene = loadSceneFile(o.scene);
  if (scene.analysis.type != AnalysisType::Dynamic) throw InputError(o.scene + ": bench contact needs a dynamic scene");
  const SceneModel model = buildSceneModel(scene);
  ShellSystem system(shellProblemFromScene(scene, model), AnalysisKind::Dynamics);
  DynamicsOptions d;
  d.timeStep = scene.analysis.timeStep;
  d.newton.maxIterations = scene.solver.maxIterations.value_or(d.newton.maxIterations);
  if (scene.solver.residualTolerance) d.newton.residualTolerance = *scene.solver.residualTolerance;
  d.acceptIterationCap = scene.solver.acceptIterationCap;
  DynamicsSolver solver(system, d);
  Objective& objective = system.objective();
  std::printf("jetshell bench contact: %s, %d vertices, %d faces, %d steps of %.4f s, %d threads\n", o.scene.c_str(),
              model.numVertices(), model.world.numFaces(), o.steps, d.timeStep, omp_get_max_threads());
  const auto start = std::chrono::steady_clock::now();
  int iterations = 0, failed = 0;
  double linear = 0.0;
  for (int s = 0; s < o.steps; ++s) {
    const StepReport r = solver.step();
    iterations += r.newtonIterations;
    linear += r.factorizationSeconds + r.solveSeconds;
    if (!r.success) {
      ++failed;
      std::printf("step %d failed: %s\n", s + 1, r.message.c_str());
      break;
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int steps = solver.stepCount();
  const std::vector<std::string> names = objective.activeTermNames();
  const std::vector<std::string> contactNames = system.contact.termNames();
  const std::set<std::string> contact(contactNames.begin(), contactNames.end());
  double contactTerms = objective.stencilSeconds(), otherTerms = 0.0;
  for (std::size_t i = 0; i < names.size(); ++i)
    (contact.count(names[i]) ? contactTerms : otherTerms) += objective.termSeconds()[i];
  const double broad = system.contact.broadPhaseSeconds();
  const double rest = wall - contactTerms - otherTerms - linear;
  auto pct = [&](double t) { return 100.0 * t / wall; };
  std::printf("%d steps in %.2f s: %.2f steps/s, %.2f Newton iterations/step, %d pattern rebuilds\n", steps, wall,
              steps / wall, steps ? static_cast<double>(iterations) / steps : 0.0, objective.patternRebuilds());
  std::printf("time split: broad phase %.1f%% (within contact), contact terms %.1f%%, other terms %.1f%%, "
              "linear solve %.1f%%, rest %.1f%%\n",
              pct(broad), pct(contactTerms), pct(otherTerms), pct(linear), pct(rest));
  std::printf("contact detection + assembly: %.1f%% of a step (target <= 30%%)\n", pct(contactTerms));
  nlohmann::json out = {{"scene", o.scene},
                        {"vertices", model.numVertices()},
                        {"steps", steps},
                        {"threads", omp_get_max_threads()},
                        {"wall_seconds", wall},
                        {"steps_per_second", steps / wall},
                        {"newton_iterations_per_step", steps ? static_cast<double>(iterations) / steps : 0.0},
                        {"pattern_rebuilds", objective.patternRebuilds()},
                        {"seconds", {{"broad_phase", broad},
                                     {"contact_terms", contactTerms},
                                     {"other_terms", otherTerms},
                                     {"linear_solve", linear},
                                     {"rest", rest}}}};
  if (!o.json.empty()) {
    std::ofstream(o.json) << out.dump(2) << "\n";
    std::printf("wrote %s\n", o.json.c_str());
  }
  return failed ? kFailed : kOk;
}

const RegisterSubcommand reg("bench contact", [](CLI::App& app, int& exitCode) {
  CLI::App* bench = benchCommand(app);
  auto opts = std::make_shared<ContactBenchOptions>();
  CLI::App* cmd = bench->add_subcommand("contact", "steps/s and time split of a contact scene (the T-shirt)");
  cmd->add_option("--scene", opts->scene, "A dynamic scene file (default: examples/tshirt_on_plane.json)");
  cmd->add_option("--steps", opts->steps, "Time steps")->check(CLI::Range(1, 100000));
  cmd->add_option("--threads", opts->threads, "OpenMP threads (default: OpenMP's)")->check(CLI::Range(1, 256));
  cmd->add_option("--json", opts->json, "Write the figures as JSON");
  cmd->callback([opts, &exitCode]() { exitCode = runContactBench(*opts); });
});

}  // namespace
}  // namespace jetshell::cli
