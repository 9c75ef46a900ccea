#include "tools/scene/run_scene.h"

#include "tools/scene/run_plots.h"

#include "core/format.h"
#include "core/input_limits.h"
#include "solvers/dynamic_relaxation.h"
#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "solvers/statics.h"
#include "solvers/time_step_policy.h"
#include "tools/output/checkpoint.h"
#include "tools/output/earlier_run_files.h"
#include "tools/output/interrupt.h"
#include "tools/output/progress.h"
#include "tools/output/run_checkpoint.h"
#include "tools/render/plot.h"
#include "tools/render/render_frames.h"
#include "tools/scene/run_plots.h"
#include "tools/scene/safeguard_report.h"
#include "tools/scene/scene_model.h"
#include "tools/scene/scene_edge_rules.h"
#include "tools/scene/scene_evaluator.h"
#include "tools/scene/scene_path_control.h"
#include "tools/scene/scene_problem.h"
#include "tools/scene/support_check.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <ostream>
#include <sstream>

namespace jetshell {
namespace {

/// The convergence claim of a solve, so that anyone can check it: the final residual, the tolerance it was held
/// to and the force scale behind that tolerance (Objective::forceScale).
void recordResidualClaim(nlohmann::json& extra, double residual, double tolerance, double forceScale,
                         const std::string& source) {
  extra["final_residual"] = residual;
  extra["residual_tolerance"] = tolerance;
  extra["force_scale"] = forceScale;
  extra["force_scale_source"] = source;
}

void recordResidualClaim(nlohmann::json& extra, const SolverSummary& s) {
  recordResidualClaim(extra, s.finalResidual, s.residualThreshold, s.forceScale, s.forceScaleSource);
  if (s.roundOffFloor > 0.0) extra["round_off_floor"] = s.roundOffFloor;
  if (!s.convergenceTest.empty()) extra["convergence_test"] = s.convergenceTest;
}

/// The up axis for pictures: against gravity, else +z.
Eigen::Vector3d upAxis(const Scene& scene) {
  return scene.gravity.norm() > 0 ? Eigen::Vector3d(-scene.gravity.normalized()) : Eigen::Vector3d::UnitZ();
}

}  // namespace

NewtonOptions newtonOptionsFor(const SolverSettings& s, int defaultIterations, bool statics) {
  NewtonOptions n;
  n.maxIterations = s.maxIterations.value_or(defaultIterations);
  if (s.residualTolerance) n.residualTolerance = *s.residualTolerance;
  if (s.decrementTolerance) n.decrementTolerance = *s.decrementTolerance;
  if (s.lineSearch != "default") n.lineSearch = lineSearchTypeFromString(s.lineSearch);
  n.linear.type = linearSolverTypeFromString(s.linearSolver);
  n.linear.preconditioner = preconditionerFromString(s.preconditioner);
  n.projection = s.psdProjection == "auto" ? (statics ? PsdProjection::None : PsdProjection::Clamp)
                                            : psdProjectionFromString(s.psdProjection);
  n.derivatives = s.derivatives == "autodiff" ? DerivativePath::AutoDiff : DerivativePath::Analytic;
  n.bendingHessian = hessianModelFromString(s.bendingHessian);
  n.fallbackBendingHessian = hessianModelFromString(s.fallbackBendingHessian);
  n.frictionHessian = s.frictionHessian == "majorizer" ? FrictionHessian::Majorizer : FrictionHessian::Exact;
  if (!statics) {
    // Time steps (dynamics and dynamic relaxation): the linear algebra of solvers/time_step_policy.h; an explicit
    // psdProjection is applied at every iteration as asked.
    applyTimeStepLinearAlgebra(n);
    if (s.psdProjection != "auto") n.exactHessianFirst = false;
  }
  return n;
}

DynamicsOptions dynamicsOptionsFor(const Scene& scene) {
  DynamicsOptions o;
  o.integrator = scene.analysis.integrator == Integrator::BDF2 ? TimeIntegrator::BDF2 : TimeIntegrator::BackwardEuler;
  o.timeStep = scene.analysis.timeStep;
  o.newton = newtonOptionsFor(scene.solver, o.newton.maxIterations);
  o.acceptIterationCap = scene.solver.acceptIterationCap;
  o.duration = scene.analysis.duration;
  return o;
}

RunResult runScene(const Scene& scene, const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const SceneModel model = buildSceneModel(scene);
  checkRigidModes(scene, model);
  if (scene.solver.threads > 0) omp_set_num_threads(scene.solver.threads);
  RunResult result;
  result.notes = unsupportedFeatures(scene);
  result.warnings = model.warnings;

  std::ostringstream discard;
  std::ostream& logStream = options.log ? *options.log : discard;
  Progress progress(logStream, options.progressBar && options.log);
  for (const std::string& note : result.notes) progress.log("note: " + note);
  for (const std::string& w : result.warnings) progress.log("warning: " + w);

  const AnalysisType type = scene.analysis.type;
  const AnalysisKind kind = type == AnalysisType::Static    ? AnalysisKind::Statics
                            : type == AnalysisType::Dynamic ? AnalysisKind::Dynamics
                                                            : AnalysisKind::DynamicRelaxation;
  // The load factor of a row at time t: a static path's time is its load factor, a dynamic run's loads follow its
  // ramp (loadRampTime), dynamic relaxation applies the whole loads.
  const auto rowLoadFactor = [&](double t) {
    return type == AnalysisType::Static ? t : type == AnalysisType::Dynamic ? model.loadFactorAtTime(t) : 1.0;
  };
  const ShellProblem problem = shellProblemFromScene(scene, model);
  ShellSystem system(problem, kind);
  selectSceneEvaluator(scene, system);
  addSceneEdgeRules(scene, problem, system);
  Objective& objective = system.objective();
  // The directory holds this run alone: what an earlier run into it left goes first (a resumed run keeps its own).
  if (!options.resume) {
    const std::string unfinished = unfinishedRunIn(options.outputDirectory);
    if (!unfinished.empty())
      throw InputError(options.outputDirectory + ": holds " + unfinished + ", which --resume " +
                       options.outputDirectory + " continues; a new run there would remove it (give another --out, "
                       "or remove " + checkpointPath(options.outputDirectory) + " to start over)");
    const int removed = removeEarlierRunFiles(options.outputDirectory);
    if (removed > 0)
      progress.log("removed " + std::to_string(removed) + " files of an earlier run from " + options.outputDirectory);
  }
  RunOutput output(options.outputDirectory, scene, model, options.scenePath);
  // Every row of probes.csv holds the contact force on each volume actor, with the solids where the analysis's
  // clock puts them at the row's time (a static path's is its load factor; a relaxation holds them).
  if (!system.contact.volume.empty())
    output.measureContactForces(system.contact.solidNames(), [&system](const Eigen::VectorXd& positions, double t) {
      std::vector<Eigen::Vector3d> forces;
      for (const auto& named : system.contact.solidForces(positions, t)) forces.push_back(named.second);
      return forces;
    });
  RunSummary& summary = result.summary;
  summary.activeTerms = objective.activeTermNames();
  {
    std::string terms;
    for (const std::string& t : summary.activeTerms) terms += (terms.empty() ? "" : ", ") + t;
    std::ostringstream s;
    s << toString(type) << " analysis of " << model.numVertices() << " vertices, " << model.world.numFaces()
      << " faces, " << model.prescribed.size() << " prescribed coordinates; active terms: " << terms;
    progress.log(s.str());
  }

  if ((options.checkpointEvery > 0 || options.resume) && type != AnalysisType::Dynamic)
    throw InputError(std::string("--checkpoint-every/--resume: only dynamic analyses have checkpoints (this one is ") +
                     toString(type) + ")");
  if (options.checkpointEvery < 0) throw InputError("--checkpoint-every: must be >= 0");
  // The run a checkpoint belongs to, and what it holds (tools/output/run_checkpoint.h checks every field).
  CheckpointScene checkpointScene;
  checkpointScene.fingerprint = options.sceneFingerprint;
  checkpointScene.vertices = model.numVertices();
  checkpointScene.timeStep = scene.analysis.timeStep;
  checkpointScene.duration = scene.analysis.duration;
  checkpointScene.probes = static_cast<int>(model.probes.size());
  checkpointScene.contactSolids = static_cast<int>(output.contactSolids().size());
  checkpointScene.frameFiles = output.filesPerFrame();
  checkpointScene.maxSteps = static_cast<int>(inputLimits().maxSteps);
  checkpointScene.cutReasons = SafeguardReport::cutReasons();
  RunCheckpoint checkpoint;
  if (options.resume)
    checkpoint = runCheckpointFromJson(readCheckpoint(options.outputDirectory), checkpointScene,
                                       checkpointPath(options.outputDirectory));
  // A resumed run checkpoints as the run it continues did, unless told otherwise: its solver restarts at the same
  // steps, so it stays that run bit for bit, and a second interruption loses no more than the first.
  const int checkpointEvery =
      options.resume && options.checkpointEvery == 0 ? checkpoint.checkpointEvery : options.checkpointEvery;
  if (options.resume && checkpointEvery != checkpoint.checkpointEvery)
    progress.log("checkpoints every " + std::to_string(checkpointEvery) + " steps, the interrupted run's every " +
                 std::to_string(checkpoint.checkpointEvery) +
                 ": the run agrees with an uninterrupted one to the solver's tolerance, not bit for bit");

  Eigen::VectorXd x = system.restPositions();
  objective.applyPrescribed(0.0, x);
  if (options.resume)
    output.restore(checkpoint.output);
  else
    output.record({0, 0.0, rowLoadFactor(0.0), &x, nullptr}, true);
  // The logged potential energy: elastic energy minus the loads' work on the displacements (F·u), i.e. the
  // potential at x minus the potential at the reference positions under the same loads (the load terms are
  // −F·x; their value at rest, −F·X, would swamp the digits that matter). An end moment's −λMθ is 0 at rest by
  // definition; evaluated there it would be unwrapped from the path's last equilibrium (2π once the edge has
  // turned full circle), so its value at rest is not subtracted.
  const Eigen::VectorXd rest = system.restPositions();
  auto potentialEnergy = [&](const Eigen::VectorXd& positions) {
    const double atX = objective.evaluate(positions, nullptr, false, EvalOptions{}, TermSelection::PotentialOnly);
    double atRest = objective.evaluate(rest, nullptr, false, EvalOptions{}, TermSelection::PotentialOnly);
    // Only the loads' work is measured from the rest positions: an end moment's energy is its work already, and
    // contact's is that of the state (at rest a moving solid may sit deep in the shell's rest positions).
    std::vector<std::string> absolute = system.contact.termNames();
    for (const std::shared_ptr<EndMomentTerm>& m : system.endMoments) absolute.push_back(m->name());
    const std::vector<std::string> names = objective.activeTermNames();
    for (const std::string& name : absolute) {
      const auto it = std::find(names.begin(), names.end(), name);
      if (it != names.end()) atRest -= objective.termEnergies()[static_cast<std::size_t>(it - names.begin())];
    }
    return atX - atRest;
  };
  // Stops the solver's loop: Ctrl-C, or the step limit of a quick check.
  auto shouldStop = [&](int steps) {
    if (interruptRequested()) return result.interrupted = true;
    if (options.stepLimit > 0 && steps >= options.stepLimit) return result.stepLimitReached = true;
    return false;
  };

  std::string termination;
  bool converged = false;
  SafeguardReport safeguards;
  const bool moveOn = scene.solver.acceptIterationCap && type != AnalysisType::Static;
  auto addSolves = [&](const StepReport& s) {
    for (const SolverSummary& solve : s.solves)
      safeguards.add(solve, solve.converged() || (moveOn && solve.reason == TerminationReason::IterationCap));
  };
  Eigen::VectorXd lastVelocity;  // dynamics: the final frame carries it like the others
  int lastStep = 0;               // the final frame's step: the last one recorded, or one after it (below)
  std::optional<double> finalLoadFactor;  // a static path's, when it stopped between two levels
  if (type == AnalysisType::Static) {
    LoadSteppingOptions o;
    // Levels k / loadSteps; the first solve from rest takes a quarter of a level (from the flat state the linear
    // response to a whole level overshoots by far), the increments then grow back to one level.
    o.maxIncrement = 1.0 / scene.analysis.loadSteps;
    o.initialIncrement = 0.25 * o.maxIncrement;
    for (int k = 1; k < scene.analysis.loadSteps; ++k) o.levels.push_back(static_cast<double>(k) / scene.analysis.loadSteps);
    o.newton = newtonOptionsFor(scene.solver, o.newton.maxIterations, true);
    setPathControl(scene.analysis.pathControl, model, system, o.path);
    o.branchSwitching = scene.analysis.branchSwitching;
    // A moving solid bounds the increments, judged once here (the log and summary.json say so when it binds); the
    // path then runs on the system's own load hooks, as solveStatics(ShellSystem&) would run it.
    const double levelIncrement = o.maxIncrement;
    o = forMovingSolids(system, x, o);
    if (o.maxIncrement < levelIncrement) {
      summary.extra["moving_solid_increment"] = o.maxIncrement;
      progress.log("a moving solid: load increments of at most " + formatNumber("%.4g", o.maxIncrement) +
                   ", so that no solid passes through the shell unseen between two solves");
    }
    int level = 0;  // output frames: the requested levels; steps between them (after cuts) are logged only
    const StaticsResult r = solveStatics(objective, loadFactorHooks(system), x, o, [&](const LoadStepResult& s) {
      const int step = s.step + 1;
      if (s.atLevel) {
        output.record({++level, s.loadFactor, s.loadFactor, &s.x, nullptr});
      }
      std::ostringstream line;
      line << "load step " << step << "  λ = " << formatNumber("%.4f", s.loadFactor) << "  Newton " << s.summary.iterations
           << "  residual " << formatNumber("%.3e", s.summary.finalResidual) << " N  E_pot "
           << formatNumber("%.6e", potentialEnergy(s.x)) << " J" << (s.cuts ? "  (" + std::to_string(s.cuts) + " cuts)" : "");
      if (s.negativePivots > 0) line << "  (unstable: " << s.negativePivots << " negative eigenvalue(s))";
      for (const auto& [solid, f] : system.contact.solidForces(s.x, s.loadFactor))
        line << "  force on '" << solid << "' (" << formatNumber("%.4g", f.x()) << ", " << formatNumber("%.4g", f.y())
             << ", " << formatNumber("%.4g", f.z()) << ") N";
      progress.log(line.str());
      progress.update(s.loadFactor, "λ = " + formatNumber("%.3f", s.loadFactor));
      return !shouldStop(level);
    });
    summary.steps = level;
    lastStep = level;
    // A path stopped between two levels (by a failure or Ctrl-C) ends on an equilibrium of its own λ: it is the
    // final frame, after the last level's, so that no row is labelled with another level's λ.
    if (!r.steps.empty() && !r.steps.back().atLevel) {
      finalLoadFactor = r.steps.back().loadFactor;
      lastStep = level + 1;
    }
    summary.newtonIterations = r.newtonIterations;
    summary.extra["load_steps_solved"] = static_cast<int>(r.steps.size());
    summary.extra["newton_iterations_per_load_step"] =
        r.steps.empty() ? 0.0 : static_cast<double>(r.newtonIterations) / static_cast<double>(r.steps.size());
    converged = r.completed;
    termination = r.completed ? "completed" : r.message;
    if (!r.completed && !r.stopped && r.steps.empty() && system.gravity)
      termination += "; no load step was reached from the rest state under the weight (a sheet as flexible as "
                     "cloth swings from flat to hanging at any load, which load stepping cannot follow; for such a "
                     "sheet use \"type\": \"dynamicRelaxation\", SCENES.md, Analysis)";
    if (!r.steps.empty()) x = r.steps.back().x;
    if (!r.steps.empty()) recordResidualClaim(summary.extra, r.steps.back().summary);
    summary.extra["final_load_factor_reached"] = r.loadFactor;
    summary.extra["path_control"] = scene.analysis.pathControl.type;
    // Path control, and load control after a branch switch (it follows the new branch by arc length).
    if (o.path.control != PathControl::Load || !r.branchSwitches.empty()) {
      nlohmann::json limits = nlohmann::json::array();
      for (const LimitPoint& l : r.limitPoints) {
        limits.push_back({{"load_step", l.step + 1}, {"load_factor", l.loadFactor},
                          {"kind", l.maximum ? "maximum" : "minimum"}});
        progress.log(std::string("limit point: the load factor ") + (l.maximum ? "turns down" : "turns back up") +
                     " at lambda = " + formatNumber("%.6g", l.loadFactor) + " (load step " + std::to_string(l.step + 1) + ")");
      }
      summary.extra["limit_points"] = limits;
      nlohmann::json bifurcations = nlohmann::json::array();
      for (const BifurcationPoint& b : r.bifurcationPoints) {
        bifurcations.push_back({{"load_step", b.step + 1},
                                {"load_factor_before", b.loadFactorBefore},
                                {"load_factor_after", b.loadFactorAfter},
                                {"negative_eigenvalues_before", b.negativeBefore},
                                {"negative_eigenvalues_after", b.negativeAfter}});
        progress.log("bifurcation: the tangent stiffness's negative eigenvalues go from " +
                     std::to_string(b.negativeBefore) + " to " + std::to_string(b.negativeAfter) +
                     " between lambda = " + formatNumber("%.6g", b.loadFactorBefore) + " and " +
                     formatNumber("%.6g", b.loadFactorAfter) + " (load step " + std::to_string(b.step + 1) +
                     "), with no limit point");
      }
      summary.extra["bifurcation_points"] = bifurcations;
      if (!r.bifurcationPoints.empty()) {
        const std::string w =
            "the path passed " + std::to_string(r.bifurcationPoints.size()) +
            " bifurcation point(s), where another branch of equilibria crosses it, and kept to its own branch, which "
            "may be the unstable one (negative_eigenvalues_after > 0); a small imperfection (a load or a rest shape "
            "slightly off the symmetry) makes the path follow the other. " +
            std::string(o.path.control == PathControl::Displacement
                            ? "Load control and arc length switch to a stable branch crossing their path "
                              "(\"branchSwitching\": true, the default); displacement control does not"
                        : !scene.analysis.branchSwitching
                            ? "With \"branchSwitching\": true (false in this scene) arc length switches to a stable "
                              "branch that leaves a stable path there"
                            : "Arc length switches only where the path was stable before the bifurcation and a "
                              "stable branch crosses it (summary.json branch_switch_failure says why a switch "
                              "failed)");
        result.warnings.push_back(w);
        progress.log("warning: " + w);
      }
    }
    summary.extra["load_step_cuts"] = r.totalCuts;
    // Steps whose equilibrium jumped (LoadJump): load control's snap-throughs, arc length's unresolved jumps,
    // displacement control's snap-backs.
    nlohmann::json jumps = nlohmann::json::array();
    for (const LoadJump& j : r.loadJumps) jumps.push_back(toJson(j));
    summary.extra["load_jumps"] = jumps;
    if (!r.loadJumps.empty()) {
      std::string w = "the equilibrium changed abruptly in " + std::to_string(r.loadJumps.size()) + " step(s) (";
      for (std::size_t i = 0; i < r.loadJumps.size(); ++i)
        w += (i > 0 ? ", " : "") + std::string("lambda = ") + formatNumber("%.6g", r.loadJumps[i].loadFactorBefore) +
             " to " + formatNumber("%.6g", r.loadJumps[i].loadFactorAfter);
      w += "): the step's change of potential energy differs from the loads' work along a continuous path, so the "
           "path in between is not traced (summary.json load_jumps). " +
           std::string(o.path.control == PathControl::Load
                           ? "Either a snap-through past a limit point, which load control passes as a jump to "
                             "another branch (\"pathControl\": {\"type\": \"arcLength\"} follows it through the "
                             "limit points), or a sheet so flexible that it swings within the step (\"type\": "
                             "\"dynamicRelaxation\" finds its end state directly)"
                           : o.path.control == PathControl::Displacement
                           ? "Displacement control jumps over a snap-back, where the driven displacement turns back "
                             "(\"type\": \"arcLength\" follows it)"
                           : "Arc length cut the step down to its smallest increment and still jumped: a branch it "
                             "cannot follow");
      result.warnings.push_back(w);
      progress.log("warning: " + w);
    }
    // Branch switches (load control and arc length, solvers/branch_switching.h).
    nlohmann::json switches = nlohmann::json::array();
    for (const BranchSwitchPoint& b : r.branchSwitches) {
      switches.push_back({{"load_step", b.step + 1},
                          {"stable_load_factor", b.stableLoadFactor},
                          {"unstable_load_factor", b.unstableLoadFactor},
                          {"negative_eigenvalues", b.negativeEigenvalues},
                          {"load_factor", b.loadFactor}});
      progress.log("bifurcation: the path became unstable (" + std::to_string(b.negativeEigenvalues) +
                   " negative eigenvalue(s)) between lambda = " + formatNumber("%.6g", b.stableLoadFactor) + " and " +
                   formatNumber("%.6g", b.unstableLoadFactor) + "; switched to the stable branch at lambda = " +
                   formatNumber("%.6g", b.loadFactor) + " (load step " + std::to_string(b.step + 1) +
                   ") and followed it by arc length");
    }
    summary.extra["branch_switches"] = switches;
    if (!r.branchSwitchFailure.empty()) {
      summary.extra["branch_switch_failure"] = r.branchSwitchFailure;
      progress.log("no branch switch " + r.branchSwitchFailure);
    }
    // Load control's check of equilibria that no positive definite factor vouched for (solvers/statics.h); path
    // control traces unstable branches on purpose and reports its limit points instead.
    if (o.path.control == PathControl::Load) {
      summary.extra["saddle_escapes"] = r.saddleEscapes;
      summary.extra["unstable_equilibria"] = r.unstableSteps;
      summary.extra["stability_checks"] = r.stabilityChecks;
    }
    if (r.saddleEscapes > 0)
      progress.log("left " + std::to_string(r.saddleEscapes) +
                   " unstable equilibrium(s) downhill along negative curvature");
    if (r.unstableSteps > 0) {
      const std::string w = std::to_string(r.unstableSteps) +
                            " load step(s) ended on an unstable equilibrium (a saddle of the potential energy: the "
                            "tangent stiffness there has negative eigenvalues), which no step along negative curvature "
                            "could leave for a lower one. A symmetric problem loaded past a bifurcation (a flat plate "
                            "or a straight column in compression) keeps to its unstable branch" +
                            (!scene.analysis.branchSwitching
                                 ? std::string(" unless \"branchSwitching\" is true (it is false in this scene)")
                             : !o.branchSwitching
                                 ? std::string(" (branch switching is off while a solid moves with the load factor: "
                                               "it corrects and goes on by arc length, which would move the solid)")
                             : r.branchSwitchFailure.empty()
                                 ? std::string(" (branch switching starts from an equilibrium known to be stable, "
                                               "and neither the load step before this saddle nor the start was one)")
                                 : "; branch switching failed " + r.branchSwitchFailure) +
                            "; a small imperfection (a load or a rest shape slightly off the symmetry) lets load "
                            "stepping follow the stable one, and dynamic relaxation at the final load steps off the "
                            "saddle and settles on it (\"type\": \"dynamicRelaxation\", examples/euler_column.json)";
      result.warnings.push_back(w);
      progress.log("warning: " + w);
    }
    for (const SolverSummary& f : r.failedSolves) safeguards.add(f, false);
    for (const LoadStepResult& step : r.steps) safeguards.add(step.summary, true);
  } else if (type == AnalysisType::Dynamic) {
    const DynamicsOptions o = dynamicsOptionsFor(scene);
    DynamicsSolver solver(system, o);
    // Say which actors' steps start without the extrapolated acceleration (solvers/dynamics.h).
    for (std::size_t a = 0; o.extrapolatedStart && a < model.actors.size(); ++a) {
      const int v = model.actors[a].firstVertex;
      if (model.actors[a].numVertices > 0 && !extrapolatesAcceleration(system, v, scene.analysis.timeStep, o))
        progress.log("shell actor '" + scene.shells[a].name + "': stiff and thin for the time step (its membrane "
                     "wave crosses " + formatNumber("%.3g", scene.analysis.timeStep * system.membraneWaveRate()[v]) +
                     " edges a step, its edges are " + formatNumber("%.3g", system.edgeOverThickness()[v]) +
                     " thicknesses long), so its steps start from x_n + dt v_n, without the extrapolated "
                     "acceleration");
    }
    solver.setState(x, Eigen::VectorXd::Zero(x.size()), 0.0);
    const double duration = scene.analysis.duration;
    int previousIterations = 0, previousCuts = 0;  // before the checkpoint resumed from
    int unconvergedSteps = 0;  // accepted at the iteration cap (the scene's acceptIterationCap)
    double worstRatio = 0.0;   // the largest final residual / tolerance over the steps
    SolverSummary lastSolve;
    if (options.resume) {
      const SolverCheckpoint& c = checkpoint.solver;
      solver.restore({c.x, c.v, c.xPrev, c.vPrev, c.t, c.historyStep, c.steps, c.historyValid});
      lastVelocity = c.v;
      previousIterations = checkpoint.newtonIterations;
      previousCuts = checkpoint.cuts;
      unconvergedSteps = checkpoint.stepsAtIterationCap;
      worstRatio = checkpoint.worstResidualOverTolerance;
      safeguards.restore(checkpoint.safeguards);
      progress.log("resumed from " + checkpointPath(options.outputDirectory) + " at step " +
                   std::to_string(solver.stepCount()) + ", t = " + formatNumber("%.4f", solver.time()) + " s");
    }
    int doneIterations = 0, doneCuts = 0;
    auto writeCheckpointNow = [&](const DynamicsSolver& d) {
      const DynamicsSolver::Snapshot snap = d.snapshot();
      RunCheckpoint c;
      c.solver = {snap.x, snap.v, snap.xPrev, snap.vPrev, snap.t, snap.historyStep, snap.steps, snap.historyValid};
      c.checkpointEvery = checkpointEvery;
      c.newtonIterations = previousIterations + doneIterations;
      c.cuts = previousCuts + doneCuts;
      c.stepsAtIterationCap = unconvergedSteps;
      c.worstResidualOverTolerance = worstRatio;
      c.safeguards = safeguards.state();
      c.output = output.state();
      writeCheckpoint(options.outputDirectory, toJson(c, checkpointScene));
    };
    // Whole steps to the end, counted from the start of the run (a resumed run does the rest).
    const int totalSteps = static_cast<int>(std::ceil(duration / o.timeStep - 1e-9));
    const double remaining = static_cast<double>(std::max(0, totalSteps - solver.stepCount())) * o.timeStep;
    if (system.nodalForces) system.nodalForces->setLoadFactor(model.loadFactorAtTime(solver.time() + o.timeStep));
    const DynamicsResult r = simulate(solver, remaining, [&](const StepReport& s, DynamicsSolver& d) {
      addSolves(s);
      if (!s.solves.empty()) {
        lastSolve = s.solves.back();
        lastSolve.trace.clear();
        // A step taken in parts moved on if any part did, though its last part may have converged; the same for
        // the worst residual.
        if (s.movedOn > 0) ++unconvergedSteps;
        worstRatio = std::max(worstRatio, s.worstResidualRatio);
      }
      output.record({s.step, d.time(), rowLoadFactor(d.time()), &d.positions(), &d.velocities()});
      lastVelocity = d.velocities();
      // The next step's loads: λ at its end time.
      if (system.nodalForces) system.nodalForces->setLoadFactor(model.loadFactorAtTime(d.time() + o.timeStep));
      const double residual = s.solves.empty() ? 0.0 : s.solves.back().finalResidual;
      std::ostringstream line;
      line << "step " << s.step << "  t = " << formatNumber("%.4f", d.time()) << " s  Newton " << s.newtonIterations
           << "  residual " << formatNumber("%.3e", residual) << " N  E_pot " << formatNumber("%.6e", potentialEnergy(d.positions()))
           << " J  E_kin " << formatNumber("%.6e", d.kineticEnergy()) << " J"
           << (s.parts > 1 ? "  (" + std::to_string(s.parts) + " parts: a moving solid)" : "")
           << (s.cuts ? "  (" + std::to_string(s.cuts) + " cuts)" : "")
           << (s.stayRestarts ? "  (solved again from the previous positions)" : "")
           << (s.guardSolves ? "  (solved on from the iteration cap: a contact guard broken there)" : "")
           << (s.movedOn ? "  (moved on at the iteration cap, not converged)" : "");
      progress.log(line.str());
      progress.update(d.time() / duration, "t = " + formatNumber("%.3f", d.time()) + " s");
      doneIterations += s.newtonIterations;
      doneCuts += s.cuts;
      if (checkpointEvery > 0 && s.step % checkpointEvery == 0) {
        writeCheckpointNow(d);
        d.forgetSolverHistory();  // a run resumed from here starts with a new solver: so does this one
      }
      return !shouldStop(s.step);
    });
    summary.steps = solver.stepCount();
    summary.newtonIterations = previousIterations + r.newtonIterations;
    // A step accepted at the iteration cap did not converge: the run says so (it moved on by the scene's choice).
    converged = r.completed && unconvergedSteps == 0;
    termination = !r.completed ? r.message : unconvergedSteps ? "completed_with_unconverged_steps" : "completed";
    x = solver.positions();
    if (r.steps > 0) recordResidualClaim(summary.extra, lastSolve);
    summary.extra["steps_at_iteration_cap"] = unconvergedSteps;
    if (unconvergedSteps > 0)
      result.notes.push_back(std::to_string(unconvergedSteps) + " of " + std::to_string(summary.steps) +
                             " steps moved on at the iteration cap without converging (the scene's "
                             "solver.acceptIterationCap; steps_at_iteration_cap in summary.json)");
    summary.extra["worst_residual_over_tolerance"] = worstRatio;
    summary.extra["final_time"] = solver.time();
    summary.extra["step_cuts"] = previousCuts + r.cuts;
  } else {
    RelaxationOptions o;
    o.timeStep = scene.analysis.timeStep;
    o.massDamping = scene.analysis.massDamping;
    o.maxSteps = scene.analysis.maxSteps;
    o.residualTolerance = scene.analysis.tolerance;
    o.newton = newtonOptionsFor(scene.solver, o.newton.maxIterations);
    double firstResidual = -1.0;
    const RelaxationResult r = relaxToStatic(system, x, o, [&](const StepReport& s, double staticResidual) {
      addSolves(s);
      output.record({s.step, s.time, rowLoadFactor(s.time), &x, nullptr});
      if (firstResidual < 0) firstResidual = staticResidual;
      std::ostringstream line;
      line << "step " << s.step << "  t = " << formatNumber("%.4f", s.time) << " s  Newton " << s.newtonIterations
           << "  static residual " << formatNumber("%.3e", staticResidual) << " N  E_pot "
           << formatNumber("%.6e", potentialEnergy(x)) << " J" << (s.cuts ? "  (" + std::to_string(s.cuts) + " cuts)" : "")
           << (s.stayRestarts ? "  (solved again from the previous positions)" : "");
      progress.log(line.str());
      // Progress in orders of magnitude of the residual still to go, or in steps when that says more.
      const double threshold = o.residualTolerance * objective.forceScale(x, firstResidual).value;
      const double byResidual = std::log(firstResidual / staticResidual) / std::log(firstResidual / threshold);
      const double bySteps = static_cast<double>(s.step) / o.maxSteps;
      progress.update(std::max(std::isfinite(byResidual) ? byResidual : 0.0, bySteps),
                      "step " + std::to_string(s.step) + ", residual " + formatNumber("%.2e", staticResidual) + " N");
      return !shouldStop(s.step);
    });
    summary.steps = r.steps;
    summary.newtonIterations = r.newtonIterations;
    converged = r.converged;
    termination = r.converged ? "converged" : r.message;
    if (!r.converged && !r.stopped && r.steps >= o.maxSteps) {
      // The step budget ran out: said once, without the step and iteration counts the run's report adds.
      std::ostringstream t;
      t << "maxSteps (" << o.maxSteps << ") reached with the static residual " << formatNumber("%.3e", r.staticResidual)
        << " N above " << formatNumber("%.3e", r.residualThreshold) << " N";
      if (r.saddleEscapes > 0) t << "; left " << r.saddleEscapes << " unstable equilibrium(s) downhill on the way";
      termination = t.str();
    }
    recordResidualClaim(summary.extra, r.staticResidual, r.residualThreshold, r.forceScale, r.forceScaleSource);
    summary.extra["pseudo_time"] = r.pseudoTime;
    // The relaxation's check of the equilibrium it reached (solvers/dynamic_relaxation.h).
    summary.extra["saddle_escapes"] = r.saddleEscapes;
    summary.extra["unstable_equilibria"] = r.converged && r.negativeEigenvalues > 0 ? 1 : 0;
    if (r.saddleEscapes > 0)
      progress.log("left " + std::to_string(r.saddleEscapes) +
                   " unstable equilibrium(s) downhill along negative curvature");
    if (r.converged && r.negativeEigenvalues > 0) {
      const std::string w = "the relaxation ended on an unstable equilibrium (a saddle of the potential energy: " +
                            std::to_string(r.negativeEigenvalues) +
                            " negative eigenvalue(s)), which no step along negative curvature could leave for a "
                            "lower one";
      result.warnings.push_back(w);
      progress.log("warning: " + w);
    }
  }
  summary.extra["safeguards"] = safeguards.toJson(moveOn ? "move_on" : "cut_step");
  // Ctrl-C during a step that then failed (every cut tried) still ends as an interruption.
  if (interruptRequested()) result.interrupted = true;
  if (result.interrupted) termination = "interrupted";
  else if (result.stepLimitReached && !converged) termination = "step_limit";
  summary.converged = converged;
  summary.termination = termination;
  // The last state always has a frame, whatever the stride.
  if (type != AnalysisType::Static) lastStep = summary.steps;
  // Its time is the last row's (the state the solvers left x in), except on a static path stopped between levels.
  const double finalTime = finalLoadFactor ? *finalLoadFactor : output.lastRow() ? output.lastRow()->time : 0.0;
  output.record({lastStep, finalTime, rowLoadFactor(finalTime), &x,
                 lastVelocity.size() ? &lastVelocity : nullptr},
                true);
  {
    std::vector<int> inverted;
    for (const ActorBlock& b : model.actors)
      for (int f : invertedFaces(b.mesh, b.topology, x.segment(3 * b.firstVertex, 3 * b.numVertices)))
        inverted.push_back(b.firstFace + f);
    summary.extra["inverted_faces"] = inverted.size();
    if (!inverted.empty()) {
      std::ostringstream w;
      w << inverted.size()
        << " inverted face(s) at the end of the run (turned by more than 120° against a neighbour, from their angle "
           "in the reference shape), e.g. face "
        << inverted.front() << ": an element was pushed through itself; the result there is not physical";
      result.warnings.push_back(w.str());
      progress.log("warning: " + w.str());
    }
  }
  summary.extra["warnings"] = result.warnings;
  progress.finish();
  summary.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.lastFrame = output.lastFrame();

  namespace fs = std::filesystem;
  if (options.pictures && scene.outputs.png && scene.outputs.vtu && !result.lastFrame.empty()) {
    try {
      RenderOptions r;
      r.up = upAxis(scene);
      std::vector<std::string> files = result.lastFrame;
      for (const std::string& f : output.volumeFiles()) files.push_back(f);
      result.finalPng = (fs::path(options.outputDirectory) / "final.png").string();
      renderVtuFiles(files, "displacement", r, result.finalPng);
    } catch (const InputError& e) {
      result.notes.push_back(std::string("final.png not drawn: ") + e.what());
      result.finalPng.clear();
    }
  }
  if (options.pictures && scene.outputs.plots) {
    const std::string title = scene.description;
    const std::string xLabel = type == AnalysisType::Static ? "load factor λ" : "time t [s]";
    // Draws one plot into the output directory; a plot that cannot be drawn is a note, not a failed run.
    auto draw = [&](std::vector<PlotSeries> curves, const std::string& what, const std::string& yLabel,
                    const std::string& file) {
      if (curves.empty()) return std::string();
      PlotSpec plot;
      plot.title = title.empty() ? what : title;
      plot.xLabel = xLabel;
      plot.yLabel = yLabel;
      plot.series = std::move(curves);
      const std::string path = (fs::path(options.outputDirectory) / file).string();
      try {
        plotPng(plot, path);
        return path;
      } catch (const InputError& e) {
        result.notes.push_back(file + " not drawn: " + e.what());
        return std::string();
      }
    };
    std::vector<std::string> probeNames;
    for (const ResolvedProbe& p : model.probes) probeNames.push_back(p.name);
    const PlotRows rows = output.plotRows();
    if (rows.recorded > 1) {
      result.probesPng = draw(rowCurves(probeNames, "u", rows, output.lastRow(), RowField::u),
                              "probe displacements", "displacement [m]", "probes.png");
      result.contactForcesPng = draw(rowCurves(output.contactSolids(), "F", rows, output.lastRow(), RowField::force),
                                     "contact forces", "force on the solid [N]", "contact_forces.png");
    }
  }
  summary.extra["pictures"] = {{"final_png", result.finalPng.empty() ? "" : "final.png"},
                               {"probes_png", result.probesPng.empty() ? "" : "probes.png"},
                               {"contact_forces_png", result.contactForcesPng.empty() ? "" : "contact_forces.png"}};
  output.finish(summary);
  return result;
}

}  // namespace jetshell
