#include "solvers/newton.h"

#include "solvers/timer.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace jetshell {

double infNorm(const Eigen::VectorXd& v) { return v.size() == 0 ? 0.0 : v.lpNorm<Eigen::Infinity>(); }

double largestVertexNorm(const Eigen::VectorXd& v) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i + 2 < v.size(); i += 3) largest = std::max(largest, v.segment<3>(i).norm());
  return largest;
}

namespace {

bool sameLinearOptions(const LinearSolverOptions& a, const LinearSolverOptions& b) {
  return a.type == b.type && a.preconditioner == b.preconditioner && a.autoDirectMaxDofs == b.autoDirectMaxDofs &&
         a.cgRelativeTolerance == b.cgRelativeTolerance && a.cgMaxIterations == b.cgMaxIterations &&
         a.maxRegularizations == b.maxRegularizations && a.ordering == b.ordering && a.blasThreads == b.blasThreads &&
         a.lagRefactorIterations == b.lagRefactorIterations && a.oneRing == b.oneRing &&
         a.oneRingParts == b.oneRingParts;
}

/// max_i Σ_j |H_ij| |x_j| over the free dofs, from the upper triangle of the symmetric H: the force error that
/// rounding every position to ε|x| can cause, divided by ε.
double absoluteHessianTimesPositions(SymmetricProduct& product, const Eigen::SparseMatrix<double>& H,
                                     const Eigen::VectorXd& x, const std::vector<char>& fixed) {
  Eigen::VectorXd y;
  product.applyAbsolute(H, x.cwiseAbs(), y);
  double m = 0.0;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (!fixed[static_cast<std::size_t>(i)]) m = std::max(m, y[i]);
  return m;
}

/// The options assemble the energy's own Hessian: nothing projected, no term's curvature left out.
bool isTrueHessian(const EvalOptions& e) {
  return e.projection == PsdProjection::None && e.hessianModel == HessianModel::Exact &&
         e.frictionHessian == FrictionHessian::Exact;
}

/// Mean |H_ii| of the assembled upper triangle (the steepest-descent fallback's scale).
double meanDiagonal(const Eigen::SparseMatrix<double>& H) {
  const Eigen::VectorXd d = H.diagonal();
  const double m = d.cwiseAbs().mean();
  return m > 0.0 && std::isfinite(m) ? m : 1.0;
}

}  // namespace

NewtonSolver::NewtonSolver(Objective& objective, const NewtonOptions& options)
    : objective_(objective), options_(options), linear_(makeLinearSolver(options.linear, objective.numDofs())) {}

void NewtonSolver::setOptions(const NewtonOptions& options) {
  const bool keepLinear = sameLinearOptions(options.linear, options_.linear);
  options_ = options;
  if (!keepLinear) {
    linear_ = makeLinearSolver(options_.linear, objective_.numDofs());
    factorReusable_ = false;
  }
}

SolverSummary NewtonSolver::minimize(Eigen::VectorXd& x) {
  const Timer total;
  const NewtonOptions& o = options_;
  SolverSummary s;
  s.minimizer = "newton";
  s.linearSolver = linear_->name();
  const int analysesBefore = linear_->symbolicAnalyses();
  const EvalOptions projected{o.derivatives, o.projection, o.bendingHessian, 0, o.frictionHessian};
  // The "exact" Hessian: unprojected, or with exactHessianFirst only the small blocks projected.
  const EvalOptions exact =
      o.exactHessianFirst && o.exactFirstProjectedDofs > 0
          ? EvalOptions{o.derivatives, o.projection, o.bendingHessian, o.exactFirstProjectedDofs, o.frictionHessian}
          : EvalOptions{o.derivatives, PsdProjection::None, o.bendingHessian, 0, o.frictionHessian};
  const bool adaptive = o.exactHessianNearSolution && o.projection != PsdProjection::None;
  // With exactHessianFirst, where the last full step agreed with its model: the whole Hessian as it is
  // (NewtonOptions::unprojectedNearSolution).
  const EvalOptions unprojected{o.derivatives, PsdProjection::None, o.bendingHessian, 0, o.frictionHessian};
  bool twoTier = adaptive && o.exactHessianFirst && o.exactFirstProjectedDofs > 0 && o.unprojectedNearSolution &&
                 unprojectedSkips_ == 0;
  if (unprojectedSkips_ > 0) --unprojectedSkips_;
  bool unprojectedHeld = false;  // an unprojected try of this solve was positive definite
  // The projected assembly an indefinite exact-first try falls back to (NewtonOptions::fallbackBendingHessian).
  EvalOptions fallback = projected;
  if (adaptive && o.exactHessianFirst && o.bendingHessian == HessianModel::Exact)
    fallback.hessianModel = o.fallbackBendingHessian;
  // The assembly of each tier: exact(-first), with twoTier the unprojected one, else the projected fallback.
  auto assemblyOptions = [&](bool withExact, bool withUnprojected) -> const EvalOptions& {
    return withExact ? (withUnprojected ? unprojected : exact) : fallback;
  };
  Objective& obj = objective_;

  Eigen::VectorXd g, d, b, xTrial, gTrial;
  double E = 0.0;
  double r = 0.0;
  double forcing = 0.0, previousGradientNorm = -1.0;  // Eisenstat–Walker state (adaptiveLinearTolerance)
  double newtonStepFraction = 0.0;  // of the last Newton direction, to the current iterate (IterateView)
  enum class Have { Nothing, Gradient, Hessian } have = Have::Nothing;
  bool tryExact = false;     // the last step's full-step model agreed: try the unprojected Hessian
  int exactCooldown = 0;     // iterations to wait before the next try, growing with each fallback
  bool haveExact = false;    // the assembled Hessian is the unprojected one
  bool haveUnprojected = false;  // twoTier: and nothing of it projected
  int exactFallbacks = 0;    // exact-first tries that were indefinite
  double decrementThreshold = 0.0;
  // The residual test's tolerance [N]: residualTolerance × F, or a preset's looser one.
  double scaledTolerance = 0.0, forceScale = 0.0;
  constexpr double kRoundOffFactor = 64.0 * std::numeric_limits<double>::epsilon();
  constexpr double kFloorCeiling = 1e-2;  // a residual above this fraction of F never passes at round-off
  // The round-off floor of the last assembled Hessian (0 while it is below the scaled tolerance), and the residual
  // a round-off pass must reach: min(floor, kFloorCeiling × F).
  double roundOffBound = 0.0;
  auto updateFloor = [&]() {
    const double floor =
        kRoundOffFactor * absoluteHessianTimesPositions(floorProduct_, obj.assembler().matrix(), x, obj.fixedDof());
    s.roundOffFloor = std::isfinite(floor) && floor > scaledTolerance ? floor : 0.0;
    roundOffBound = std::min(s.roundOffFloor, kFloorCeiling * forceScale);
  };

  // Why a residual above 1% of F cannot pass: rounding the positions alone leaves more (said when it stops).
  auto floorNote = [&]() -> std::string {
    if (!(r > kFloorCeiling * forceScale && s.roundOffFloor > kFloorCeiling * forceScale)) return "";
    std::ostringstream m;
    m << "; the residual's round-off floor " << s.roundOffFloor << " N is above 1% of the force scale " << forceScale
      << " N: the loads move the shell by less than its positions' round-off";
    return m.str();
  };

  auto finish = [&](TerminationReason reason, const std::string& message) {
    s.reason = reason;
    if (reason == TerminationReason::Converged && s.convergenceTest.empty()) s.convergenceTest = "residual";
    s.message = message;
    s.finalEnergy = E;
    s.finalResidual = r;
    s.symbolicAnalyses = linear_->symbolicAnalyses() - analysesBefore;
    const bool passedAtStart = reason == TerminationReason::Converged && s.iterations == 0;
    solvesSinceStartPass_ = passedAtStart ? 0 : std::min(solvesSinceStartPass_ + 1, kStartPassMemory);
    if (twoTier && unprojectedHeld && unprojectedFailures_ > 0) --unprojectedFailures_;
    linear_->setRelativeTolerance(0.0);
    // A preconditioner prepared for the last assembly belongs to this solve: later solves on the same linear
    // solver (sensitivities) set up their own.
    linear_->discardPrepared();
    s.totalSeconds = total.seconds();
    return s;
  };
  bool floorPassed = false;  // the current iterate's residual is above the scaled tolerance but within roundOffBound
  auto convergedOnResidual = [&]() {
    std::ostringstream m;
    m << "residual " << r << " N <= " << scaledTolerance << " N (" << o.residualTolerance << " x force scale "
      << forceScale << " N from " << s.forceScaleSource << ")";
    return finish(TerminationReason::Converged, m.str());
  };
  // Overlapped preconditioning (NewtonOptions::overlapPreconditioner). The projected re-assembly after an
  // indefinite try only records the narrow part: its solve factors the whole one-ring part as before. The wide
  // part of a solve's first iteration is the previous solve's last (measured at 10k vertices: with the narrow
  // part alone there, CG took a median 11 iterations instead of 4, and the iteration 113 ms instead of 75).
  // With one thread there is nothing to overlap with: the plain preconditioner of the whole Hessian is better.
  // Nor with moving contacts: measured on the T-shirt, whose pattern changes at almost every iteration, a
  // preconditioner with the wide part of another iterate took 1 283 CG iterations instead of 1 094 over 30
  // steps, and bending on one thread cost more than the factorizations saved (0.86-0.93x the steps per second).
  // There the whole one-ring factor failing is also what sends an indefinite unprojected Hessian to the projected
  // one: with the first iteration's preconditioner the narrow part alone, no fallback fired and the T-shirt's
  // landing went 8.6 mm below the plane instead of 0.5 mm.
  const bool overlap = o.overlapPreconditioner && omp_get_max_threads() >= 2 && !obj.hasMovingStencils();
  auto assemble = [&](bool withExact, bool withUnprojected, IterationRecord& rec, bool factorAhead) {
    const Timer t;
    Objective::NarrowAssembledHook prepare;
    if (overlap)
      prepare = [&](const HessianAssembler& a) {
        return linear_->preparePreconditioner(a.matrix(), a.patternVersion(), factorAhead);
      };
    E = obj.evaluate(x, &g, true, assemblyOptions(withExact, withUnprojected), TermSelection::All, prepare);
    rec.assemblySeconds += t.seconds();
    ++s.energyEvaluations;
    ++s.gradientEvaluations;
    ++s.hessianEvaluations;
    have = Have::Hessian;
    haveExact = withExact;
    haveUnprojected = withExact && withUnprojected;
  };

  // Trial points of the line search; the last one's gradient is reused when it is accepted. The gradient does
  // not depend on the projection.
  double trialAlpha = std::numeric_limits<double>::quiet_NaN();
  bool trialHasGradient = false;
  const LineSearchEvaluator evaluateTrial = [&](double alpha, bool wantGradient) {
    xTrial = x + alpha * d;
    LineSearchPoint p;
    p.energy = obj.evaluate(xTrial, wantGradient ? &gTrial : nullptr, false, projected);
    if (!std::isfinite(p.energy) || (wantGradient && !gTrial.allFinite())) ++s.nonFiniteTrials;
    ++s.energyEvaluations;
    if (wantGradient) {
      ++s.gradientEvaluations;
      p.hasGradient = true;
      p.slope = gTrial.dot(d);
      p.residual = gTrial.norm();
    }
    trialAlpha = alpha;
    trialHasGradient = wantGradient;
    return p;
  };

  bool lastStepReused = false;  // reuseFactor: the last step's direction came from an earlier factor
  double residualBeforeStep = 0.0;
  for (int k = 0;; ++k) {
    IterationRecord rec;
    rec.iteration = k;
    const bool useExact = adaptive && (tryExact || o.exactHessianFirst) && exactCooldown == 0;
    if (exactCooldown > 0) --exactCooldown;
    const bool useUnprojected = twoTier && useExact && tryExact && k >= o.unprojectedFromIteration;
    const bool gradientFirst = k > 0 || (o.gradientFirstStart && solvesSinceStartPass_ < kStartPassMemory);
    const bool mayReuse = o.reuseFactor && factorReusable_;
    if (have == Have::Nothing && ((iterateTest_ && gradientFirst) || mayReuse)) {
      // The iterate test may end the solve here: the gradient first, the Hessian only if it is needed.
      const Timer t;
      E = obj.evaluate(x, &g, false, projected);
      rec.assemblySeconds += t.seconds();
      ++s.energyEvaluations;
      ++s.gradientEvaluations;
      have = Have::Gradient;
    }
    if (have == Have::Nothing) assemble(useExact, useUnprojected, rec, true);
    r = infNorm(g);
    if (lastStepReused && !(r <= o.reuseContraction * residualBeforeStep)) factorReusable_ = false;
    lastStepReused = false;
    if (!std::isfinite(E) || !g.allFinite()) {
      s.assemblySeconds += rec.assemblySeconds;
      return finish(TerminationReason::NonFinite, "non-finite energy or gradient at iteration " + std::to_string(k));
    }
    if (k == 0) {
      s.initialEnergy = E;
      s.initialResidual = r;
      const ForceScale F = obj.forceScale(x, r);
      forceScale = F.value;
      s.forceScale = F.value;
      s.forceScaleSource = F.source;
      scaledTolerance = o.residualTolerance * F.value;
      // Presets that state their own tolerances (the page's: absolute 1e-3 N, relative 1e-6 of the step's first
      // residual) loosen the test to the larger one; the summary records which tolerance held.
      if (o.absoluteResidualTolerance > 0.0) scaledTolerance = std::max(scaledTolerance, o.absoluteResidualTolerance);
      if (o.relativeResidualTolerance > 0.0) scaledTolerance = std::max(scaledTolerance, o.relativeResidualTolerance * r);
      decrementThreshold = o.decrementTolerance * F.value * obj.scales().length;
      s.residualThreshold = scaledTolerance;
      s.decrementThreshold = decrementThreshold;
      if (have == Have::Hessian) updateFloor();
    }
    rec.energy = E;
    rec.residual = r;
    // A residual within the round-off floor passes only with the Newton decrement (below): the floor bounds what
    // rounding may leave, and a smooth residual at it can still carry a real error (measured: the slit ring on
    // 64x1024 quads stopped 0.16% off its equilibrium at a floor 40-500x above the residual that one more
    // iteration reached; on 96x1536, 11% off at λ = 0.1, residual 4.17e-5 N within a floor of 4.18e-5 N).
    floorPassed = r > scaledTolerance && r <= roundOffBound;
    if (r <= scaledTolerance) {
      s.assemblySeconds += rec.assemblySeconds;
      return convergedOnResidual();
    }
    if (iterateTest_) {
      IterateView view{x, g, k, newtonStepFraction, {}};
      if (newtonStepFraction == 1.0 && !s.trace.empty() && s.trace.back().exactHessian) {
        // The last iteration's system, solved again (its record takes the time and CG iterations).
        view.solveLastSystem = [&](const Eigen::VectorXd& rhs, Eigen::VectorXd& y) {
          LinearSolveReport again;
          const bool solved = linear_->solveLastSystem(obj.assembler().matrix(), obj.assembler().patternVersion(),
                                                       rhs, y, kSimplifiedCorrectionTolerance, again);
          s.trace.back().solveSeconds += again.solveSeconds;
          s.trace.back().cgIterations += again.cgIterations;
          s.solveSeconds += again.solveSeconds;
          if (solved) obj.zeroFixed(y);
          return solved;
        };
      }
      const IterateTestResult t = iterateTest_(view);
      if (t.passed) {
        s.assemblySeconds += rec.assemblySeconds;
        std::ostringstream m;
        m << "iterate test: " << t.estimateName << " " << t.estimate << " m <= " << t.threshold << " m; residual " << r << " N";
        s.convergenceTest = "iterate";
        s.iterateEstimate = t.estimateName;
        s.iterateThreshold = t.threshold;
        return finish(TerminationReason::Converged, m.str());
      }
    }
    if (k >= o.maxIterations) {
      s.assemblySeconds += rec.assemblySeconds;
      std::ostringstream m;
      m << "reached " << o.maxIterations << " iterations with residual " << r << " N > " << scaledTolerance << " N";
      m << floorNote();
      return finish(TerminationReason::IterationCap, m.str());
    }
    // Modified Newton: the direction from the last factor, nothing assembled (NewtonOptions::reuseFactor).
    bool reused = false;
    if (o.reuseFactor && factorReusable_ && have != Have::Hessian) {
      const Timer t;
      if (linear_->solveWithLastFactor(obj.assembler().patternVersion(), -g, d)) {
        obj.zeroFixed(d);
        reused = g.dot(d) < 0.0;
      }
      rec.solveSeconds += t.seconds();
      factorReusable_ = reused;
    }
    if (!reused && (have != Have::Hessian || haveExact != useExact || haveUnprojected != useUnprojected))
      assemble(useExact, useUnprojected, rec, true);
    if (!reused) updateFloor();

    // Newton direction. An unprojected Hessian gets no regularization: if it is indefinite, the projected one
    // is the better fix.
    b = -g;
    if (o.adaptiveLinearTolerance) {
      const double gNorm = b.norm();
      const double floorTolerance = o.linear.cgRelativeTolerance, ceiling = std::max(o.maxForcingTerm, floorTolerance);
      if (previousGradientNorm <= 0.0) {
        forcing = ceiling;
      } else {
        const double ratio = gNorm / previousGradientNorm;
        double eta = 0.9 * ratio * ratio;
        const double safeguard = 0.9 * forcing * forcing;  // do not tighten faster than the last term allows
        if (safeguard > 0.1) eta = std::max(eta, safeguard);
        forcing = std::clamp(eta, floorTolerance, ceiling);
      }
      previousGradientNorm = gNorm;
      linear_->setRelativeTolerance(forcing);
    }
    LinearSolveReport lin;
    lin.success = reused;
    if (!reused) lin = linear_->solve(obj.assembler(), b, d, haveExact ? 0 : -1);
    bool exactFailed = haveExact && !lin.success;
    if (haveExact && lin.success) {
      // CG can finish on an indefinite system without meeting negative curvature: a direction that does not
      // descend means the same.
      obj.zeroFixed(d);
      exactFailed = !(g.dot(d) < 0.0);
    }
    if (exactFailed) {
      // Each fallback costs an assembly and a factorization: back off (2, 4, 8, ... iterations) where the
      // unprojected Hessian keeps being indefinite.
      ++s.projectionFallbacks;
      tryExact = false;
      if (haveUnprojected) {
        // Only the unprojected tries back off (NewtonOptions::unprojectedNearSolution): exact-first goes on.
        twoTier = false;
        ++s.unprojectedFallbacks;
        unprojectedFailures_ = std::min(unprojectedFailures_ + 1, 6);
        unprojectedSkips_ = 1 << unprojectedFailures_;
      } else {
        ++exactFallbacks;
        exactCooldown = 1 << std::min(exactFallbacks, 6);
      }
      rec.factorizationSeconds += lin.factorizationSeconds;
      rec.overlappedFactorizationSeconds += lin.preparedSeconds;
      rec.solveSeconds += lin.solveSeconds;
      s.numericFactorizations += lin.numericFactorizations;
      assemble(false, false, rec, false);
      const LinearSolveReport first = lin;
      lin = linear_->solve(obj.assembler(), b, d);
      lin.symbolicAnalysis = lin.symbolicAnalysis || first.symbolicAnalysis;
      lin.cgIterations += first.cgIterations;
      lin.directFallbacks += first.directFallbacks;
      rec.projectionFallback = true;
    }
    s.assemblySeconds += rec.assemblySeconds;
    rec.exactHessian = haveExact;  // false after a fallback: its assembly was the projected one
    rec.unprojected = haveUnprojected;
    rec.factorizationSeconds += lin.factorizationSeconds;
    rec.overlappedFactorizationSeconds += lin.preparedSeconds;
    rec.solveSeconds += lin.solveSeconds;
    rec.regularizations = lin.regularizations;
    if (!reused)
      s.lastHessianPositiveDefinite =
          lin.positiveDefinite && isTrueHessian(assemblyOptions(haveExact, haveUnprojected));
    rec.shift = lin.shift;
    rec.cgIterations = lin.cgIterations;
    rec.directFallbacks = lin.directFallbacks;
    s.directFallbacks += lin.directFallbacks;
    rec.numericFactorizations = lin.numericFactorizations;
    s.numericFactorizations += lin.numericFactorizations;
    s.factorizationSeconds += rec.factorizationSeconds;
    s.solveSeconds += rec.solveSeconds;
    s.regularizations += lin.regularizations;
    if (!lin.success) {
      s.trace.push_back(rec);
      return finish(TerminationReason::LinearSolverFailure, lin.message);
    }
    factorReusable_ = true;
    if (haveExact && !reused) ++s.exactHessianSteps;
    if (haveUnprojected && !reused) {
      unprojectedHeld = true;
      ++s.unprojectedSteps;
    }
    obj.zeroFixed(d);
    double slope = g.dot(d);
    bool newtonDirection = true;
    if (!(slope < 0.0)) {
      newtonDirection = false;
      // Round-off can cost a nearly singular system its descent property; fall back to scaled steepest descent.
      d = g / -meanDiagonal(obj.assembler().matrix());
      obj.zeroFixed(d);
      slope = g.dot(d);
    }
    const double decrement = -0.5 * slope;
    rec.decrement = decrement;
    s.finalDecrement = decrement;
    const double noise = 1e-13 * obj.energyMagnitude();

    const Timer ls;
    // (An old factor's decrement is only an estimate: its step goes through the line search, whose failure, or a
    // residual that does not shrink, brings a fresh factor.)
    // Within the round-off floor, a step that would release less energy than the energy's own round-off is also
    // nothing more to gain (the line search could not see it).
    if ((decrement <= decrementThreshold || (floorPassed && decrement <= noise)) && !reused) {
      // The step releases next to no energy. Take it if it does not raise the energy beyond round-off; then the
      // residual decides. A residual still above its tolerance after such a step will not improve: stalled.
      const LineSearchPoint p = evaluateTrial(1.0, true);
      rec.lineSearchEvaluations = 1;
      bool moved = false;
      // An iterate within the floor is kept unless the step keeps the residual within it.
      const bool keepsFloorPass = !floorPassed || infNorm(gTrial) <= roundOffBound;
      if (std::isfinite(p.energy) && gTrial.allFinite() && p.energy <= E + noise && keepsFloorPass) {
        x = xTrial;
        E = p.energy;
        g = gTrial;
        r = infNorm(g);
        rec.stepLength = 1.0;
        rec.largestMove = largestVertexNorm(d);
        ++s.iterations;
        moved = true;
      }
      rec.lineSearchSeconds = ls.seconds();
      s.lineSearchSeconds += rec.lineSearchSeconds;
      s.trace.push_back(rec);
      if (r <= scaledTolerance) {
        std::ostringstream m;
        m << "residual " << r << " N <= " << scaledTolerance << " N after a step with Newton decrement " << decrement
          << " J";
        return finish(TerminationReason::Converged, m.str());
      }
      // Converged to round-off: the residual is within the round-off floor (an estimate that bounds rounding's
      // residual from above) and within kFloorCeiling × F, and Newton's next step would release no energy.
      // Nothing more can be gained in double precision.
      if (r <= roundOffBound) {
        std::ostringstream m;
        m << "round-off: residual " << r << " N <= " << roundOffBound << " N (the residual's round-off floor "
          << s.roundOffFloor << " N, at most " << kFloorCeiling << " x force scale " << forceScale
          << " N) and Newton decrement " << decrement << " J <= " << std::max(decrementThreshold, noise) << " J";
        s.residualThreshold = roundOffBound;
        s.convergenceTest = "round_off";
        return finish(TerminationReason::Converged, m.str());
      }
      std::ostringstream m;
      m << "stalled: Newton decrement " << decrement << " J <= " << decrementThreshold << " J"
        << (moved ? "" : " (the step raised the energy)") << " but residual " << r << " N > " << scaledTolerance
        << " N" << floorNote();
      return finish(TerminationReason::Stalled, m.str());
    }

    // Step bound (Objective::stepBound; contact): the largest safe fraction of d, from which the search starts,
    // so no contact sample crosses a layer or surface in one iteration.
    const double bound = obj.stepBound(x, d);
    if (bound < 1.0) {
      d *= bound;
      slope *= bound;
    }
    LineSearchOptions lso;
    lso.type = o.lineSearch;
    lso.c1 = o.armijoC1;
    lso.c2 = o.wolfeC2;
    lso.maxEvaluations = o.maxLineSearchEvaluations;
    lso.energyNoise = noise;
    LineSearchPoint start;
    start.energy = E;
    start.slope = slope;
    start.residual = g.norm();
    start.hasGradient = true;
    const LineSearchResult res = lineSearch(lso, start, evaluateTrial);
    rec.lineSearchEvaluations = res.evaluations;
    rec.lineSearchSeconds = ls.seconds();
    s.lineSearchSeconds += rec.lineSearchSeconds;
    if (!res.success && reused) {
      factorReusable_ = false;  // the old factor's direction failed: the same iterate again, with a fresh one
      s.trace.push_back(rec);
      continue;
    }
    if (!res.success) {
      s.trace.push_back(rec);
      return finish(res.allNonFinite ? TerminationReason::NonFinite : TerminationReason::LineSearchFailure,
                    res.message);
    }
    const double alpha = res.point.alpha;
    newtonStepFraction = newtonDirection ? alpha * std::min(bound, 1.0) : 0.0;
    rec.stepLength = alpha;
    rec.largestMove = alpha * largestVertexNorm(d);
    s.trace.push_back(rec);
    ++s.iterations;
    lastStepReused = reused;
    residualBeforeStep = r;
    // The quadratic model predicts a decrease of −½ gᵀd for the full step (with the H that was solved).
    const double ratio = (E - res.point.energy) / (decrement * bound * (2.0 - bound));
    // A predicted decrease within the energy's round-off says nothing either way: the full step is judged alone.
    const bool withinNoise = decrement * bound * (2.0 - bound) <= noise;
    tryExact = alpha == 1.0 && (withinNoise || (ratio >= 0.5 && ratio <= 2.0));
    if (alpha == trialAlpha) {
      x = xTrial;
    } else {
      x += alpha * d;
    }
    E = res.point.energy;
    if (alpha == trialAlpha && trialHasGradient) {
      g = gTrial;
      have = Have::Gradient;
    } else {
      have = Have::Nothing;
    }
  }
}

}  // namespace jetshell
