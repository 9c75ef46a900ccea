#include "solvers/statics.h"

#include "core/mesh.h"
#include "solvers/indefinite_factor.h"
#include "solvers/path_energy.h"
#include "solvers/path_following.h"
#include "solvers/stability_check.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace jetshell {
namespace {

void check(bool ok, const char* field, double value, const char* rule) {
  if (ok) return;
  std::ostringstream s;
  s << "load stepping: " << field << " = " << value << ": " << rule;
  throw InputError(s.str());
}

/// LoadSteppingOptions::checkStability on the equilibrium x that `summary` reached, whose check is `s` (the caller's,
/// which branch switching reads first): returns the negative eigenvalues of the exact Hessian at the equilibrium
/// finally kept (-1: the factorization failed, so unknown).
/// x and summary are replaced when a saddle is left for a lower equilibrium (at most saddleEscapes times). The
/// factorization is the supernodal LDLᵀ of solvers/indefinite_factor.h, BLAS on one thread; `factor` is the path's
/// own, as in path control, so its symbolic analysis is done once per Hessian pattern, not once per check.
int leaveSaddles(Objective& objective, NewtonSolver& newton, IndefiniteFactor& factor, const LoadSteppingOptions& o,
                 Eigen::VectorXd& x, SolverSummary& summary, StaticsResult& result, Stability s) {
  for (int escape = 0;; ++escape) {
    if (escape > 0) s = assessStability(objective, factor, x, o.newton.derivatives, o.saddleStep);
    if (s.negativeEigenvalues <= 0 || escape == o.saddleEscapes || s.downhill.size() == 0) return s.negativeEigenvalues;
    const double roundOff = 1e-13 * objective.energyMagnitude();
    Eigen::VectorXd trial = x + s.downhill;
    SolverSummary solve = newton.minimize(trial);
    result.newtonIterations += solve.iterations;
    if (!solve.converged() || !(solve.finalEnergy < s.energy - roundOff)) return s.negativeEigenvalues;
    x = trial;
    summary = std::move(solve);
    ++result.saddleEscapes;
    if (summary.lastHessianPositiveDefinite) return 0;  // the new solve's own last factor says so
  }
}

}  // namespace

void LoadFactorHooks::set(double lambda) const {
  if (nodalForces != nullptr) nodalForces->setLoadFactor(lambda);
  if (gravity != nullptr) gravity->setLoadFactor(lambda);
  for (const Hook& h : others)
    if (h.set) h.set(lambda);
}

void LoadFactorHooks::accept(const Eigen::VectorXd& x) const {
  for (const Hook& h : others)
    if (h.accept) h.accept(x);
}

Eigen::VectorXd extrapolateEquilibria(const std::vector<std::pair<double, Eigen::VectorXd>>& history, double lambda,
                                      int points) {
  const int size = static_cast<int>(history.size());
  const int n = points < 0 ? size : std::min(points, size);
  if (n < 2) return history.front().second;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(history.front().second.size());
  for (int i = 0; i < n; ++i) {
    double w = 1.0;
    for (int j = 0; j < n; ++j)
      if (j != i) w *= (lambda - history[j].first) / (history[i].first - history[j].first);
    p += w * history[i].second;
  }
  return p;
}

std::vector<double> pathStops(double start, double target, const std::vector<double>& levels) {
  const double direction = target >= start ? 1.0 : -1.0;
  const double eps = 1e-12 * std::max({1.0, std::abs(target), std::abs(start)});
  std::vector<double> stops;
  for (double l : levels) {
    check(std::isfinite(l) && direction * (l - start) > eps && direction * (target - l) >= -eps, "level", l,
          "must lie after startLoadFactor and not beyond targetLoadFactor");
    stops.push_back(l);
  }
  stops.push_back(target);
  std::sort(stops.begin(), stops.end(), [&](double a, double b) { return direction * a < direction * b; });
  stops.erase(std::unique(stops.begin(), stops.end(), [&](double a, double b) { return std::abs(a - b) <= eps; }),
              stops.end());
  return stops;
}

NewtonOptions staticNewtonOptions() {
  NewtonOptions o;
  o.projection = PsdProjection::None;
  return o;
}

StaticsResult solveStatics(Objective& objective, const LoadFactorHooks& loads, Eigen::VectorXd& x,
                           const LoadSteppingOptions& o, const LoadStepCallback& callback) {
  check(std::isfinite(o.targetLoadFactor), "targetLoadFactor", o.targetLoadFactor, "must be finite");
  check(std::isfinite(o.startLoadFactor), "startLoadFactor", o.startLoadFactor, "must be finite");
  check(o.minIncrement > 0.0, "minIncrement", o.minIncrement, "must be > 0");
  check(o.maxIncrement >= o.minIncrement, "maxIncrement", o.maxIncrement, "must be >= minIncrement");
  check(o.initialIncrement >= o.minIncrement, "initialIncrement", o.initialIncrement, "must be >= minIncrement");
  check(o.growth >= 1.0, "growth", o.growth, "must be >= 1");
  check(o.predictorOrder >= 0 && o.predictorOrder <= 5, "predictorOrder", o.predictorOrder, "must be in 0..5");
  check(o.levels.size() <= 1000000, "levels (count)", static_cast<double>(o.levels.size()), "must be <= 1e6");
  check(o.saddleEscapes >= 0 && o.saddleEscapes <= 100, "saddleEscapes", o.saddleEscapes, "must be in 0..100");
  check(std::isfinite(o.saddleStep) && o.saddleStep > 0.0 && o.saddleStep <= 10.0, "saddleStep", o.saddleStep,
        "must be in (0, 10]");
  checkBranchSwitchOptions(o.branchSwitch);
  if (x.size() != objective.numDofs()) throw InputError("load stepping: x has the wrong size");

  // Residuals along this path are judged against its prescribed motion as a whole (Objective::forceScale).
  struct PrescribedPathScope {
    Objective& objective;
    ~PrescribedPathScope() { objective.clearPrescribedPath(); }
  } scope{objective};
  objective.setPrescribedPath(o.startLoadFactor, o.targetLoadFactor,
                              loads.solidMotion ? loads.solidMotion(o.startLoadFactor, o.targetLoadFactor) : 0.0);
  if (o.path.control != PathControl::Load) return followPath(objective, loads, x, o, callback);
  const double start = o.startLoadFactor, target = o.targetLoadFactor;
  const double direction = target >= start ? 1.0 : -1.0;
  const std::vector<double> stops = pathStops(start, target, o.levels);

  StaticsResult result;
  result.activeTerms = objective.activeTermNames();
  NewtonSolver newton(objective, o.newton);
  IndefiniteFactor stability;  // checkStability's factor, analysed once per pattern
  double lambda = start;
  double increment = std::min(o.initialIncrement, o.maxIncrement);
  int cuts = 0;
  std::vector<std::pair<double, Eigen::VectorXd>> history = {{start, x}};  // accepted (λ, x), newest first
  std::size_t nextStop = 0;
  int order = o.predictorOrder;
  bool first = true;
  bool previousStable = false;  // the last accepted equilibrium is known to be stable (branchSwitching)
  const EvalOptions energyOptions{o.newton.derivatives, PsdProjection::None, o.newton.bendingHessian};
  std::optional<PathEnergy> lastEnergy;  // at the last accepted equilibrium (LoadJump)
  const Eigen::VectorXd pathStart = x;
  // At least one solve, even for target = start (gravity or prescribed positions alone).
  while (first || nextStop < stops.size()) {
    const double stop = nextStop < stops.size() ? stops[nextStop] : target;
    const double remaining = direction * (stop - lambda);
    const bool landing = remaining <= increment * (1.0 + 1e-9);
    // Two even steps rather than a full one and a sliver.
    const double size = remaining < 2.0 * increment ? 0.5 * remaining : increment;
    const double next = landing ? stop : lambda + direction * size;
    // The prediction at λ_next of order k (k + 1 newest equilibria; 0: the last one), prescribed positions applied.
    auto predict = [&](int k) {
      Eigen::VectorXd p = extrapolateEquilibria(history, next, k + 1);
      objective.applyPrescribed(next, p);
      return p;
    };
    const Eigen::VectorXd prediction = predict(order);  // the order adapts, see below
    Eigen::VectorXd trial = prediction;
    loads.set(next);
    SolverSummary summary = newton.minimize(trial);
    result.newtonIterations += summary.iterations;
    if (!summary.converged()) {
      summary.trace.clear();
      result.failedSolves.push_back(summary);
      ++cuts;
      ++result.totalCuts;
      increment = 0.5 * std::abs(next - lambda);
      if (increment < o.minIncrement) {
        loads.set(lambda);
        std::ostringstream s;
        s << "load step to lambda = " << next << " failed (" << toString(summary.reason) << ": " << summary.message
          << ") with the increment cut below " << o.minIncrement << "; stopped at lambda = " << lambda;
        result.message = s.str();
        result.loadFactor = lambda;
        return result;
      }
      continue;
    }
    int negativePivots = -1;
    const int escapesBefore = result.saddleEscapes;
    if (o.checkStability && !summary.lastHessianPositiveDefinite) {
      ++result.stabilityChecks;
      const Stability checked = assessStability(objective, stability, trial, o.newton.derivatives, o.saddleStep);
      bool stableBefore = previousStable;
      Eigen::VectorXd from = x;
      if (o.branchSwitching && first && checked.negativeEigenvalues > 0) {
        // The first step has no accepted equilibrium before it: the start, solved at its λ (no iteration from the
        // rest state at λ = 0), is checked instead, and is the bracket's stable end if it is stable.
        objective.applyPrescribed(lambda, from);
        loads.set(lambda);
        const SolverSummary atStart = newton.minimize(from);
        result.newtonIterations += atStart.iterations;
        if (atStart.converged()) {
          ++result.stabilityChecks;
          stableBefore =
              assessStability(objective, stability, from, o.newton.derivatives, o.saddleStep).negativeEigenvalues == 0;
        }
        loads.set(next);
      }
      if (o.branchSwitching && stableBefore && checked.negativeEigenvalues > 0) {
        BranchSwitchResult sw = switchBranch(newton, loads, stability, o.branchSwitch, lambda, from, next, trial);
        result.newtonIterations += sw.newtonIterations;
        result.stabilityChecks += sw.factorizations;
        if (sw.switched) {
          followNewBranch(objective, loads, x, o, callback, stops, increment, cuts, sw, result, sw.loadFactor);
          return result;
        }
        result.branchSwitchFailure = switchFailure(sw);
      }
      negativePivots = leaveSaddles(objective, newton, stability, o, trial, summary, result, checked);
      if (negativePivots > 0) ++result.unstableSteps;
    }
    previousStable = negativePivots == 0 || (negativePivots < 0 && summary.lastHessianPositiveDefinite);
    first = false;
    // A polynomial through a strongly curved or unevenly spaced stretch of the path can land farther from the
    // equilibrium than the last one was: then the order drops by one (down to 0, the last equilibrium); it
    // climbs back by one (up to predictorOrder) when the next order's prediction would have landed at least twice
    // as close as the last equilibrium (the errors are max-norm distances to the new equilibrium). Measured on a
    // cantilever swinging down under 1e6 m/s² gravity: a fixed order 3 started Newton 0.43 m off, with 7–10
    // iterations however small the increment, which shrank to minIncrement (5,013 steps).
    if (o.predictorOrder > 0 && history.size() >= 2) {
      auto error = [&](int k) { return (trial - (k == order ? prediction : predict(k))).lpNorm<Eigen::Infinity>(); };
      const double held = error(0);
      if (order > 0 && error(order) > held) --order;
      else if (order < o.predictorOrder && history.size() >= static_cast<std::size_t>(order) + 2 &&
               2.0 * error(order + 1) <= held)
        ++order;
    }
    // A jump (LoadJump): the energy change against the trapezoid of ∂E/∂λ. A step that left a saddle downhill
    // jumped on purpose and is reported as an escape instead. The first step is not checked: the start need not be
    // an equilibrium (a caller may start off balance), and a sheet as flexible as cloth swings from flat to hanging
    // there, continuously but within any first step (`jetshell stress`: 0.7–0.97 of the step's work).
    const bool checkJump = o.detectJumps && !result.steps.empty();
    const PathEnergy energy =
        checkJump ? pathEnergy(objective, loads, trial, next, pathStart, energyOptions) : PathEnergy{};
    if (checkJump && (!lastEnergy || lastEnergy->lambda != lambda))
      lastEnergy = pathEnergy(objective, loads, x, lambda, pathStart, energyOptions);
    if (checkJump && result.saddleEscapes == escapesBefore) {
      const PathMismatch m = chordMismatch(*lastEnergy, energy);
      if (m.work > 0.0 && std::abs(m.released) > LoadJump::kRatio * m.work) {
        // Confirmed at the step's midpoint (solved from the step's own predictor): a jump keeps its released
        // energy in one half of the step; a continuous path whose derivative is singular where the step starts (a
        // sheet swinging from flat under its weight, u ∝ λ^p from the rest state) spreads it, the worse half
        // keeping 2^-(1+p) < ½ of it. A midpoint that cannot be solved leaves the jump reported.
        const double mid = 0.5 * (lambda + next);
        Eigen::VectorXd xm = extrapolateEquilibria(history, mid, order + 1);
        objective.applyPrescribed(mid, xm);
        loads.set(mid);
        const SolverSummary ms = newton.minimize(xm);
        result.newtonIterations += ms.iterations;
        bool jump = true;
        if (ms.converged()) {
          const PathEnergy e = pathEnergy(objective, loads, xm, mid, pathStart, energyOptions);
          const double worse = std::max(std::abs(chordMismatch(*lastEnergy, e).released),
                                        std::abs(chordMismatch(e, energy).released));
          jump = worse > LoadJump::kConcentration * std::abs(m.released);
        }
        if (jump)
          result.loadJumps.push_back({static_cast<int>(result.steps.size()), lambda, next, m.released,
                                      std::abs(m.released) / m.work});
      }
    }
    if (checkJump) lastEnergy = energy;
    loads.set(next);
    lambda = next;
    x = trial;
    loads.accept(x);
    history.insert(history.begin(), {lambda, x});
    if (static_cast<int>(history.size()) > o.predictorOrder + 1) history.pop_back();
    LoadStepResult step;
    step.step = static_cast<int>(result.steps.size());
    step.loadFactor = step.pathParameter = lambda;
    step.atLevel = landing;
    if (landing) ++nextStop;
    step.x = x;
    step.cuts = cuts;
    step.negativePivots = negativePivots;
    // The next increment aims at easyIterations Newton iterations: Δλ ×= √(easy / taken), within [½, growth].
    const double factor =
        std::clamp(std::sqrt(static_cast<double>(o.easyIterations) / std::max(1, summary.iterations)), 0.5, o.growth);
    step.summary = std::move(summary);
    result.steps.push_back(std::move(step));
    cuts = 0;
    increment = std::clamp(increment * factor, o.minIncrement, o.maxIncrement);
    result.loadFactor = lambda;
    if (callback && !callback(result.steps.back())) {
      result.stopped = true;
      result.message = "stopped by the callback at lambda = " + std::to_string(lambda);
      return result;
    }
  }
  result.completed = true;
  result.loadFactor = target;
  std::ostringstream s;
  s << "reached lambda = " << target << " in " << result.steps.size() << " steps (" << result.totalCuts << " cuts, "
    << result.newtonIterations << " Newton iterations)";
  if (result.saddleEscapes > 0) s << "; left " << result.saddleEscapes << " unstable equilibria downhill";
  if (result.unstableSteps > 0)
    s << "; " << result.unstableSteps << " step(s) ended on an unstable equilibrium (a saddle of the potential)";
  if (!result.branchSwitchFailure.empty()) s << "; no branch switch " << result.branchSwitchFailure;
  for (const LoadJump& j : result.loadJumps)
    s << "; the equilibrium changed abruptly between lambda = " << j.loadFactorBefore << " and " << j.loadFactorAfter
      << " (energy released " << j.energyReleased << " J)";
  result.message = s.str();
  return result;
}

LoadFactorHooks loadFactorHooks(ShellSystem& system, const std::vector<LoadFactorHooks::Hook>& extra) {
  LoadFactorHooks hooks;
  hooks.nodalForces = system.nodalForces.get();
  hooks.gravity = system.gravity.get();
  for (const std::shared_ptr<EndMomentTerm>& m : system.endMoments)
    hooks.others.push_back(
        {[m](double lambda) { m->setLoadFactor(lambda); }, [m](const Eigen::VectorXd& x) { m->advance(x); }});
  // A moving solid is where its path puts it at time λ (a statics system reads its keyframes only), and its
  // travel from the rest positions counts in the force scale.
  for (const VolumeContactTerms& v : system.contact.volume)
    if (!v.state->collider->path().isStatic()) {
      const std::shared_ptr<VolumeContactState> state = v.state;
      hooks.others.push_back({[state](double lambda) { state->time = lambda; }, {}});
    }
  if (!movingSolids(system).empty()) {
    const ShellSystem* s = &system;
    hooks.solidMotion = [s](double from, double to) {
      return movingSolidTravel(*s, s->restPositions(), std::min(from, to), std::max(from, to));
    };
  }
  hooks.others.insert(hooks.others.end(), extra.begin(), extra.end());
  return hooks;
}

std::vector<std::string> movingSolids(const ShellSystem& system) {
  std::vector<std::string> names;
  for (const VolumeContactTerms& v : system.contact.volume)
    if (!v.state->collider->path().isStatic()) {
      const std::string& name = v.state->collider->name();
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  return names;
}

double movingSolidTravel(const ShellSystem& system, const Eigen::VectorXd& x, double from, double to) {
  double travel = 0.0;
  if (!(to > from)) return travel;
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(x.size());
  for (const VolumeContactTerms& v : system.contact.volume)
    travel = std::max(travel, v.state->solidTravel(x, still, from, to - from));
  return travel;
}

double movingSolidIncrement(const ShellSystem& system, const Eigen::VectorXd& x, double start, double target) {
  const double span = target - start;
  if (movingSolids(system).empty() || !(span > 0.0)) return std::numeric_limits<double>::infinity();
  // The solids move at constant rates between their keyframes, not evenly over the path: each stretch between two
  // keyframe times (of any solid) is divided on its own, and the increment is the smallest any stretch needs.
  std::vector<double> times = {start, target};
  for (const VolumeContactTerms& v : system.contact.volume) {
    if (v.state->collider->path().isStatic()) continue;
    for (const RigidPath::Piece& piece : v.state->collider->path().piecesOver(start, span)) {
      times.push_back(piece.start);
      if (times.size() > static_cast<std::size_t>(kMaxMovingSolidIncrements) + 2)
        throw InputError("static path: the volume actor '" + v.state->collider->name() + "' has more than " +
                         std::to_string(static_cast<int>(kMaxMovingSolidIncrements)) +
                         " keyframes between lambda = " + std::to_string(start) + " and " + std::to_string(target) +
                         ", more than the load increments a static path takes");
    }
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(x.size());
  double most = std::numeric_limits<double>::infinity();
  ShellContact::SolidSweep worst;
  double worstFrom = start, worstTo = target;
  for (std::size_t k = 0; k + 1 < times.size(); ++k) {
    const double from = std::max(start, times[k]), to = std::min(target, times[k + 1]);
    if (!(to > from)) continue;
    const ShellContact::SolidSweep sweep =
        system.contact.solidSweep(x, still, from, to - from, kMaxMovingSolidIncrements);
    if (!(sweep.parts > 1.0)) continue;
    const double increment = (to - from) / std::ceil(sweep.parts - 1e-9);
    if (increment < most) {
      most = increment;
      worst = sweep;
      worstFrom = from;
      worstTo = to;
    }
  }
  if (!std::isfinite(most)) return most;
  if (span / most > kMaxMovingSolidIncrements * (1.0 + 1e-9)) {
    std::ostringstream s;
    s << "static path: the solid '" << worst.solid << "' moves " << worst.travel << " m near the shell between "
      << "lambda = " << worstFrom << " and " << worstTo << ", which needs load increments of at most "
      << most << ", more than " << kMaxMovingSolidIncrements << " of them over the path (each may move it "
      << worst.allowed << " m, a fraction of its thinnest half-width, or it may pass through the shell unseen): "
      << "move it less or over more of the path, or make it thicker";
    throw InputError(s.str());
  }
  return most;
}

StaticsResult solveStatics(ShellSystem& system, Eigen::VectorXd& x, const LoadSteppingOptions& options,
                           const LoadStepCallback& callback, const std::vector<LoadFactorHooks::Hook>& extra) {
  if (system.kind() != AnalysisKind::Statics)
    throw InputError(std::string("solveStatics: the system was built for ") + toString(system.kind()));
  const LoadSteppingOptions o =
      x.size() == system.objective().numDofs() ? forMovingSolids(system, x, options) : options;
  return solveStatics(system.objective(), loadFactorHooks(system, extra), x, o, callback);
}

LoadSteppingOptions forMovingSolids(const ShellSystem& system, const Eigen::VectorXd& x, LoadSteppingOptions o) {
  const std::vector<std::string> solids = movingSolids(system);
  if (solids.empty()) return o;
  if (o.path.control != PathControl::Load)
    throw InputError(std::string("static path: the volume actor '") + solids.front() +
                     "' moves with the load factor, which " + toString(o.path.control) +
                     " control solves for; a moving solid needs load control");
  // A branch switch corrects onto the new branch by arc length and follows it so, both solving for λ: the solid
  // would move inside a correction, as under arc-length control (measured: a bar turned in a sheet tried it at a
  // saddle and every correction diverged, the residual 685 N -> 3e9 N). Load control keeps to its branch.
  o.branchSwitching = false;
  const double most = movingSolidIncrement(system, x, o.startLoadFactor, o.targetLoadFactor);
  o.maxIncrement = std::min(o.maxIncrement, most);
  o.initialIncrement = std::min(o.initialIncrement, most);
  o.minIncrement = std::min(o.minIncrement, o.initialIncrement);
  return o;
}

}  // namespace jetshell
