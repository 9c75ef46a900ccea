#include "solvers/path_following.h"

#include "core/mesh.h"
#include "solvers/path_corrector.h"
#include "solvers/path_energy.h"
#include "solvers/stability_check.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

namespace jetshell {
namespace {

/// The cubic Hermite basis on t ∈ [0, 1]: f(t) = h00 f(0) + h10 f'(0) + h01 f(1) + h11 f'(1) for a cubic f (slopes
/// in t: the interval's length times the slopes in its own parameter). Limit points (hermiteTurn) and landings.
struct HermiteBasis {
  double h00, h10, h01, h11;
};
HermiteBasis hermiteBasis(double t) {
  const double t2 = t * t, t3 = t2 * t;
  return {2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + t, -2.0 * t3 + 3.0 * t2, t3 - t2};
}

/// The cubic Hermite interpolant between (λ_a, x_a) and (λ_b, x_b) = (λ_a + Δλ, ...) with slopes dx/dλ t_a and t_b,
/// less the chord, at s = (λ − λ_a)/Δλ; zero on the fixed dofs (which keep the chord's values: prescribed motion
/// is linear in λ).
Eigen::VectorXd hermiteBend(const Eigen::VectorXd& xa, const Eigen::VectorXd& xb, const Eigen::VectorXd& ta,
                            const Eigen::VectorXd& tb, double dLambda, double s, const Objective& objective) {
  const HermiteBasis h = hermiteBasis(s);
  Eigen::VectorXd bend = (h.h00 - (1.0 - s)) * xa + (h.h01 - s) * xb;
  bend += (h.h10 * dLambda) * ta + (h.h11 * dLambda) * tb;
  objective.zeroFixed(bend);
  return bend;
}

void checkPathOption(bool ok, const char* field, double value, const char* rule) {
  if (ok) return;
  std::ostringstream s;
  s << "path following: " << field << " = " << value << ": " << rule;
  throw InputError(s.str());
}

/// Arc length: a correction whose increment turns by more than 60° from the previous one is cut (a large step
/// can land on another branch or cut a sharp turn of the path short; smaller steps follow it).
constexpr double kMinCosine = 0.5;
/// Arc length: the largest vertex move of the first increment along the start's tangent, in the shell's size.
constexpr double kFirstMove = 0.05;
/// Arc length: the share of maxIncrement that an increment's λ along the last tangent may take.
constexpr double kLambdaMargin = 0.9;

struct PathPoint {
  double p = 0.0;  // path parameter: arc length or τ
  double lambda = 0.0;
  Eigen::VectorXd x;
  int step = 0;    // its index in the result's steps
  double rate = std::nan("");  // dλ/dp there along the path, from its tangent (NaN: none)
};

/// (x, λ) at p from the polynomial through the history's points (newest first).
void extrapolate(const std::deque<PathPoint>& history, double p, Eigen::VectorXd& x, double& lambda) {
  std::vector<std::pair<double, Eigen::VectorXd>> h;
  for (const PathPoint& q : history) {
    Eigen::VectorXd z(q.x.size() + 1);
    z << q.x, q.lambda;
    h.emplace_back(q.p, std::move(z));
  }
  const Eigen::VectorXd z = extrapolateEquilibria(h, p);
  x = z.head(z.size() - 1);
  lambda = z[z.size() - 1];
}

}  // namespace

nlohmann::json toJson(const LoadJump& j) {
  return {{"load_step", j.step + 1},
          {"load_factor_before", j.loadFactorBefore},
          {"load_factor_after", j.loadFactorAfter},
          {"energy_released", j.energyReleased},
          {"energy_mismatch", j.ratio}};
}

const char* toString(PathControl c) {
  switch (c) {
    case PathControl::Load: return "load";
    case PathControl::ArcLength: return "arcLength";
    case PathControl::Displacement: return "displacement";
  }
  return "?";
}

double parabolaVertex(const double p[3], const double v[3]) {
  const double f01 = (v[1] - v[0]) / (p[1] - p[0]), f12 = (v[2] - v[1]) / (p[2] - p[1]);
  const double f012 = (f12 - f01) / (p[2] - p[0]);
  if (!(std::abs(f012) > 0.0) || !std::isfinite(f012)) return p[1];
  const double vertex = 0.5 * (p[0] + p[1]) - f01 / (2.0 * f012);
  return vertex >= p[0] && vertex <= p[2] ? vertex : p[1];
}

double hermiteTurn(double pa, double la, double ra, double pb, double lb, double rb, double fallback) {
  const double h = pb - pa, m0 = h * ra, m1 = h * rb;
  // λ(t) = (2t³ − 3t² + 1) la + (t³ − 2t² + t) m0 + (−2t³ + 3t²) lb + (t³ − t²) m1, t ∈ [0, 1]; λ'(t) = A t² + B t + C.
  const double A = 6.0 * la + 3.0 * m0 - 6.0 * lb + 3.0 * m1, B = -6.0 * la - 4.0 * m0 + 6.0 * lb - 2.0 * m1, C = m0;
  double t = std::nan("");
  if (std::abs(A) <= 1e-14 * (std::abs(B) + std::abs(C))) {
    if (B != 0.0) t = -C / B;
  } else {
    const double disc = B * B - 4.0 * A * C;
    if (disc >= 0.0) {
      const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
      for (double r : {q / A, q != 0.0 ? C / q : std::nan("")})
        if (r >= 0.0 && r <= 1.0) t = r;
    }
  }
  if (!(t >= 0.0 && t <= 1.0) || !std::isfinite(h)) return fallback;
  const HermiteBasis b = hermiteBasis(t);
  const double value = b.h00 * la + b.h10 * m0 + b.h01 * lb + b.h11 * m1;
  return std::isfinite(value) ? value : fallback;
}

double limitLoadFactor(const double p[3], const double l[3]) {
  const double s = parabolaVertex(p, l);
  if (s == p[1]) return l[1];
  const double f01 = (l[1] - l[0]) / (p[1] - p[0]), f12 = (l[2] - l[1]) / (p[2] - p[1]);
  const double f012 = (f12 - f01) / (p[2] - p[0]);
  return l[0] + f01 * (s - p[0]) + f012 * (s - p[0]) * (s - p[1]);
}

namespace {

/// Path control's bifurcations (BifurcationPoint): successive known negative-pivot counts that differ where no
/// limit point lies at either step (a limit point changes the count by itself, at the turn).
std::vector<BifurcationPoint> bifurcationPoints(const StaticsResult& r) {
  std::vector<BifurcationPoint> points;
  const LoadStepResult* last = nullptr;  // the last step with a known count
  for (const LoadStepResult& s : r.steps) {
    if (s.negativePivots < 0) continue;
    if (last != nullptr && s.negativePivots != last->negativePivots) {
      const bool atLimit = std::any_of(r.limitPoints.begin(), r.limitPoints.end(), [&](const LimitPoint& l) {
        return l.step >= last->step && l.step <= s.step;
      });
      if (!atLimit) points.push_back({s.step, last->loadFactor, s.loadFactor, last->negativePivots, s.negativePivots});
    }
    last = &s;
  }
  return points;
}

/// A branch switch that arc length made (LoadSteppingOptions::branchSwitching): followPath follows the new branch.
struct PendingSwitch {
  BranchSwitchResult sw;
  std::vector<double> stops;  // the path's stops (followNewBranch keeps those after the landing)
  double increment = 0.0;
  int cuts = 0;
  double landingParameter = 0.0;  // the landing's arc length from the path's start
};

/// followPath without its bifurcations and without following a switched branch (the loop returns from several
/// places; followPath adds both once).
StaticsResult tracePath(Objective& objective, const LoadFactorHooks& loads, Eigen::VectorXd& x,
                        const LoadSteppingOptions& o, const LoadStepCallback& callback,
                        std::optional<PendingSwitch>& pending) {
  const PathFollowingOptions& po = o.path;
  const bool arc = po.control == PathControl::ArcLength;
  checkPathOption(po.control != PathControl::Load, "control", 0, "load control is not path following");
  checkPathOption(po.maxSteps >= 1 && po.maxSteps <= 10000000, "maxSteps", po.maxSteps, "must be in 1..1e7");
  checkPathOption(std::isfinite(po.loadScaling) && po.loadScaling >= 0.0, "loadScaling", po.loadScaling,
                  "must be >= 0");
  if (!objective.finalized()) objective.finalize();
  const std::vector<char>& fixed = objective.fixedDof();
  if (!arc) {
    checkPathOption(po.controlledDof >= 0 && po.controlledDof < objective.numDofs(), "controlledDof", po.controlledDof,
          "must be a dof of the shell (3 x vertex + component)");
    checkPathOption(!fixed[static_cast<std::size_t>(po.controlledDof)], "controlledDof", po.controlledDof,
          "is a fixed dof: displacement control needs a free one");
    checkPathOption(std::isfinite(po.displacement) && po.displacement != 0.0, "displacement", po.displacement,
          "must be finite and non-zero");
  }
  const double start = o.startLoadFactor, target = o.targetLoadFactor;
  const std::vector<double> stops = arc ? pathStops(start, target, o.levels) : pathStops(0.0, 1.0, o.levels);
  const double eps = 1e-12 * std::max({1.0, std::abs(target), std::abs(start)});
  const int order = std::max(1, o.predictorOrder);

  StaticsResult result;
  result.activeTerms = objective.activeTermNames();
  IndefiniteFactor factor;
  const EvalOptions evalOptions{o.newton.derivatives, PsdProjection::None, o.newton.bendingHessian};

  // The start's tangent t = K⁻¹ q: the first predictor, and the scale that turns λ increments into arc lengths.
  double lambda = start;
  objective.applyPrescribed(lambda, x);
  loads.set(lambda);
  Eigen::VectorXd g, t;
  objective.evaluate(x, &g, true, evalOptions);
  if (!g.allFinite() || !factor.factorize(objective.assembler().matrix(), objective.assembler().patternVersion())) {
    result.message = "path following: the tangent stiffness at the start cannot be factored (" + factor.message() + ")";
    return result;
  }
  const Eigen::VectorXd q0 = loadVector(objective, loads, x, lambda, g, evalOptions);
  if (!factor.solve(q0, t)) {
    result.message = "path following: the start's tangent is not finite";
    return result;
  }
  objective.zeroFixed(t);
  int lastPivots = factor.negativePivots();  // at the last path point (branch switching)
  const double loadWeight = arc ? po.loadScaling * po.loadScaling * freeDot(q0, q0, fixed) : 0.0;
  checkPathOption(std::isfinite(loadWeight), "loadScaling", po.loadScaling,
                  "too large: the constraint's load term psi^2 |q|^2 is not finite for these loads");
  const double unit = std::sqrt(freeDot(t, t, fixed) + loadWeight);  // ds/dλ at the start
  if (!(unit > 0.0) || !std::isfinite(unit)) {
    result.message = "path following: the loads do not move the shell (no load vector at the start)";
    return result;
  }
  if (!arc && !(std::abs(t[po.controlledDof]) > 0.0)) {
    result.message = "path following: the loads do not move the controlled dof at the start";
    return result;
  }
  // Arc length per unit of `increment`: ds/dλ at the start, unless the start is so soft that the first increment
  // along its tangent would move some vertex by more than kFirstMove of the shell's size (a sheet as flexible as
  // cloth under its weight: the linear response to a level is kilometres, and every correction from there fails);
  // then the first increment moves it by that much, and λ follows from the corrector.
  double scale = unit;
  if (arc) {
    double largest = 0.0;
    Eigen::Vector3d low = Eigen::Vector3d::Constant(HUGE_VAL), high = -low;
    for (Eigen::Index v = 0; v + 2 < x.size(); v += 3) {
      largest = std::max(largest, t.segment<3>(v).norm());
      low = low.cwiseMin(x.segment<3>(v));
      high = high.cwiseMax(x.segment<3>(v));
    }
    const double size = (high - low).norm(), first = std::min(o.initialIncrement, o.maxIncrement) * largest;
    if (first > kFirstMove * size && size > 0.0) scale = unit * kFirstMove * size / first;
  }
  const double direction = target >= start ? 1.0 : -1.0;
  const double x0 = arc ? 0.0 : x[po.controlledDof];
  auto distance = [&](const Eigen::VectorXd& xa, double la, const PathPoint& b) {
    const Eigen::VectorXd d = xa - b.x;
    return std::sqrt(freeDot(d, d, fixed) + loadWeight * (la - b.lambda) * (la - b.lambda));
  };

  // The energy identity (LoadJump, solvers/path_energy.h), from the first path point on: a step whose energy change
  // the loads' work along the path does not explain jumped to another branch (arc length cuts it, displacement
  // control reports it).
  const Eigen::VectorXd pathStart = x;
  std::optional<PathEnergy> lastEnergy;  // at the last path point
  Eigen::VectorXd lastTangent = t;       // K⁻¹q there (arc length, or with detectJumps; empty: none)
  // The smallest increment, in the units of `increment`. Arc length: λ along the start's tangent (scale), so where
  // the path has stiffened since (dλ/dp grown: a sheet as flexible at rest as cloth, |K⁻¹q| ~ 100 times its later
  // value) the floor is scaled to stay minIncrement in λ along the current tangent; it never rises above
  // minIncrement.
  double minStep = o.minIncrement;
  // The largest increment, in the same units: maxIncrement, lowered by the same factor where the path has stiffened
  // (kLambdaMargin of it: the increment's λ along the current tangent stays within maxIncrement, which a
  // correction may not exceed; without it the slit annular plate's scene cut 27 of its 98 steps for that).
  double maxStep = o.maxIncrement;
  // dλ/dp at a point with tangent t, for the increment (du, dl) that leaves or reaches it (its sign, arc length).
  auto loadRate = [&](const Eigen::VectorXd& tangent, const Eigen::VectorXd& du, double dl) {
    if (!arc) return po.displacement / tangent[po.controlledDof];
    const double along = freeDot(tangent, du, fixed) + loadWeight * dl;
    return (along >= 0.0 ? 1.0 : -1.0) / std::sqrt(freeDot(tangent, tangent, fixed) + loadWeight);
  };
  // The tangent at an equilibrium just corrected, on the corrector's last factor (made at or next to it), from the
  // gradient the corrector converged on.
  auto tangentAt = [&](const Eigen::VectorXd& at, double l, const PathCorrection& pc, Eigen::VectorXd& tangent) {
    if (pc.gradient.size() != at.size()) return false;
    const Eigen::VectorXd q = loadVector(objective, loads, at, l, pc.gradient, evalOptions);
    if (!factor.solve(q, tangent) || !tangent.allFinite()) return false;
    objective.zeroFixed(tangent);
    return arc ? freeDot(tangent, tangent, fixed) + loadWeight > 0.0 : std::abs(tangent[po.controlledDof]) > 0.0;
  };

  // The stops between two path points' λ (the first excluded, the second included).
  auto crossedLevels = [&](double from, double to) {
    std::vector<double> crossed;
    for (double level : stops) {
      const bool atNew = std::abs(level - to) <= eps, atLast = std::abs(level - from) <= eps;
      if (!atLast && (atNew || (level - from) * (level - to) < 0.0)) crossed.push_back(level);
    }
    return crossed;
  };

  std::deque<PathPoint> history = {{0.0, start, x, -1}};  // path points, newest first
  double increment = std::min(o.initialIncrement, o.maxIncrement);  // in λ (arc) or τ units
  std::size_t nextStop = 0;
  int cuts = 0, pathPoints = 0;
  std::vector<std::string> missed;
  std::deque<PathPoint> recent = {{0.0, start, Eigen::VectorXd(), -1}};  // the last three path points, oldest first

  auto emit = [&](double l, const Eigen::VectorXd& xs, double p, bool atLevel, PathCorrection& pc) {
    LoadStepResult step;
    step.step = static_cast<int>(result.steps.size());
    step.loadFactor = l;
    step.atLevel = atLevel;
    step.x = xs;
    step.pathParameter = p;
    step.negativePivots = pc.negativePivots;
    step.cuts = cuts;
    step.summary = std::move(pc.summary);
    result.steps.push_back(std::move(step));
    result.loadFactor = l;
    loads.set(l);  // the callback sees the loads at the step's λ (a landing or the energy check moved them)
    loads.accept(xs);
    return !callback || callback(result.steps.back());
  };
  auto stopByCallback = [&](double l) {
    result.stopped = true;
    result.message = "stopped by the callback at lambda = " + std::to_string(l);
    return result;
  };

  for (;;) {
    if (pathPoints >= po.maxSteps) {
      std::ostringstream s;
      s << toString(po.control) << " control: stopped after " << po.maxSteps << " path points (maxSteps) at lambda = "
        << history.front().lambda;
      result.message = s.str();
      x = history.front().x;
      loads.set(history.front().lambda);
      return result;
    }
    const PathPoint& last = history.front();
    double pNext = 0.0;
    bool landing = false;
    if (arc) {
      pNext = last.p + increment * scale;
    } else {
      const double stop = stops[nextStop], remaining = stop - last.p;
      landing = remaining <= increment * (1.0 + 1e-9);
      pNext = landing ? stop : last.p + (remaining < 2.0 * increment ? 0.5 * remaining : increment);
    }
    Eigen::VectorXd trial;
    double trialLambda = 0.0;
    if (history.size() == 1) {
      const double dl = arc ? direction * (pNext - last.p) / unit
                            : (pNext - last.p) * po.displacement / t[po.controlledDof];
      trial = last.x + dl * t;
      trialLambda = last.lambda + dl;
    } else {
      extrapolate(history, pNext, trial, trialLambda);
    }
    PathConstraint c;
    if (arc) {
      c.kind = PathConstraint::Kind::ArcLength;
      c.anchor = &last.x;
      c.anchorLoadFactor = last.lambda;
      c.radius = distance(trial, trialLambda, last);
      c.loadWeight = loadWeight;
    } else {
      c.kind = PathConstraint::Kind::Displacement;
      c.dof = po.controlledDof;
      c.value = x0 + pNext * po.displacement;
      trial[c.dof] = c.value;
    }
    PathCorrection pc = correctOnPath(objective, loads, factor, trial, trialLambda, c, o.newton);
    result.newtonIterations += pc.summary.iterations;
    bool ok = pc.summary.converged();
    if (ok && arc && std::abs(trialLambda - last.lambda) > o.maxIncrement * (1.0 + 1e-9)) {
      // As in load control, no step changes λ by more than maxIncrement: the start tangent that turns λ increments
      // into arc lengths can be far steeper than the path later on (a branch leaving a bifurcation), and a long
      // step can land on another branch.
      ok = false;
      pc.summary.reason = TerminationReason::Stalled;
      pc.summary.message = "the correction changed lambda by more than maxIncrement";
    }
    if (ok && arc && history.size() >= 2) {
      const Eigen::VectorXd du = trial - last.x, previous = last.x - history[1].x;
      const double dl = trialLambda - last.lambda, dlPrevious = last.lambda - history[1].lambda;
      const double along = freeDot(du, previous, fixed) + loadWeight * dl * dlPrevious;
      const double norms = std::sqrt((freeDot(du, du, fixed) + loadWeight * dl * dl) *
                                     (freeDot(previous, previous, fixed) + loadWeight * dlPrevious * dlPrevious));
      if (!(along >= kMinCosine * norms)) {
        ok = false;
        pc.summary.reason = TerminationReason::Stalled;
        pc.summary.message = along <= 0.0 ? "the correction turned back along the path"
                                          : "the correction turned more than 60 degrees from the last increment";
      }
    }
    if (!ok) {
      pc.summary.trace.clear();
      result.failedSolves.push_back(pc.summary);
      ++cuts;
      ++result.totalCuts;
      increment = 0.5 * (arc ? increment : pNext - last.p);
      if (increment < minStep) {
        loads.set(last.lambda);
        x = last.x;
        std::ostringstream s;
        s << toString(po.control) << " control: the step from lambda = " << last.lambda << " failed ("
          << toString(pc.summary.reason) << ": " << pc.summary.message << ") with the increment cut below "
          << o.minIncrement << "; stopped there";
        result.message = s.str();
        result.loadFactor = last.lambda;
        return result;
      }
      continue;
    }
    const int iterations = pc.summary.iterations;
    const double pNew = arc ? last.p + distance(trial, trialLambda, last) : pNext;

    // The energy identity over the step (the first step is not checked, as under load control: the start need not
    // be an equilibrium). Arc length cuts a jump while the increment can be halved: a smooth step's mismatch falls
    // with the step against the work (as Δp², or Δp where λ turns within it), a jump's does not, so only a jump that
    // the smallest increment cannot resolve is kept, and reported. Displacement control reports its jumps without
    // cutting: they are snap-backs, which no smaller step passes (the corrections beyond one fail to converge).
    std::optional<PathEnergy> energy;
    Eigen::VectorXd tangent;
    bool jumped = false;
    PathMismatch mismatch;
    if ((arc || o.detectJumps) && !tangentAt(trial, trialLambda, pc, tangent)) tangent.resize(0);
    const Eigen::VectorXd du = trial - last.x;
    const double dl = trialLambda - last.lambda;
    if (o.detectJumps && tangent.size() > 0) {
      energy = pathEnergy(objective, loads, trial, trialLambda, pathStart, evalOptions, loadRate(tangent, du, dl));
      if (lastEnergy) {
        PathEnergy before = *lastEnergy;
        before.loadRate = loadRate(lastTangent, du, dl);
        mismatch = arc ? tangentMismatch(before, *energy, pNew - last.p)
                       : chordMismatch(before, *energy, ChordWork::OverDisplacement);
        jumped = mismatch.work > 0.0 && std::abs(mismatch.released) > LoadJump::kRatio * mismatch.work;
      }
      loads.set(trialLambda);
    }
    const double halved = 0.5 * (arc ? increment : pNext - last.p);
    // A converged step that is not kept: recorded as a failed attempt, and the increment halved.
    auto cutConverged = [&](const char* why) {
      pc.summary.reason = TerminationReason::Stalled;
      pc.summary.message = why;
      pc.summary.trace.clear();
      result.failedSolves.push_back(pc.summary);
      ++cuts;
      ++result.totalCuts;
      increment = halved;
    };
    if (jumped && arc && halved >= minStep) {
      cutConverged("the step's energy change differs from the loads' work along a continuous path (a jump to "
                   "another branch)");
      continue;
    }
    // A bifurcation (branchSwitching): the step left a stable point for one with negative eigenvalues while λ kept
    // its direction (dλ/dp has one sign at both ends, so no limit point lies between), as on a straight column
    // compressed past its buckling load. Load control's switch (solvers/branch_switching.h) takes the stable
    // crossing branch, and followPath follows it. A step that also crosses a level is cut first, so that levels
    // below the bifurcation are landed on the fundamental branch and those above it on the new one.
    if (arc && o.branchSwitching && !jumped && lastPivots == 0 && pc.negativePivots > 0 && tangent.size() > 0 &&
        lastTangent.size() > 0 && loadRate(lastTangent, du, dl) * loadRate(tangent, du, dl) > 0.0) {
      if (!crossedLevels(last.lambda, trialLambda).empty() && halved >= minStep) {
        cutConverged("a bifurcation within a step that crosses a level (cut before the switch)");
        continue;
      }
      NewtonSolver newton(objective, o.newton);
      IndefiniteFactor stability;  // the stability counts' factor (solvers/stability_check.h)
      BranchSwitchResult sw = switchBranch(newton, loads, stability, o.branchSwitch, last.lambda, last.x, trialLambda,
                                           trial);
      result.newtonIterations += sw.newtonIterations;
      if (sw.switched) {
        const double landingP = last.p + distance(sw.x, sw.loadFactor, last);
        pending = PendingSwitch{std::move(sw), stops, increment, cuts, landingP};
        return result;
      }
      result.branchSwitchFailure = switchFailure(sw);
      loads.set(trialLambda);
    }
    if (jumped)  // kept (displacement control, or arc length at its smallest increment): the steps emitted next
                 // land after the jump
      result.loadJumps.push_back({static_cast<int>(result.steps.size()), last.lambda, trialLambda, mismatch.released,
                                  std::abs(mismatch.released) / mismatch.work});

    // Arc length: land on every requested λ crossed between the last path point and this one.
    bool reachedTarget = false;
    if (arc) {
      std::vector<double> crossed = crossedLevels(last.lambda, trialLambda);
      const double towards = trialLambda >= last.lambda ? 1.0 : -1.0;
      std::sort(crossed.begin(), crossed.end(), [&](double a, double b) { return towards * a < towards * b; });
      // Each landing is a load-controlled correction from the cubic Hermite interpolant in λ between the two path
      // points, with their tangents dx/dλ = K⁻¹q, where λ is monotone between them (dλ/dp of one sign at both
      // ends); from the chord otherwise. One that fails cuts the whole step while the increment can still be
      // halved (a shorter chord starts closer); only then is the level reported missed.
      struct Landing {
        double level, p;
        Eigen::VectorXd x;
        PathCorrection correction;
      };
      std::vector<Landing> landings;
      bool cutStep = false;
      const bool hermite = tangent.size() > 0 && lastTangent.size() > 0 &&
                           loadRate(lastTangent, du, dl) * loadRate(tangent, du, dl) > 0.0;
      for (double level : crossed) {
        const double f = (level - last.lambda) / (trialLambda - last.lambda);
        Landing l{level, last.p + f * (pNew - last.p), last.x + f * (trial - last.x), {}};
        if (hermite) l.x += hermiteBend(last.x, trial, lastTangent, tangent, dl, f, objective);
        double ll = level;
        PathConstraint held;
        held.kind = PathConstraint::Kind::LoadFactor;
        held.loadFactor = level;
        l.correction = correctOnPath(objective, loads, factor, l.x, ll, held, o.newton);
        result.newtonIterations += l.correction.summary.iterations;
        if (!l.correction.summary.converged()) {
          l.correction.summary.trace.clear();
          result.failedSolves.push_back(l.correction.summary);
          if (0.5 * increment >= minStep) {
            cutStep = true;
            break;
          }
          std::ostringstream s;
          s << level << " (" << l.correction.summary.message << ")";
          missed.push_back(s.str());
          continue;
        }
        landings.push_back(std::move(l));
      }
      if (cutStep) {
        ++cuts;
        ++result.totalCuts;
        increment *= 0.5;
        continue;
      }
      for (Landing& l : landings) {
        if (!emit(l.level, l.x, l.p, true, l.correction)) {
          x = l.x;
          return stopByCallback(l.level);
        }
        cuts = 0;
        if (std::abs(l.level - target) <= eps) {
          x = l.x;
          reachedTarget = true;
          break;
        }
      }
    }
    if (reachedTarget) break;

    const bool crossedTarget = arc && direction * (trialLambda - target) > eps;
    if (!emit(trialLambda, trial, pNew, landing, pc)) {
      x = trial;
      return stopByCallback(trialLambda);
    }
    cuts = 0;
    ++pathPoints;
    lastEnergy = energy;
    lastPivots = pc.negativePivots;
    if (arc && tangent.size() > 0) {
      const double stiffening = std::max(1.0, scale * std::abs(loadRate(tangent, du, dl)));
      if (std::isfinite(stiffening)) {  // a vanishing tangent (no load vector there) keeps the last bounds
        minStep = o.minIncrement / stiffening;
        maxStep = kLambdaMargin * o.maxIncrement / stiffening;
      }
    }
    lastTangent = std::move(tangent);
    const double rateHere = lastTangent.size() > 0 ? loadRate(lastTangent, du, dl) : std::nan("");
    history.push_front(PathPoint{pNew, trialLambda, trial, result.steps.back().step, rateHere});
    if (static_cast<int>(history.size()) > order + 1) history.pop_back();
    // A turn of λ over the last three path points.
    recent.push_back(history.front());
    recent.back().x.resize(0);
    if (recent.size() > 3) recent.pop_front();
    if (recent.size() == 3) {
      const double before = recent[1].lambda - recent[0].lambda, after = recent[2].lambda - recent[1].lambda;
      if (before * after < 0.0) {
        const double p[3] = {recent[0].p, recent[1].p, recent[2].p};
        const double l[3] = {recent[0].lambda, recent[1].lambda, recent[2].lambda};
        double turn = limitLoadFactor(p, l);
        // With the tangents' dλ/dp at both ends of the interval where it changes sign, the turn is the extremum of
        // the cubic Hermite interpolant there: exact for a cubic λ(p), where the parabola is exact for a quadratic.
        for (int i = 0; i < 2; ++i)
          if (recent[i].rate * recent[i + 1].rate < 0.0) {
            turn = hermiteTurn(recent[i].p, recent[i].lambda, recent[i].rate, recent[i + 1].p, recent[i + 1].lambda,
                               recent[i + 1].rate, turn);
            break;
          }
        result.limitPoints.push_back({recent[1].step, turn, before > 0.0});
      }
    }
    const double factorUp =
        std::clamp(std::sqrt(static_cast<double>(o.easyIterations) / std::max(1, iterations)), 0.5, o.growth);
    increment = std::clamp(increment * factorUp, minStep, std::max(minStep, maxStep));
    if (crossedTarget) {
      // The target was passed but its landing failed: the path stops beyond it, not completed.
      x = trial;
      std::ostringstream s;
      s << "arc-length control passed the target lambda = " << target << " but could not land on it";
      result.message = s.str();
      return result;
    }
    if (!arc && landing && ++nextStop == stops.size()) {
      x = trial;
      break;
    }
  }
  result.completed = true;
  std::ostringstream s;
  s << toString(po.control) << " control: reached " << (arc ? "lambda = " : "tau = 1, lambda = ") << result.loadFactor
    << " in " << result.steps.size() << " steps (" << result.totalCuts << " cuts, " << result.newtonIterations
    << " Newton iterations, " << result.limitPoints.size() << " limit points)";
  for (const LoadJump& j : result.loadJumps)
    s << "; the equilibrium changed abruptly between lambda = " << j.loadFactorBefore << " and " << j.loadFactorAfter
      << (arc ? " at the smallest increment" : " (a snap-back, which displacement control jumps over)")
      << " (energy released " << j.energyReleased << " J)";
  if (!missed.empty()) {
    s << "; levels not landed on:";
    for (const std::string& m : missed) s << " " << m;
  }
  result.message = s.str();
  return result;
}

}  // namespace

StaticsResult followPath(Objective& objective, const LoadFactorHooks& loads, Eigen::VectorXd& x,
                         const LoadSteppingOptions& o, const LoadStepCallback& callback) {
  std::optional<PendingSwitch> pending;
  StaticsResult result = tracePath(objective, loads, x, o, callback, pending);
  result.bifurcationPoints = bifurcationPoints(result);
  if (pending)
    followNewBranch(objective, loads, x, o, callback, pending->stops, pending->increment, pending->cuts, pending->sw,
                    result, pending->landingParameter);
  return result;
}

void followNewBranch(Objective& objective, const LoadFactorHooks& loads, Eigen::VectorXd& x,
                     const LoadSteppingOptions& o, const LoadStepCallback& callback, const std::vector<double>& stops,
                     double increment, int cuts, BranchSwitchResult& sw, StaticsResult& result,
                     double landingParameter) {
  x = sw.x;
  loads.accept(x);
  LoadStepResult landing;
  landing.step = static_cast<int>(result.steps.size());
  landing.loadFactor = sw.loadFactor;
  landing.pathParameter = landingParameter;
  landing.x = x;
  landing.summary = std::move(sw.summary);
  landing.cuts = cuts;
  landing.negativePivots = 0;
  result.steps.push_back(std::move(landing));
  result.loadFactor = sw.loadFactor;
  const std::size_t switchIndex = result.branchSwitches.size();
  result.branchSwitches.push_back({result.steps.back().step, sw.stableLoadFactor, sw.unstableLoadFactor,
                                   sw.negativeEigenvalues, sw.loadFactor});
  if (callback && !callback(result.steps.back())) {
    result.stopped = true;
    result.message = "stopped by the callback at lambda = " + std::to_string(sw.loadFactor);
    return;
  }
  LoadSteppingOptions rest = o;
  rest.path.control = PathControl::ArcLength;
  rest.startLoadFactor = sw.loadFactor;
  rest.initialIncrement = std::clamp(increment, o.minIncrement, o.maxIncrement);
  rest.levels.clear();
  const double direction = o.targetLoadFactor >= sw.loadFactor ? 1.0 : -1.0;
  const double eps = 1e-12 * std::max({1.0, std::abs(o.targetLoadFactor), std::abs(sw.loadFactor)});
  for (double s : stops)
    if (direction * (s - sw.loadFactor) > eps) rest.levels.push_back(s);
  const int offset = static_cast<int>(result.steps.size());
  const bool arc = o.path.control == PathControl::ArcLength;  // the tail's arc length continues the path's
  const LoadStepCallback shifted = [&](const LoadStepResult& s) {
    if (!callback) return true;
    LoadStepResult renumbered = s;
    renumbered.step += offset;
    if (arc) renumbered.pathParameter += landingParameter;
    return callback(renumbered);
  };
  StaticsResult tail = followPath(objective, loads, x, rest, shifted);
  for (LoadStepResult& s : tail.steps) {
    s.step += offset;
    if (arc) s.pathParameter += landingParameter;
    result.steps.push_back(std::move(s));
  }
  for (LimitPoint l : tail.limitPoints) {
    l.step += offset;
    result.limitPoints.push_back(l);
  }
  for (BifurcationPoint b : tail.bifurcationPoints) {
    b.step += offset;
    result.bifurcationPoints.push_back(b);
  }
  for (LoadJump j : tail.loadJumps) {
    j.step += offset;
    result.loadJumps.push_back(j);
  }
  for (BranchSwitchPoint b : tail.branchSwitches) {  // the new branch bifurcated again
    b.step += offset;
    result.branchSwitches.push_back(b);
  }
  if (!tail.branchSwitchFailure.empty()) result.branchSwitchFailure = tail.branchSwitchFailure;
  result.totalCuts += tail.totalCuts;
  result.newtonIterations += tail.newtonIterations;
  for (SolverSummary& f : tail.failedSolves) result.failedSolves.push_back(std::move(f));
  result.completed = tail.completed;
  result.stopped = tail.stopped;
  if (!tail.steps.empty()) result.loadFactor = tail.loadFactor;
  std::ostringstream s;
  const BranchSwitchPoint& b = result.branchSwitches[switchIndex];
  s << toString(o.path.control) << " control switched at a bifurcation between lambda = " << b.stableLoadFactor
    << " and " << b.unstableLoadFactor << " to the stable branch (landed at lambda = " << b.loadFactor << "), then "
    << tail.message;
  result.message = s.str();
}

}  // namespace jetshell
