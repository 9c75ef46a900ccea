// `jetshell bench contact`: the T-shirt on a plane (examples/tshirt_on_plane.json by default), run for a number
// of 60 Hz steps. Prints steps per second, Newton iterations per step, and where a step's time goes: the
// point-cloud broad phase, the contact terms (their evaluation plus stencil updates and pattern rebuilds), the
// other terms, the linear solves (factorization + solve) and the rest (line-search bookkeeping, the Newton
// loop, the stepping), the symbolic analyses against the numeric factorizations, and how the steps' solves ended
// (Newton's residual test, the time-step rule's residual estimate or Newton correction, or moved on at the
// iteration cap: solvers/dynamics.h). `--pattern both` runs the scene
// twice, with the Hessian pattern rebuilt exactly to the contacts and then grow-only, and prints their ratio.
// `--solver both` runs it with the scene's time-step linear algebra (solvers/time_step_policy.h: CG preconditioned
// by the one-ring factor, element Hessians projected only where needed) and then with the direct solver
// (CHOLMOD on the whole Hessian, every element block projected), and prints their ratio.
// It ends with the guards of the T-shirt's checks over the run: the deepest sample inside a volume collider, the
// closest interacting point-cloud pair (in units of their contact distance 2r), the final kinetic energy, the
// largest gain of potential + kinetic energy over the start;
// `--trace` prints them, the Newton and CG iterations and how the solve ended for every step, and then each
// Newton iteration of the step: the residual it started from, its accepted step length α, its CG iterations and
// the largest vertex move of its step (how far Newton still moved some vertex when the step ended).
// `--reference-iterations N` first runs the scene with up to N Newton iterations a step (untimed as a reference,
// though its own figures are printed), keeps its positions every few steps, and gives each timed run's distance
// from them: the error a run's iteration budget costs, beside its steps per second.
// Wall time: run it on a quiet machine and quote `uptime`'s load beside the figures.
#include "solvers/dynamics.h"
#include "solvers/fill_ordering.h"
#include "solvers/shell_system.h"
#include "tools/bench_cloth.h"
#include "tools/bench_newton_error.h"
#include "tools/bench_trajectory.h"
#include "tools/output/atomic_file.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_edge_rules.h"
#include "tools/scene/scene_evaluator.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"
#include "tools/scene/scene_problem.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace jetshell::cli {
namespace {

struct ContactBenchOptions {
  std::string scene = "examples/tshirt_on_plane.json";
  int steps = 60;
  int threads = 0;
  std::string pattern = "exact";  // grow | exact | both
  std::string solver = "scene";   // scene | direct | both
  bool noOverlap = false;         // NewtonOptions::overlapPreconditioner off
  bool trace = false;             // one line per step
  bool newtonError = false;       // check every step an iterate test passed (tools/bench_newton_error.h)
  std::string fallbackBending = "exact";  // NewtonOptions::fallbackBendingHessian
  std::string ordering = "auto";          // LinearSolverOptions::ordering
  std::string oneRingParts = "auto";      // LinearSolverOptions::oneRingParts
  int referenceIterations = 0;            // > 0: a reference run with up to this many Newton iterations a step
  std::string evaluator = "scene";        // scene | perFace | staged (the membrane's)
  bool termSplit = false;                 // each term's time by request kind
  std::string json;
};

struct Variant {
  bool growOnly = false;  // the Hessian pattern grow-only, or exact (rebuilt to the current contacts)
  bool direct = false;    // CHOLMOD on the whole Hessian with every block projected, or the scene's solver
  int maxIterations = 0;  // > 0: Newton iterations a step instead of the scene's (the reference run)
};

/// The positions of a reference run at every `stride`-th step and at the last (1-based step numbers), and where it
/// started; the timed runs are compared with it at those steps.
struct ReferenceRun {
  int stride = 1;
  Eigen::VectorXd start;
  std::vector<int> steps;
  std::vector<Eigen::VectorXd> positions;
};

/// Every how many steps a reference run keeps its positions: about a hundred snapshots, and at most 5e7 doubles
/// in all (400 MB), whatever the scene's size.
int trajectoryStride(int steps, Eigen::Index dofs) {
  const double cap = 5e7;
  const double byMemory = std::ceil(static_cast<double>(steps) * static_cast<double>(dofs) / cap);
  return std::max({1, steps / 100, static_cast<int>(byMemory)});
}

/// Whether step `step` (1-based) of a run of `steps` is one a reference keeps.
bool keptStep(int step, int steps, int stride) { return step % stride == 0 || step == steps; }

/// The scene's system with its evaluator and boundary-edge rules, as `jetshell run` applies them, and the Hessian
/// pattern of the variant.
/// `evaluator` (--evaluator) other than "scene" replaces the scene's membrane evaluator: perFace or staged (the
/// membrane on its stage graph; the bending term is always on its own).
std::unique_ptr<ShellSystem> sceneSystem(const Scene& scene, const ShellProblem& problem, bool growOnly,
                                         const std::string& evaluator) {
  auto system = std::make_unique<ShellSystem>(problem, AnalysisKind::Dynamics);
  selectSceneEvaluator(scene, *system);
  if (evaluator != "scene") {
    for (const std::shared_ptr<MembraneTerm>& t : system->membraneTerms) t->setStaged(evaluator == "staged");
  }
  addSceneEdgeRules(scene, problem, *system);
  system->objective().setGrowOnlyPattern(growOnly);
  return system;
}

/// One run of the scene in one variant.
/// `record`: keep the run's positions as a reference trajectory; `reference`: compare the run with one (both
/// untimed).
nlohmann::json runOnce(const Scene& scene, const SceneModel& model, const ContactBenchOptions& o, Variant v,
                       bool& failedRun, ReferenceRun* record = nullptr, const ReferenceRun* reference = nullptr) {
  const bool growOnly = v.growOnly;
  const ShellProblem problem = shellProblemFromScene(scene, model);
  const std::unique_ptr<ShellSystem> runSystem = sceneSystem(scene, problem, growOnly, o.evaluator);
  ShellSystem& system = *runSystem;
  Objective& objective = system.objective();
  // The scene's integrator, time step and Newton settings, as `jetshell run` takes them.
  DynamicsOptions d = dynamicsOptionsFor(scene);
  if (v.direct) {
    d.newton.linear.type = LinearSolverType::Cholmod;
    d.newton.adaptiveLinearTolerance = false;
    d.newton.exactHessianFirst = false;
  }
  if (v.maxIterations > 0) d.newton.maxIterations = v.maxIterations;
  if (o.noOverlap) d.newton.overlapPreconditioner = false;
  d.newton.fallbackBendingHessian = hessianModelFromString(o.fallbackBending);
  d.newton.linear.ordering = fillOrderingFromString(o.ordering);
  d.newton.linear.oneRingParts = oneRingPartsFromString(o.oneRingParts);
  DynamicsSolver solver(system, d);
  if (v.maxIterations > 0)
    std::printf("-- reference: up to %d Newton iterations a step (the timed runs are compared with it) --\n",
                v.maxIterations);
  else
    std::printf("-- %s pattern, %s --\n", growOnly ? "grow-only" : "exact",
                v.direct ? "direct solver (CHOLMOD, every block projected)" : "the scene's solver");
  if (record != nullptr) {
    record->stride = trajectoryStride(o.steps, solver.positions().size());
    record->start = solver.positions();
  }
  // Against the reference, at its kept steps: the RMS and largest vertex distance at the last step compared, and
  // the largest RMS over the run.
  double lastRms = 0.0, lastLargest = 0.0, worstRms = 0.0, referenceMoved = 0.0;
  int lastCompared = 0, worstStep = 0;
  std::size_t nextReference = 0;
  // --newton-error: a second solver on its own system takes each step again from the same state, tightly, on from
  // the run's accepted iterate (checkStepError). The run is the plain run, but its time is not the benchmark's:
  // the whole steps' checks are timed apart from it, the parts' checks run inside their step (the substep observer).
  std::unique_ptr<NewtonErrorWatch> watch;
  if (o.newtonError && v.maxIterations == 0) {
    watch = std::make_unique<NewtonErrorWatch>(solver, sceneSystem(scene, problem, growOnly, o.evaluator));
    std::printf("--newton-error: the parts' checks run inside their steps; the time is not the benchmark's\n");
  }
  const auto start = std::chrono::steady_clock::now();
  const double cpuStart = processCpuSeconds();
  int iterations = 0, failed = 0, analyses = 0, factorizations = 0, exactSteps = 0, fallbacks = 0, cg = 0;
  int directFallbacks = 0;  // CG solves finished with the whole Hessian's factor (LinearSolverOptions::cgDirectAfter)
  // How the steps' solves ended: Newton's residual test, the time-step rule's residual estimate or its Newton
  // correction (solvers/dynamics.h), or moved on at the iteration cap.
  int endedResidual = 0, endedEstimate = 0, endedCorrection = 0, endedAtCap = 0;
  int stayRestarts = 0;  // steps solved again from x_n, the first solve having ended above it (guardedEnd)
  int guardSolves = 0;   // solves on from the iteration cap, a contact guard broken there (contactGuardSolves)
  double factorSeconds = 0.0;
  double linear = 0.0;
  // The guards of the T-shirt's checks: the deepest sample in a volume collider (signed distance, m) and the
  // closest interacting point-cloud pair (distance / 2r), over every step and at the last one. Their time (a
  // broad phase of its own) is left out of the figures.
  double guardWall = 0.0, guardCpu = 0.0;
  double deepest = 0.0, closest = 1.0, lastDeepest = 0.0, lastClosest = 1.0;
  // And no energy made: the largest gain of potential + kinetic energy over the start after any step (a
  // dissipative run has none; a step that moves on at the iteration cap far from its solution shows here).
  const double startEnergy = solver.potentialEnergy() + solver.kineticEnergy();
  double mostGained = -std::numeric_limits<double>::infinity();
  auto guards = [&](const Eigen::VectorXd& x) {
    mostGained = std::max(mostGained, solver.potentialEnergy() + solver.kineticEnergy() - startEnergy);
    lastDeepest = 0.0;
    for (const VolumeContactTerms& vc : system.contact.volume)
      lastDeepest = std::min(lastDeepest, vc.state->minDistance(x));
    lastClosest = system.contact.pointCloud.state ? system.contact.pointCloud.state->minDistanceRatio(x) : 1.0;
    deepest = std::min(deepest, lastDeepest);
    closest = std::min(closest, lastClosest);
  };
  for (int s = 0; s < o.steps; ++s) {
    const StepReport r = solver.step();
    const auto guardStart = std::chrono::steady_clock::now();
    const double guardCpuStart = processCpuSeconds();
    guards(solver.positions());
    if (watch) watch->afterStep(r);
    if (record != nullptr && keptStep(s + 1, o.steps, record->stride)) {
      record->steps.push_back(s + 1);
      record->positions.push_back(solver.positions());
    }
    if (reference != nullptr && nextReference < reference->steps.size() && reference->steps[nextReference] == s + 1) {
      const VertexDistance gap = vertexDistance(solver.positions(), reference->positions[nextReference]);
      lastRms = gap.rms;
      lastLargest = gap.largest;
      lastCompared = s + 1;
      if (gap.rms >= worstRms) {
        worstRms = gap.rms;
        worstStep = s + 1;
      }
      ++nextReference;
    }
    guardWall += std::chrono::duration<double>(std::chrono::steady_clock::now() - guardStart).count();
    guardCpu += processCpuSeconds() - guardCpuStart;
    if (o.trace) {
      int stepCg = 0;
      for (const SolverSummary& solve : r.solves)
        for (const IterationRecord& it : solve.trace) stepCg += it.cgIterations;
      std::printf("step %d: %d Newton iterations, %d CG, deepest %.2f mm, closest %.3f x 2r: %s\n", s + 1,
                  r.newtonIterations, stepCg, 1e3 * lastDeepest, lastClosest,
                  r.solves.empty() ? "" : r.solves.back().message.c_str());
      for (const SolverSummary& solve : r.solves)
        for (const IterationRecord& it : solve.trace)
          std::printf("  iteration %d: residual %.3g N, alpha %.3g, %d CG (%s), largest move %.3f mm\n",
                      it.iteration + 1, it.residual, it.stepLength, it.cgIterations,
                      it.exactHessian ? "exact Hessian"
                                      : (it.projectionFallback ? "exact Hessian indefinite, then projected" : "projected"),
                      1e3 * it.largestMove);
    }
    iterations += r.newtonIterations;
    linear += r.factorizationSeconds + r.solveSeconds;
    factorSeconds += r.factorizationSeconds;
    for (const SolverSummary& solve : r.solves) {
      analyses += solve.symbolicAnalyses;
      factorizations += solve.numericFactorizations;
      exactSteps += solve.exactHessianSteps;
      fallbacks += solve.projectionFallbacks;
      directFallbacks += solve.directFallbacks;
      for (const IterationRecord& it : solve.trace) cg += it.cgIterations;
      if (!solve.converged() || solve.discarded) continue;
      if (solve.convergenceTest != "iterate")
        ++endedResidual;
      else if (solve.iterateEstimate == "Newton correction")
        ++endedCorrection;
      else
        ++endedEstimate;
    }
    endedAtCap += r.movedOn;
    stayRestarts += r.stayRestarts;
    guardSolves += r.guardSolves;
    if (!r.success) {
      ++failed;
      std::printf("step %d failed: %s\n", s + 1, r.message.c_str());
      break;
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - guardWall;
  const double cpu = processCpuSeconds() - cpuStart - guardCpu;
  const int steps = solver.stepCount();
  const std::vector<std::string> names = objective.activeTermNames();
  const std::vector<std::string> contactNames = system.contact.termNames();
  const std::set<std::string> contact(contactNames.begin(), contactNames.end());
  double contactTerms = objective.stencilSeconds(), otherTerms = 0.0;
  for (std::size_t i = 0; i < names.size(); ++i)
    (contact.count(names[i]) ? contactTerms : otherTerms) += objective.termSeconds()[i];
  const double broad = system.contact.broadPhaseSeconds();
  const double pattern = objective.patternSeconds();
  const double rest = wall - contactTerms - otherTerms - linear;
  auto pct = [&](double t) { return 100.0 * t / wall; };
  const double perStep = steps ? static_cast<double>(iterations) / steps : 0.0;
  std::printf("%d steps in %.2f s wall (%.2f s CPU): %.3f steps/s, %.2f Newton iterations/step\n", steps, wall, cpu,
              steps / wall, perStep);
  std::printf("pattern: %d re-declarations, %d new patterns; linear solver: %d symbolic analyses, %d numeric "
              "factorizations\n",
              objective.patternRebuilds(), objective.patternGrowths(), analyses, factorizations);
  std::printf("linear solve: %.2f s factorization (or preconditioner), %.2f s solves, %d CG iterations\n",
              factorSeconds, linear - factorSeconds, cg);
  const FactorStatistics fs = solver.newton().linearSolver().factorStatistics();
  std::printf("factor: nnz(L) %.0f, %.3f GFlop per factorization, ordering %s, %d factor%s\n", fs.nnzL,
              1e-9 * fs.flops, fs.ordering.c_str(), fs.factors, fs.factors == 1 ? "" : "s (one per part)");
  std::printf("Hessian: %d Newton steps on the unprojected Hessian, %d fallbacks to the projected one; %d CG solves "
              "finished with the whole Hessian's factor\n",
              exactSteps, fallbacks, directFallbacks);
  std::printf("solves ended: %d by Newton's residual test, %d by the residual estimate, %d by the Newton correction, "
              "%d moved on at the iteration cap; %d solved again from x_n (the first solve ended above it, or "
              "crushed); %d solved on from the cap, a contact guard broken there\n",
              endedResidual, endedEstimate, endedCorrection, endedAtCap, stayRestarts, guardSolves);
  std::printf("time split: broad phase %.1f%% and pattern rebuilds %.1f%% (both within contact), contact terms "
              "%.1f%%, other terms %.1f%%, linear solve %.1f%%, rest %.1f%%\n",
              pct(broad), pct(pattern), pct(contactTerms), pct(otherTerms), pct(linear), pct(rest));
  std::printf("contact detection + assembly: %.1f%% of a step (target <= 30%%)\n", pct(contactTerms));
  std::printf("guards: deepest sample in a volume %.2f mm (last step %.2f mm), closest pair %.3f x 2r (last step "
              "%.3f x 2r), kinetic energy at the end %.3g J, largest energy gain over the start %.3g J\n",
              1e3 * deepest, 1e3 * lastDeepest, closest, lastClosest, solver.kineticEnergy(), mostGained);
  if (watch) watch->tally().print("");
  // How far the reference itself moved by the last step compared (nextReference is one past it): the scale of
  // the distances.
  if (reference != nullptr && lastCompared > 0) {
    referenceMoved = vertexDistance(reference->positions[nextReference - 1], reference->start).rms;
    std::printf("against the reference: at step %d the positions are %.2f mm RMS and at most %.1f mm from it (it "
                "moved %.1f mm RMS from the start); the largest RMS over the steps compared %.2f mm, at step %d\n",
                lastCompared, 1e3 * lastRms, 1e3 * lastLargest, 1e3 * referenceMoved, 1e3 * worstRms, worstStep);
  }
  failedRun = failed > 0;
  nlohmann::json figures = {{"pattern", growOnly ? "grow" : "exact"},
          {"solver", v.direct ? "direct" : "scene"},
          {"linear_solver", toString(d.newton.linear.type)},
          {"ordering", fs.ordering},
          {"one_ring_parts", o.oneRingParts},
          {"factors", fs.factors},
          {"steps", steps},
          {"wall_seconds", wall},
          {"cpu_seconds", cpu},
          {"steps_per_second", steps / wall},
          {"steps_per_cpu_second", cpu > 0.0 ? steps / cpu : 0.0},
          {"newton_iterations_per_step", perStep},
          {"pattern_rebuilds", objective.patternRebuilds()},
          {"pattern_growths", objective.patternGrowths()},
          {"symbolic_analyses", analyses},
          {"numeric_factorizations", factorizations},
          {"unprojected_hessian_steps", exactSteps},
          {"cg_iterations", cg},
          {"factorization_seconds", factorSeconds},
          {"projection_fallbacks", fallbacks},
          {"direct_factor_fallbacks", directFallbacks},
          {"solves_ended", {{"residual", endedResidual},
                            {"residual_estimate", endedEstimate},
                            {"newton_correction", endedCorrection},
                            {"moved_on_at_cap", endedAtCap}}},
          {"solved_again_from_previous_positions", stayRestarts},
          {"solved_on_for_contact_guards", guardSolves},
          {"deepest_in_volume_m", deepest},
          {"closest_pair_ratio", closest},
          {"final_kinetic_energy", solver.kineticEnergy()},
          {"largest_energy_gain", mostGained},
          {"seconds", {{"broad_phase", broad},
                       {"pattern_rebuilds", pattern},
                       {"contact_terms", contactTerms},
                       {"other_terms", otherTerms},
                       {"linear_solve", linear},
                       {"rest", rest}}}};
  if (o.termSplit) {
    // Each term's calls and milliseconds per call by request kind: where an evaluator's cost in a step lies.
    static const char* const kinds[Objective::kRequestKinds] = {"value", "gradient", "hessian", "projected_hessian"};
    nlohmann::json split = nlohmann::json::object();
    std::printf("term split (calls, ms per call): value | + gradient | + Hessian | + Hessian projected\n");
    for (std::size_t i = 0; i < names.size(); ++i) {
      const Objective::TermRequests& r = objective.termRequests()[i];
      std::printf("  %-32s", names[i].c_str());
      nlohmann::json term = nlohmann::json::object();
      for (int k = 0; k < Objective::kRequestKinds; ++k) {
        const auto kk = static_cast<std::size_t>(k);
        const double perCall = r.calls[kk] > 0 ? 1e3 * r.seconds[kk] / static_cast<double>(r.calls[kk]) : 0.0;
        std::printf("%s %5ld %8.3f", k == 0 ? "" : " |", r.calls[kk], perCall);
        term[kinds[k]] = {{"calls", r.calls[kk]}, {"seconds", r.seconds[kk]}};
      }
      std::printf("\n");
      split[names[i]] = term;
    }
    figures["term_split"] = split;
  }
  if (watch) figures["newton_error"] = watch->tally().toJson();
  if (v.maxIterations > 0) figures["max_iterations"] = v.maxIterations;
  if (reference != nullptr && lastCompared > 0)
    figures["against_reference"] = {{"step", lastCompared},
                                    {"rms_m", lastRms},
                                    {"largest_m", lastLargest},
                                    {"reference_moved_rms_m", referenceMoved},
                                    {"largest_rms_m", worstRms},
                                    {"largest_rms_step", worstStep}};
  return figures;
}

int runContactBench(const ContactBenchOptions& o) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  const Scene scene = loadSceneFile(o.scene);
  if (scene.analysis.type != AnalysisType::Dynamic) throw InputError(o.scene + ": bench contact needs a dynamic scene");
  const SceneModel model = buildSceneModel(scene);
  const char* integrator = toString(dynamicsOptionsFor(scene).integrator);
  std::printf("jetshell bench contact: %s, %d vertices, %d faces, %d steps of %.4f s (%s), %d threads\n",
              o.scene.c_str(), model.numVertices(), model.world.numFaces(), o.steps, scene.analysis.timeStep, integrator,
              omp_get_max_threads());
  if (o.pattern == "both" && o.solver == "both") throw InputError("bench contact: --pattern both and --solver both together");
  std::vector<Variant> variants;
  for (bool growOnly : {false, true}) {
    if (o.pattern != (growOnly ? "exact" : "grow")) {
      for (bool direct : {false, true})
        if (o.solver != (direct ? "scene" : "direct")) variants.push_back({growOnly, direct});
    }
  }
  nlohmann::json runs = nlohmann::json::array();
  bool failed = false;
  std::unique_ptr<ReferenceRun> reference;
  nlohmann::json referenceRun;
  if (o.referenceIterations > 0) {
    reference = std::make_unique<ReferenceRun>();
    Variant r;
    r.maxIterations = o.referenceIterations;
    referenceRun = runOnce(scene, model, o, r, failed, reference.get());
  }
  for (const Variant& v : variants) {
    bool f = false;
    runs.push_back(runOnce(scene, model, o, v, f, nullptr, reference.get()));
    failed = failed || f;
  }
  nlohmann::json out = runs.back();
  if (reference) out["reference_run"] = referenceRun;
  out["scene"] = o.scene;
  out["vertices"] = model.numVertices();
  out["threads"] = omp_get_max_threads();
  out["integrator"] = integrator;
  if (runs.size() == 2) {
    const double wallRatio = runs[0]["wall_seconds"].get<double>() / runs[1]["wall_seconds"].get<double>();
    const double cpuRatio = runs[0]["cpu_seconds"].get<double>() / runs[1]["cpu_seconds"].get<double>();
    const bool patterns = o.pattern == "both";
    std::printf("%s: %.2fx the steps/s (wall), %.2fx (CPU)\n",
                patterns ? "grow-only against exact pattern" : "the scene's solver against the direct solver",
                patterns ? wallRatio : 1.0 / wallRatio, patterns ? cpuRatio : 1.0 / cpuRatio);
    out["runs"] = runs;
    if (patterns) out["speedup_grow_over_exact"] = {{"wall", wallRatio}, {"cpu", cpuRatio}};
    else out["speedup_scene_over_direct"] = {{"wall", 1.0 / wallRatio}, {"cpu", 1.0 / cpuRatio}};
  }
  if (!o.json.empty()) {
    writeFileAtomically(o.json, out.dump(2) + "\n");
    std::printf("wrote %s\n", o.json.c_str());
  }
  return failed ? kFailed : kOk;
}

const RegisterSubcommand registerBenchContact("bench contact", [](CLI::App& app, int& exitCode) {
  CLI::App* bench = benchCommand(app);
  auto opts = std::make_shared<ContactBenchOptions>();
  CLI::App* cmd = bench->add_subcommand("contact", "steps/s and time split of a contact scene (the T-shirt)");
  cmd->add_option("--scene", opts->scene, "A dynamic scene file (default: examples/tshirt_on_plane.json)");
  cmd->add_option("--steps", opts->steps, "Time steps")->check(CLI::Range(1, 100000));
  cmd->add_option("--threads", opts->threads, "OpenMP threads (default: OpenMP's)")->check(CLI::Range(1, 256));
  cmd->add_option("--pattern", opts->pattern,
                  "Hessian pattern: exact (rebuilt to the current contacts, the default), grow (grow-only), or both "
                  "(exact, then grow, and their ratio)")
      ->check(CLI::IsMember({"grow", "exact", "both"}));
  cmd->add_option("--solver", opts->solver,
                  "Linear algebra: scene (the scene's time-step solver, the default), direct (CHOLMOD, every block "
                  "projected), or both (scene, then direct, and their ratio)")
      ->check(CLI::IsMember({"scene", "direct", "both"}));
  cmd->add_flag("--no-overlap", opts->noOverlap,
                "Factor the one-ring preconditioner after the whole assembly, never during the bending assembly");
  cmd->add_option("--fallback-bending", opts->fallbackBending,
                  "The bending Hessian of the projected assembly an indefinite Newton try falls back to: gaussNewton "
                  "(positive semi-definite, not projected) or exact (projected block by block, the default)")
      ->check(CLI::IsMember({"gaussNewton", "exact"}));
  cmd->add_option("--ordering", opts->ordering,
                  "Fill-reducing ordering of the Cholesky factors (the one-ring preconditioner's or the direct "
                  "solver's): auto (CHOLMOD's default), amd, metis or nesdis")
      ->check(CLI::IsMember({"auto", "amd", "metis", "nesdis"}));
  cmd->add_option("--one-ring-parts", opts->oneRingParts,
                  "The one-ring preconditioner as 1 factor, 2 (the mesh bisected, one factor per core), or auto "
                  "(2 with contact, else 1: the default)")
      ->check(CLI::IsMember({"auto", "1", "2"}));
  cmd->add_flag("--trace", opts->trace,
                "Per step: Newton and CG iterations, the guards, how it ended; then per Newton iteration: residual, "
                "step length, CG iterations, largest vertex move");
  cmd->add_flag("--newton-error", opts->newtonError,
                "Solve every step (or part of a step) an iterate test passed again from the same state, on from its "
                "iterate, to eta 1e-6, and report the error left against the test's threshold");
  cmd->add_option("--reference-iterations", opts->referenceIterations,
                  "First run the scene with up to N Newton iterations a step, and give each timed run's distance from "
                  "its positions (every few steps and at the last)")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--evaluator", opts->evaluator,
                  "The membrane's evaluator: the scene's (default), perFace (one composed stage per face) or staged (its "
                  "stage graph); the bending term has one, its stage graph")
      ->check(CLI::IsMember({"scene", "perFace", "staged"}));
  cmd->add_flag("--term-split", opts->termSplit,
                "Each term's calls and time per call by request: value, with gradient, with Hessian, projected");
  cmd->add_option("--json", opts->json, "Write the figures as JSON")->check(outputFile());
  cmd->callback([opts, &exitCode]() { exitCode = runContactBench(*opts); });
});

}  // namespace
}  // namespace jetshell::cli
