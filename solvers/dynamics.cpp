#include "solvers/dynamics.h"

#include "core/input_limits.h"

#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace jetshell {

TimeIntegrator timeIntegratorFromString(const std::string& name) {
  if (name == "backward_euler") return TimeIntegrator::BackwardEuler;
  if (name == "bdf2") return TimeIntegrator::BDF2;
  throw InputError("time integrator '" + name + "': expected backward_euler or bdf2");
}

const char* toString(TimeIntegrator t) {
  switch (t) {
    case TimeIntegrator::BackwardEuler: return "backward_euler";
    case TimeIntegrator::BDF2: return "bdf2";
  }
  return "?";
}

namespace {

/// The correction test needs the residual estimate to have fallen at least this much over the last iteration
/// (evidence that Newton contracts).
constexpr double kCorrectionContraction = 0.5;
/// The correction test trusts a correction only while the residual estimate overstates it by at most this
/// factor: the estimate is the error under the inertia alone, so the factor is the stiffness-to-inertia ratio
/// the correction relies on. Measured at every pass (BENCHMARKS.md "Contact", session 33): 7.6-95 on the T-shirt
/// and 6.9-59 on its variant without self-contact, whose crushed, tangled panels also passed at 7e5-5e9 with
/// residuals of 1e4-6e5 N, moved by a Newton step of 0.06-1 µm against that stiffness. A stiffer system that
/// goes over the limit only takes Newton's other tests.
constexpr double kCorrectionOverstatementLimit = 1e4;
/// With contact terms, the correction test's RMS threshold is at least this fraction of the narrowest contact
/// ramp δ: a time-error threshold below it (a shell at rest: ‖x − x̃‖ of micrometres) asks for more than the
/// contact forces resolve.
constexpr double kContactCorrectionFloor = 0.01;

void checkTimeStep(double h) {
  if (!(std::isfinite(h) && h > 0.0)) {
    std::ostringstream s;
    s << "dynamics: timeStep = " << h << ": must be finite and > 0";
    throw InputError(s.str());
  }
}

double checkedMassDamping(const ShellSystem& system, const DynamicsOptions& o) {
  checkTimeStep(o.timeStep);
  if (o.maxCuts < 0 || o.maxCuts > 30) throw InputError("dynamics: maxCuts must lie in [0, 30]");
  if (!(o.extrapolationWaveLimit >= 0.0))  // +∞ allowed: every actor extrapolates
    throw InputError("dynamics: extrapolationWaveLimit must be >= 0 (or infinite), not " +
                     std::to_string(o.extrapolationWaveLimit));
  if (!(o.extrapolationThinLimit >= 0.0))
    throw InputError("dynamics: extrapolationThinLimit must be >= 0 (or infinite), not " +
                     std::to_string(o.extrapolationThinLimit));
  if (!(std::isfinite(o.updateTolerance) && o.updateTolerance >= 0.0))
    throw InputError("dynamics: updateTolerance must be finite and >= 0");
  if (!(std::isfinite(o.contactCorrectionFraction) && o.contactCorrectionFraction >= 0.0 &&
        o.contactCorrectionFraction <= 1.0))
    throw InputError("dynamics: contactCorrectionFraction must be in [0, 1]");
  if (o.contactGuardSolves < 0 || o.contactGuardSolves > 100)
    throw InputError("dynamics: contactGuardSolves must lie in [0, 100]");
  if (!(std::isfinite(o.contactGuardDepth) && o.contactGuardDepth >= 0.0))
    throw InputError("dynamics: contactGuardDepth must be finite and >= 0 (a fraction of the activation distance)");
  if (!(std::isfinite(o.contactGuardPairRatio) && o.contactGuardPairRatio >= 0.0 && o.contactGuardPairRatio <= 1.0))
    throw InputError("dynamics: contactGuardPairRatio must be in [0, 1] (a fraction of the contact distance 2r)");
  if (system.kind() == AnalysisKind::Statics)
    throw InputError("dynamics: the system was built for statics (no inertia)");
  const double alpha = o.massDampingOverride >= 0.0 ? o.massDampingOverride
                                                     : system.material().massDampingCoefficient;
  if (!std::isfinite(alpha)) throw InputError("dynamics: massDampingOverride must be finite");
  if (alpha > 0.0 && !system.massDamping && system.material().density > 0.0)
    throw InputError("dynamics: mass damping requested but the system has no mass_damping term");
  return alpha;
}

/// The Newton options a time step of this system uses: the one-ring filter of its mesh, and no unprojected
/// Hessian near a solution with contact terms (NewtonOptions::unprojectedNearSolution).
NewtonOptions forSystem(NewtonOptions o, const ShellSystem& system) {
  if (o.linear.oneRingParts < 0 || o.linear.oneRingParts > 2)
    throw InputError("dynamics: newton.linear.oneRingParts must be 0 (auto), 1 or 2, not " +
                     std::to_string(o.linear.oneRingParts));
  if (o.linear.preconditioner == Preconditioner::OneRingCholesky && !o.linear.oneRing) {
    o.linear.oneRing = std::make_shared<OneRingFilter>(
        system.mesh().F, system.mesh().numVertices(), oneRingPartsFor(o.linear, system.objective().hasMovingStencils()));
  }
  // Penalty contact's negative curvature leaves the whole Hessian indefinite near most solutions: measured on the
  // T-shirt, 7 unprojected tries fell back in 60 steps even with the solver's back-off, 0.94x the steps per second.
  if (!system.contact.empty()) o.unprojectedNearSolution = false;
  return o;
}

void addTimes(StepReport& r, const SolverSummary& s) {
  r.newtonIterations += s.iterations;
  r.assemblySeconds += s.assemblySeconds;
  r.factorizationSeconds += s.factorizationSeconds;
  r.solveSeconds += s.solveSeconds;
  r.lineSearchSeconds += s.lineSearchSeconds;
}

}  // namespace

bool extrapolatesAcceleration(const ShellSystem& system, Eigen::Index v, double h, const DynamicsOptions& o) {
  return !(h * system.membraneWaveRate()[v] > o.extrapolationWaveLimit &&
           system.edgeOverThickness()[v] > o.extrapolationThinLimit);
}

bool correctionTestApplies(double residualEstimate, double lastResidualEstimate, double bound) {
  return residualEstimate <= kCorrectionContraction * lastResidualEstimate &&
         residualEstimate <= kCorrectionOverstatementLimit * bound;
}

double simplifiedErrorEstimate(double simplifiedCorrection, double correction) {
  const double theta = simplifiedCorrection / correction;
  return theta <= kSimplifiedContractionLimit ? simplifiedCorrection / (1.0 - theta)
                                              : std::numeric_limits<double>::infinity();
}

DynamicsSolver::DynamicsSolver(ShellSystem& system, const DynamicsOptions& options)
    : system_(system),
      options_(options),
      newton_(system.objective(), forSystem(options.newton, system)),
      massDamping_(checkedMassDamping(system, options)) {
  Eigen::VectorXd x = system.restPositions();
  system.objective().applyPrescribed(0.0, x);
  setState(x, Eigen::VectorXd::Zero(x.size()), 0.0);
  if (options.duration > 0.0) system.objective().setPrescribedPath(0.0, options.duration);
}

DynamicsSolver::~DynamicsSolver() { system_.objective().clearPrescribedPath(); }

void DynamicsSolver::setState(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double t) {
  const Eigen::Index n = system_.objective().numDofs();
  if (x.size() != n || v.size() != n) throw InputError("dynamics: state vectors have the wrong size");
  if (!x.allFinite() || !v.allFinite() || !std::isfinite(t)) throw InputError("dynamics: state must be finite");
  x_ = x;
  v_ = v;
  t_ = t;
  historyValid_ = false;
  nextStart_.resize(0);
  newton_.linearSolver().forgetPreparationHistory();
}

void DynamicsSolver::restore(const Snapshot& s) {
  setState(s.x, s.v, s.t);
  forgetSolverHistory();
  if (s.historyValid) {
    if (s.xPrev.size() != s.x.size() || s.vPrev.size() != s.x.size() || !s.xPrev.allFinite() || !s.vPrev.allFinite())
      throw InputError("dynamics: the BDF2 history of the snapshot does not match the state");
    xPrev_ = s.xPrev;
    vPrev_ = s.vPrev;
  }
  historyStep_ = s.historyStep;
  historyValid_ = s.historyValid;
  steps_ = s.steps;
}

double DynamicsSolver::kineticEnergy() const {
  const Eigen::VectorXd& m = system_.vertexMass();
  double e = 0.0;
  for (Eigen::Index i = 0; i < m.size(); ++i) e += m[i] * v_.segment<3>(3 * i).squaredNorm();
  return 0.5 * e;
}

double DynamicsSolver::potentialEnergy() {
  return system_.objective().evaluate(x_, nullptr, false, EvalOptions{}, TermSelection::PotentialOnly);
}

bool DynamicsSolver::attempt(double h, bool bdf2, StepReport& report) {
  ShellSystem& sys = system_;
  const double beta = sys.material().stiffnessDampingCoefficient;
  Eigen::VectorXd centre;  // x̂ (BDF2) or x_n (backward Euler): the damping origin
  Eigen::VectorXd predictor;
  double inertiaCoefficient, dampingScale;
  if (bdf2) {
    centre = (4.0 * x_ - xPrev_) / 3.0;
    predictor = centre + (8.0 * h / 9.0) * (v_ - 0.25 * vPrev_);
    inertiaCoefficient = 9.0 / (4.0 * h * h);
    dampingScale = 1.5 / h;
  } else {
    centre = x_;
    predictor = x_ + h * v_;
    inertiaCoefficient = 1.0 / (h * h);
    dampingScale = 1.0 / h;
  }
  if (sys.inertia) sys.inertia->setCentre(predictor, inertiaCoefficient);
  if (sys.massDamping) sys.massDamping->setCentre(centre, massDamping_ * dampingScale);
  if (sys.stiffnessDamping.membrane) sys.stiffnessDamping.membrane->setStrainOrigin(centre, beta * dampingScale);
  if (sys.stiffnessDamping.bending) sys.stiffnessDamping.bending->setCurvatureOrigin(centre, beta * dampingScale);
  sys.objective().beginStep(x_, t_, h);  // lagged contact data (friction normal forces, damping origins)

  // The start: the extrapolated trajectory (the integrator's own step under the constant acceleration of the last
  // full step) or the predictor, followed only as far as the objective's step bound allows (contact: no sample
  // starts the solve on the wrong side of a layer).
  Eigen::VectorXd drift = h * v_;
  if (options_.extrapolatedStart && historyValid_) {
    // Not for an actor stiff and thin for the step (see the header): its acceleration is its membrane's ringing.
    const double scale = (bdf2 ? 0.5 : 1.0) * (h * h / historyStep_);
    for (Eigen::Index v = 0; v < sys.vertexMass().size(); ++v)
      if (extrapolatesAcceleration(sys, v, h, options_))
        drift.segment<3>(3 * v) += scale * (v_.segment<3>(3 * v) - vPrev_.segment<3>(3 * v));
  }
  Eigen::VectorXd x;
  if (nextStart_.size() > 0) {
    x = std::move(nextStart_);
    nextStart_.resize(0);
  } else {
    x = x_ + sys.objective().stepBound(x_, drift) * drift;
  }
  sys.objective().applyPrescribed(t_ + h, x);
  // BDF2's local truncation error is O(Δt³): its time-error scale is the step's change against its own step
  // under constant acceleration (Milne's predictor–corrector difference, see the header).
  const Eigen::VectorXd extrapolated =
      bdf2 ? Eigen::VectorXd(x_ + h * v_ + 0.5 * h * (v_ - vPrev_)) : Eigen::VectorXd();
  Eigen::VectorXd lastIterate;       // the correction test's memory of this solve's previous iterate
  double lastResidualEstimate = 0.0;
  double lastCorrection = 0.0;  // the last Newton correction of this solve, 0 when the last step was not one
  Eigen::VectorXd simplifiedCorrection;
  // Whether the last iterate the test judged overstated its threshold beyond kCorrectionOverstatementLimit: a
  // stiffness no time step should meet (crushed elements), so its solve is done again from x_n (below).
  bool crushedIterate = false;
  // The iterate test below captures this step's locals: it is cleared however the solve ends (a throw included).
  struct ClearIterateTest {
    NewtonSolver& newton;
    ~ClearIterateTest() { newton.setIterateTest({}); }
  } clearIterateTest{newton_};
  // The rule weighs each vertex's residual by its mass: a massless vertex (an actor of zero density beside massive
  // ones) would go unjudged, so then Newton's residual test alone decides.
  if (options_.updateTolerance > 0.0 && sys.inertia && sys.vertexMass().minCoeff() > 0.0) {
    // Time-discretization rule (see the header): Newton error estimates against the step's change, all as
    // mass-weighted RMS vertex distances.
    const Eigen::VectorXd& m = sys.vertexMass();
    const double eta = options_.updateTolerance, floor = 1e-9 * sys.objective().scales().length;
    const double totalMass = m.sum();
    // With contact terms the correction is also judged on the contact's own length (see the header): its largest
    // vertex move at most κ δ, its RMS threshold at least δ/100. Without them no vertex move is too large.
    const bool withContact = !sys.contact.empty();
    const double largestMoveBound = withContact ? options_.contactCorrectionFraction * sys.contact.narrowestRamp
                                                : std::numeric_limits<double>::infinity();
    const double correctionFloor = withContact ? kContactCorrectionFloor * sys.contact.narrowestRamp : 0.0;
    const bool correctionTest = options_.correctionTest && largestMoveBound > 0.0;
    newton_.setIterateTest([&predictor, &extrapolated, &m, &lastIterate, &lastResidualEstimate, &lastCorrection,
                            &simplifiedCorrection, &crushedIterate, eta, floor, totalMass, inertiaCoefficient,
                            correctionTest, bdf2, largestMoveBound, correctionFloor,
                            withContact](const IterateView& it) {
      const Eigen::VectorXd& xk = it.x;
      const Eigen::VectorXd& g = it.gradient;
      // The correction x_k − x_{k−1} is a Newton correction only after a full Newton step.
      const bool haveCorrection = correctionTest && it.newtonStepFraction == 1.0 && lastIterate.size() == xk.size();
      double errorSq = 0.0, changeSq = 0.0, extrapolationSq = 0.0, correctionSq = 0.0, largestMoveSq = 0.0;
      for (Eigen::Index v = 0; v < m.size(); ++v) {
        if (!(m[v] > 0.0)) continue;
        errorSq += g.segment<3>(3 * v).squaredNorm() / m[v];
        changeSq += m[v] * (xk.segment<3>(3 * v) - predictor.segment<3>(3 * v)).squaredNorm();
        if (bdf2) extrapolationSq += m[v] * (xk.segment<3>(3 * v) - extrapolated.segment<3>(3 * v)).squaredNorm();
        if (haveCorrection) {
          const double moveSq = (xk.segment<3>(3 * v) - lastIterate.segment<3>(3 * v)).squaredNorm();
          correctionSq += m[v] * moveSq;
          largestMoveSq = std::max(largestMoveSq, moveSq);
        }
      }
      const double residualEstimate = std::sqrt(errorSq / totalMass) / inertiaCoefficient;
      if (bdf2) changeSq = std::min(changeSq, extrapolationSq);
      const double threshold = eta * std::max(std::sqrt(changeSq / totalMass), floor);
      IterateTestResult result{residualEstimate <= threshold, residualEstimate, threshold, "residual estimate"};
      // ‖H_{k−1}⁻¹ g_k‖_M, the simplified Newton correction, where the last system can be solved again (once per
      // iterate); -1 if not.
      double simplifiedNorm = std::numeric_limits<double>::quiet_NaN();
      const auto simplified = [&]() {
        if (std::isnan(simplifiedNorm)) {
          simplifiedNorm = -1.0;
          if (it.solveLastSystem && it.solveLastSystem(-g, simplifiedCorrection)) {
            double simplifiedSq = 0.0;
            for (Eigen::Index v = 0; v < m.size(); ++v)
              if (m[v] > 0.0) simplifiedSq += m[v] * simplifiedCorrection.segment<3>(3 * v).squaredNorm();
            simplifiedNorm = std::sqrt(simplifiedSq / totalMass);
          }
        }
        return simplifiedNorm;
      };
      const double correction = haveCorrection ? std::sqrt(correctionSq / totalMass) : 0.0;
      // With contact terms the residual estimate is no bound where the Hessian falls below the inertia (see the
      // header). After a Newton correction whose system can be solved again, Newton's own contraction
      // θ = s / correction must say it too: a pass is refused unless θ < 1 and s / (1 − θ) is within the threshold.
      if (result.passed && withContact && correction > 0.0) {
        const double s = simplified();
        if (s >= 0.0 && !(s < correction && s / (1.0 - s / correction) <= threshold)) result.passed = false;
      }
      const double bound = std::max(threshold, correctionFloor);  // the correction's
      crushedIterate = !result.passed && residualEstimate > kCorrectionOverstatementLimit * bound;
      if (!result.passed && haveCorrection && correctionTestApplies(residualEstimate, lastResidualEstimate, bound) &&
          correction <= bound && std::sqrt(largestMoveSq) <= largestMoveBound) {
        // The error left (see the header), from the simplified Newton correction −H_{k−1}⁻¹ g_k, where the last
        // system can be solved again and the iterate is Newton's second correction or a later one.
        double errorLeft = std::numeric_limits<double>::infinity();
        if (correction > 0.0 && lastCorrection > 0.0) {
          const double s = simplified();
          if (s >= 0.0) errorLeft = simplifiedErrorEstimate(s, correction);
        }
        if (errorLeft <= bound) result = {true, correction, bound, "Newton correction"};
      }
      if (correctionTest) {
        lastIterate = xk;
        lastResidualEstimate = residualEstimate;
        lastCorrection = correction;
      }
      return result;
    });
  }
  // No step ends worse than staying put (see the header). x_n's incremental potential is taken here, where the
  // contact terms' candidates were just gathered around x_n (beginStep), so it costs no broad phase.
  Eigen::VectorXd stay = x_;
  sys.objective().applyPrescribed(t_ + h, stay);
  const bool guarded = options_.guardedEnd && stay != x;  // nothing to guard when the start is x_n
  const double stayEnergy = guarded ? sys.objective().evaluate(stay, nullptr, false, EvalOptions{}) : 0.0;
  const double stayNoise = guarded ? 1e-13 * sys.objective().energyMagnitude() : 0.0;
  SolverSummary summary = newton_.minimize(x);
  addTimes(report, summary);
  bool movedOn = options_.acceptIterationCap && summary.reason == TerminationReason::IterationCap;
  // The solve set aside (kept in the report, discarded) for another from x, with the iterate test's history reset.
  const auto solveAgain = [&]() {
    summary.discarded = true;
    report.solves.push_back(std::move(summary));
    lastIterate.resize(0);
    lastResidualEstimate = 0.0;
    lastCorrection = 0.0;
    summary = newton_.minimize(x);
    addTimes(report, summary);
    movedOn = options_.acceptIterationCap && summary.reason == TerminationReason::IterationCap;
  };
  if (guarded && (summary.converged() || movedOn)) {
    // Solved again from x_n: above staying put, or moved on from a crushed iterate.
    if (!(summary.finalEnergy <= stayEnergy + stayNoise) || (movedOn && crushedIterate)) {
      ++report.stayRestarts;
      x = std::move(stay);
      solveAgain();
    }
  }
  // A solve that would move on at the cap with its contact guards broken solves on from its iterate (see the
  // header): at the cap the contact forces can be far from their solution, and a landing presses samples deep.
  for (int more = 0; movedOn && more < options_.contactGuardSolves && !sys.contact.empty() &&
                     sys.contact.guardsBroken(x, options_.contactGuardDepth, options_.contactGuardPairRatio);
       ++more) {
    ++report.guardSolves;
    solveAgain();
  }
  const bool ok = summary.converged() || movedOn;
  if (!ok) {
    std::ostringstream s;
    s << "step " << h << " s at t = " << t_ << ": " << toString(summary.reason) << " (" << summary.message << ")";
    report.message = s.str();
  }
  report.solves.push_back(std::move(summary));
  if (!ok || !x.allFinite()) return false;
  const Eigen::VectorXd v = bdf2 ? Eigen::VectorXd((3.0 * x - 4.0 * x_ + xPrev_) / (2.0 * h))
                                 : Eigen::VectorXd((x - x_) / h);
  if (!v.allFinite()) return false;
  if (observer_) observer_({h, bdf2, &x_, &v_, &xPrev_, &vPrev_, &x, &report.solves.back(), movedOn, t_});
  x_ = x;
  v_ = v;
  t_ += h;
  ++report.substeps;
  if (movedOn) ++report.movedOn;
  const SolverSummary& accepted = report.solves.back();
  if (accepted.residualThreshold > 0.0)
    report.worstResidualRatio =
        std::max(report.worstResidualRatio, accepted.finalResidual / accepted.residualThreshold);
  return true;
}

bool DynamicsSolver::advance(double h, int depth, int planned, bool allowBdf2, StepReport& report) {
  if (depth >= planned) {
    const bool bdf2 = allowBdf2 && options_.integrator == TimeIntegrator::BDF2 && historyValid_ &&
                      std::abs(historyStep_ - h) <= 1e-12 * h;
    if (attempt(h, bdf2, report)) return true;
    if (depth - planned >= options_.maxCuts) return false;
    ++report.cuts;
  }
  const Eigen::VectorXd x0 = x_, v0 = v_;
  const double t0 = t_;
  const int substeps0 = report.substeps, movedOn0 = report.movedOn;
  const double worstRatio0 = report.worstResidualRatio;
  if (advance(0.5 * h, depth + 1, planned, false, report) && advance(0.5 * h, depth + 1, planned, false, report))
    return true;
  x_ = x0;
  v_ = v0;
  t_ = t0;
  report.substeps = substeps0;
  report.movedOn = movedOn0;
  report.worstResidualRatio = worstRatio0;
  return false;
}

int DynamicsSolver::plannedHalvings(double h, StepReport& report) const {
  if (system_.contact.volume.empty()) return 0;
  const ShellContact::SolidSweep sweep = system_.contact.solidSweep(x_, v_, t_, h, std::ldexp(1.0, options_.maxCuts));
  int k = 0;
  while (k <= options_.maxCuts && std::ldexp(1.0, k) < sweep.parts) ++k;
  if (k <= options_.maxCuts) return k;
  std::ostringstream s;
  const int most = 1 << options_.maxCuts;
  s << "time step at t = " << t_ << ": the solid '" << sweep.solid << "' moves " << sweep.travel
    << " m near the shell within the step, more than " << most << " parts of it can follow (each may move "
    << sweep.allowed << " m, a fraction of its thinnest half-width, or it may pass through the shell unseen: "
    << "take a time step of at most " << h * most / sweep.parts << " s)";
  report.message = s.str();
  return -1;
}

void DynamicsSolver::setTimeStep(double h) {
  checkTimeStep(h);
  options_.timeStep = h;
}

void DynamicsSolver::startNextSolveFrom(const Eigen::VectorXd& x) {
  if (x.size() != x_.size() || !x.allFinite())
    throw InputError("dynamics: a solve's start must be " + std::to_string(x_.size()) + " finite coordinates");
  nextStart_ = x;
}

StepReport DynamicsSolver::step() {
  StepReport report;
  const double h = options_.timeStep;
  report.timeStep = h;
  const Eigen::VectorXd x0 = x_, v0 = v_;
  const int planned = plannedHalvings(h, report);
  report.parts = planned > 0 ? 1 << planned : 1;
  report.success = planned >= 0 && advance(h, 0, planned, true, report);
  if (report.success) {
    // The state one full step back is the BDF2 history, whether or not the step was cut.
    xPrev_ = x0;
    vPrev_ = v0;
    historyStep_ = h;
    historyValid_ = true;
    ++steps_;
    report.message.clear();
  } else if (planned >= 0) {
    std::ostringstream s;
    s << "time step at t = " << t_ << " failed after " << report.cuts << " cuts; last attempt: " << report.message;
    report.message = s.str();
  }
  report.step = steps_;
  report.time = t_;
  return report;
}

DynamicsResult simulate(DynamicsSolver& solver, double duration, const StepCallback& callback) {
  if (!(std::isfinite(duration) && duration >= 0.0)) throw InputError("dynamics: duration must be finite and >= 0");
  DynamicsResult result;
  result.activeTerms = solver.system().objective().activeTermNames();
  const double stepCount = std::ceil(duration / solver.options().timeStep - 1e-9);
  if (!(stepCount <= static_cast<double>(inputLimits().maxSteps))) {
    std::ostringstream s;
    s << "dynamics: duration / timeStep gives " << stepCount << " steps, too many (at most " << inputLimits().maxSteps
      << ")";
    throw InputError(s.str());
  }
  const int steps = static_cast<int>(stepCount);
  for (int i = 0; i < steps; ++i) {
    const StepReport r = solver.step();
    result.newtonIterations += r.newtonIterations;
    result.cuts += r.cuts;
    result.movedOn += r.movedOn;
    result.stayRestarts += r.stayRestarts;
    result.guardSolves += r.guardSolves;
    result.time = solver.time();
    if (!r.success) {
      result.message = r.message;
      return result;
    }
    ++result.steps;
    if (callback && !callback(r, solver)) {
      result.stopped = true;
      result.message = "stopped by the callback at t = " + std::to_string(solver.time());
      return result;
    }
  }
  result.completed = true;
  std::ostringstream s;
  s << result.steps << " steps to t = " << result.time << " s (" << result.newtonIterations << " Newton iterations, "
    << result.cuts << " cuts";
  if (result.movedOn > 0) s << "; moved on unconverged at the iteration cap in " << result.movedOn << " solves";
  if (result.stayRestarts > 0)
    s << "; " << result.stayRestarts << " solves done again from the previous positions, the first having ended above them";
  if (result.guardSolves > 0)
    s << "; " << result.guardSolves << " solves on from the iteration cap, a contact guard broken there";
  s << ")";
  result.message = s.str();
  return result;
}

}  // namespace jetshell
