// Implicit time stepping as incremental potentials: each step minimizes, over the end-of-step positions x,
//   backward Euler:  ½/Δt² ‖x − x̃‖²_M + E(x) + (α_R/2Δt) ‖x − x_n‖²_M + (β_R/Δt) Σ area·[W_m(ε − ε_n) + W_b(κ − κ_n)]
//                    with x̃ = x_n + Δt v_n, then v = (x − x_n)/Δt;
//   BDF2:            (9/8Δt²) ‖x − x̃‖²_M + E(x) + (3α_R/4Δt) ‖x − x̂‖²_M + (3β_R/2Δt) Σ area·[W(ε − ε(x̂)) + ...]
//                    with x̂ = (4x_n − x_{n−1})/3, x̃ = x̂ + (8Δt/9)(v_n − v_{n−1}/4), then
//                    v = (3x − 4x_n + x_{n−1})/(2Δt).
// M is the lumped mass, E the potential terms (elastic, gravity, loads). Both are exact for constant
// acceleration once started; BDF2 starts (and restarts after a change of step) with one backward Euler step.
// The stiffness-damping origin x̂ makes BDF2's ε̇ = 3(ε(x) − ε(x̂))/(2Δt) second order for the linear part of
// ε (ε(x̂) differs from (4ε_n − ε_{n−1})/3 by a term quadratic in x_n − x_{n−1}).
// Velocities are rebuilt from positions only. Prescribed positions are applied at the end-of-step time
// (their velocities follow from the same formulas).
// A step whose Newton solve fails (see DynamicsOptions::acceptIterationCap) is cut: the state is restored and
// the step is retried as two half steps (backward Euler), recursively up to maxCuts times. The state only ever
// takes converged (or, with acceptIterationCap, "moved on") finite values; when every cut fails the step reports
// failure and the state is unchanged. A step near a fast moving solid is divided up front into 2^k equal parts
// (ShellContact::solidSweep: in each part no solid moves near the shell by more than half its thinnest
// half-width, or its surface at the shell's reachable sample points does not, so none passes through it unseen),
// each part cut as above when it fails; a step that would need
// more than 2^maxCuts parts fails, saying which solid and what time step would do.
// Newton starts from the extrapolated trajectory when extrapolatedStart: the integrator's own step under the constant
// acceleration a = (v_n − v_{n−1})/Δt_{n−1} of the last full step, x_n + Δt v_n + Δt² a for backward Euler
// (v_{n+1} = v_n + Δt a) and x_n + Δt v_n + ½Δt² a for BDF2 (exact for a parabola); else from the inertial
// predictor x_n + Δt v_n. (BDF2 used backward Euler's formula until 2026-11-23: off by ½Δt² a, about the whole
// step's change; the 2,601-vertex falling cloth took 273 Newton iterations, against 178 now: BENCHMARKS.md.)
// The acceleration is dropped for an actor that is stiff and thin for the step: its membrane wave (speed
// c = √((λ + 2μ)/ρ_A)) crosses more than extrapolationWaveLimit (20) of its edges (mean length ℓ) a step, and ℓ
// is more than extrapolationThinLimit (50) times its thickness; such an actor starts from x_n + Δt v_n. There
// (v_n − v_{n−1})/Δt is mostly the ringing of a wrinkling membrane, which the step cannot follow, and
// extrapolating it stretches the membrane: a 1 m steel foil of 0.1 mm (E 2e11 Pa) hanging from two corners at
// 60 Hz (1,560 edges a step, ℓ = 567 h) started at residuals of up to 6.5e5 N and took 32 Newton iterations a
// step with 8 cuts in 60 steps; from the inertial predictor 5 a step and no cut, its trajectory nearer the
// reference (`jetshell bench dynamics --material steel-foil`). Measured on a hanging sheet over E, thickness,
// Δt and mesh (BENCHMARKS.md, Dynamics, session 62): with ℓ/h of 57–1,140 the extrapolation saves iterations
// below about 18 edges a step and costs 1.06–6.3× as many from about 20 on; with ℓ/h of 28–45 it still saves
// them at 44–180 edges a step (likely because a thick sheet does not wrinkle at the mesh's scale), is mixed at
// 300 and costs them at 1,780, which the rule leaves as it was. Every scene of examples/ keeps it (the T-shirts
// cross 6 and 12 edges a step, the hanging cloth 18; the turntable's cloth 44, with ℓ = 45 h). Dynamic
// relaxation keeps it always. Those savings were measured with the correction test of session 63, whose passes
// on a 10-square foil left up to 5.8 times their threshold (below). With the error left judged as below
// (session 64) the foil takes 855 Newton iterations in 60 steps with the acceleration and 871 without, 14 and 10
// cuts: the saving is gone there, and the rule stays until the sheets above are measured again (BENCHMARKS.md,
// Dynamics).
// A solve about to move on at the iteration cap (acceptIterationCap) with a contact guard broken
// (contactGuardSolves: a sample more than half the activation distance below a volume's surface, or two interacting
// samples closer than half their contact distance 2r) solves on from its iterate instead, up to four more times.
// At the cap a landing's contact forces can be far from their solution: the T-shirt example on 2.5 and 1.67 cm
// cells went 3.47 and 5.32 mm below the floor in its first 30 steps, and 0.00 mm with 8 or 16 iterations allowed
// (BENCHMARKS.md, Contact, session 72). Steps whose guards hold move on as before.
// A step ends no higher than staying put (guardedEnd): when a solve that converged or moved on at the cap ends
// with a higher incremental potential than x_n's (x_n with the prescribed positions of the step's end, a point
// the step could always have taken), the step is solved again from x_n, and Newton's line search, which only
// lowers the potential, keeps it there. An extrapolated start can crush elements: the T-shirt without
// self-contact (so without the point cloud's step bound) extrapolated a landing into a start whose bending energy
// was 109 J (−2.5 J of potential at x_n) with a gradient of 1.4e6 N; a tiny correction against that stiffness
// passed the correction test below, and the shirt blew up over the following steps (BENCHMARKS.md, Contact,
// session 32). It costs one energy value a step; the T-shirt with self-contact never needs the second solve.
// A solve that moved on at the cap from a crushed iterate (its residual estimate over 1e4 times the bound of the
// correction test, below) is solved again from x_n as well: it is lower than x_n, but no state to step from.
// Time-discretization stopping rule (updateTolerance η > 0, with inertia): Newton stops at the first iterate x_k
// whose error estimate e_k = ‖M⁻¹g‖_M / c (c = 1/Δt² for backward Euler, 9/(4Δt²) for BDF2; g the step
// objective's gradient) is at most η · ‖x_k − x̃‖_M, x̃ the inertial predictor; both are mass-weighted RMS vertex
// distances (‖u‖_M² = Σ m_v |u_v|² / Σ m_v). While the step's Hessian is at least its inertia c M (a
// positive semi-definite stiffness; inertia dominates at the usual Δt), e_k bounds the distance to the step's
// minimizer; ‖x − x̃‖ is Δt²‖a‖ (backward Euler; 4/9 of it for BDF2), the scale of the step's local truncation
// error. So the Newton error stays a fraction η of the time-discretization error, and the test needs no solve:
// a good start (the extrapolated trajectory) can pass it after one iteration. floor = 1e-9 × the mean edge
// length stands for ‖x − x̃‖ when the step changes nothing. Newton's own residual tests still apply. The rule
// needs every vertex massive (a massless one's residual would weigh nothing); otherwise the residual tests alone
// decide.
// BDF2: its local truncation error is O(Δt³) (≈ (2/9)Δt³ x'''), far below ‖x − x̃‖ = (4/9)Δt² ‖a‖ at small Δt, so
// a Newton error held to a fraction of ‖x − x̃‖ adds up to an O(Δt) global error that BDF2's O(Δt²) one does not
// hide (measured, 441 vertices, Δt = 1/240: 7 of 240 steps accepted at their start raised the RMS trajectory
// error from 8.98 to 9.76 mm; the page's tighter solves give 8.69 mm). BDF2 steps therefore measure the change
// by min(‖x − x̃‖_M, ‖x − p‖_M), p = x_n + Δt v_n + ½Δt (v_n − v_{n−1}) the BDF2 step under constant acceleration
// (the start): the predictor–corrector difference, the usual LTE estimate of multistep codes (Milne’s device;
// the LTE is about a third of it). It is 0 at an unbounded start: a BDF2 step then takes a Newton iteration.
// Newton correction test (correctionTest): the residual estimate overstates the error by up to the ratio of the
// stiffness to the inertia c M (fine meshes, stiff membranes: 10–100× measured on the 2,601-vertex cloth). So an
// iterate x_k reached by a full Newton step (α = 1, no step bound) also passes when that correction
// ‖x_k − x_{k−1}‖_M is at most the same threshold while the residual estimate fell at least ×2 over it: the
// classic increment test, the correction bounding the error left once Newton contracts. Measured on that cloth
// against fully converged steps (backward Euler, 60 steps): the error left at acceptance was at most 0.84 of the
// threshold (0.19 with the residual estimate alone), for 28% fewer iterations in the same steps.
// The correction bounds the error left only once Newton is seen contracting, and a residual estimate that fell
// ×2 is no such evidence where the residual is the stiff membrane's: a 2 mm sheet of E 1e10 Pa hanging at 60 Hz
// has Newton wander before it contracts, and a first correction that happened to be short passed with the
// error left (against the step solved to η = 1e-6) up to 2.7 times the threshold on 12 of 36 such passes, for a
// trajectory 0.07 m from the fully solved one. So the correction must also bound the error left, estimated from
// the simplified Newton correction s = ‖H_{k−1}⁻¹ g_k‖_M: the last iteration's system solved again for the new
// gradient (a back-substitution, or a few CG iterations with the last preconditioner), with Deuflhard's
// contraction θ = s/‖x_k − x_{k−1}‖_M and error estimate s/(1 − θ). The estimate is trusted
// only where Newton shows its local regime: after at least two Newton corrections, and with θ ≤ 1/4 (θ ≈ h/2 in
// Newton's local theory, h Kantorovich's quantity). Neither condition is idle. The exact-first assembly
// projected small blocks (NewtonOptions::exactFirstProjectedDofs; near a solution it now tries the unprojected
// Hessian instead, NewtonOptions::unprojectedNearSolution), and there these solves contracted only linearly,
// ×0.2 per iteration on that sheet and ×0.37 on the 2,601-vertex cloth, after a global phase in
// which a short correction can precede long ones: measured by solving every passed step again to η = 1e-6
// (`jetshell bench dynamics --newton-error`, BENCHMARKS.md, Dynamics, session 64), a pass at θ of 0.27–0.42
// left up to 2.7 times the threshold on the cloth (8 of 18 passes), and a pass on the first correction 1.45
// times on the sheet. Before this, the test also passed on two corrections that halved, and those left up to
// 48 times the threshold on the sheet at η = 0.001 (a correction of 3 µm followed by one of 0.2 mm).
// Only an exact-first system gives a simplified correction: a projected one is stiffer than the sheet in its
// buckling modes, and its simplified correction understated the error left 15-fold on that sheet. Measured
// (session 64): every pass within its threshold on the sheet (backward Euler and BDF2, η 0.1–0.001), the cloth
// and the steel foil (η 0.1, 0.01), for 1.09–1.32 times session 63's iterations on the sheet, 1.00–1.17 on the
// cloth and 1.4–2.6 on the foil, whose cheaper steps had passed on corrections nobody measured.
// With contact terms the error left is judged the same way, under the correction's move bound (below). Until
// session 67 the correction alone was judged there (requiring the corrections to halve had moved the
// cloth-over-ball drape 40 mm from its tightly solved run in 20 steps, its folds forming by a bifurcation that
// any change of the solves flips). Measured with `jetshell bench contact --newton-error` and the drape's steps
// solved again tightly, those passes ended up to 1.47 times their threshold on the T-shirt and 3.3 times on the
// drape: Newton's corrections there do not contract steadily (the T-shirt's step 54: 0.53 and 0.13 mm, then
// 0.09, 0.39, 0.08 mm in its tight solve). The T-shirt's steps that passed by the correction (18 of 60) now
// run on to the iteration cap, 3.58 Newton iterations a step instead of 3.22 (BENCHMARKS.md, Contact,
// session 67).
// The residual estimate's bound needs the step's Hessian to be at least its inertia: a penalty against a curved
// surface (its tangential curvature is negative) and compression take some of that away, and a residual pass of
// the drape ended 1.045 times its threshold from its tight solve, after corrections that shrank ×0.98, ×1.2,
// ×0.92. So with contact terms, at an iterate reached by a Newton correction whose system can be solved again,
// the residual estimate passes only if Newton's contraction agrees: θ = s/‖x_k − x_{k−1}‖_M < 1 and the linear
// rate's error estimate s/(1 − θ) within the threshold. It only refuses passes, so it cannot loosen the rule.
// Measured on the drape's 60 steps: 12 correction passes within 0.30 of their threshold, 44 residual passes
// within 0.84; the T-shirt's solves are unchanged by it.
// With contact terms a small RMS correction is no bound on the penetration left: a penalty's stiffness can hide
// a few samples' large moves in a small mean (the T-shirt's landing went 3.6 mm below the plane with the RMS test
// alone, against its test's 2.5 mm). There the correction must also move no vertex farther than κ δ
// (contactCorrectionFraction, κ = 0.3), δ the narrowest contact ramp's width, the length over which a contact
// force goes from nothing to its full slope; and the RMS threshold is at least δ/100, since a shell at rest
// changes by micrometres per step, finer than the contact forces resolve. Measured on the T-shirt (BENCHMARKS.md,
// Contact, session 29): 3.22 instead of 3.58 Newton iterations per step, its frames within 0.05 mm RMS (1 mm at
// most) of the run without it, against 6.3–6.9 mm RMS between that run and the same steps solved on to 40
// iterations.
// The correction is trusted only while the residual estimate overstates the bound the correction must meet by
// at most 1e4, a bound on the stiffness-to-inertia ratio it relies on (7–95 at every pass on the T-shirt and its
// variants): crushed, tangled elements made Newton's steps sub-micrometre under residuals of 1e4–6e5 N, and
// passed at 7e5–5e9.
#pragma once

#include "solvers/newton.h"
#include "solvers/shell_system.h"
#include "solvers/solver_summary.h"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace jetshell {

enum class TimeIntegrator { BackwardEuler, BDF2 };
TimeIntegrator timeIntegratorFromString(const std::string& name);  // backward_euler | bdf2
const char* toString(TimeIntegrator t);

struct DynamicsOptions {
  TimeIntegrator integrator = TimeIntegrator::BackwardEuler;
  double timeStep = 1.0 / 60.0;  // s
  NewtonOptions newton;
  int maxCuts = 6;  // halvings of a failed step (down to Δt/2^maxCuts)
  /// Take the unconverged iterate when Newton hits its iteration cap (the engine the spec comes from moves on
  /// this way, with 4 iterations) instead of cutting the step.
  bool acceptIterationCap = false;
  /// α_R [1/s] to use instead of the material's (dynamic relaxation sets it); < 0: the material's.
  double massDampingOverride = -1.0;
  /// Start Newton from the constant-acceleration extrapolation of the trajectory (see the file comment).
  bool extrapolatedStart = true;
  /// The extrapolation drops the acceleration of an actor that is both stiff and thin for the step: its membrane
  /// wave crosses more than extrapolationWaveLimit of its edges a step (Δt · ShellSystem::membraneWaveRate) and
  /// its edges are more than extrapolationThinLimit times its thickness (ShellSystem::edgeOverThickness). Such
  /// an actor starts from the inertial predictor x_n + Δt v_n (see the file comment). +∞: every actor keeps it.
  double extrapolationWaveLimit = 20.0;
  double extrapolationThinLimit = 50.0;
  /// Solve a step again from x_n when its solve ended with a higher incremental potential than x_n's, or moved on
  /// at the cap from a crushed iterate (see the file comment).
  bool guardedEnd = true;
  /// η of the time-discretization stopping rule (see the file comment); 0: off (only Newton's own tests).
  /// The default is jetshell's (solvers/time_step_policy.h, chosen by `jetshell bench dynamics`).
  double updateTolerance = 0.1;
  /// With updateTolerance: also pass an iterate reached by a full Newton step whose correction ‖Δx‖_M is at
  /// most η ‖x − x̃‖_M while the residual estimate fell at least ×2, and the error left estimated from the
  /// simplified Newton correction is too (see the file comment). Such a solve is converged; its summary's message
  /// names the "Newton correction". With contact terms it also needs
  /// contactCorrectionFraction (see the file comment).
  bool correctionTest = true;
  /// κ of the correction test with contact terms: there the correction must also move no vertex farther than
  /// κ δ, δ the narrowest contact ramp (ShellContact::narrowestRamp), and its RMS threshold is at least δ/100.
  /// 0: no correction test with contact terms (only the residual estimate and Newton's own tests).
  double contactCorrectionFraction = 0.3;
  /// With acceptIterationCap and contact terms: a solve that would move on at the cap with its contact guards
  /// broken (ShellContact::guardsBroken: a sample deeper below a volume's surface than contactGuardDepth × the
  /// activation distance, or two interacting samples closer than contactGuardPairRatio × 2r) solves on from its
  /// iterate, up to this many more times (each up to newton.maxIterations), before it moves on (see the file
  /// comment). 0: it moves on at once.
  int contactGuardSolves = 4;
  double contactGuardDepth = 0.5;
  double contactGuardPairRatio = 0.5;
  /// The run's length [s]: while the solver lives, its residuals judge the prescribed motion by its largest
  /// displacement over [0, duration] (Objective::setPrescribedPath), so a grip turned by full turns keeps its
  /// tolerance where it passes its reference. 0: by the displacement at each step's end alone.
  double duration = 0.0;
};

/// Whether the extrapolated start keeps vertex v's acceleration in a step of h (DynamicsOptions::
/// extrapolationWaveLimit and extrapolationThinLimit; see the file comment).
bool extrapolatesAcceleration(const ShellSystem& system, Eigen::Index v, double h, const DynamicsOptions& o);

/// Whether the Newton correction test may judge an iterate (see the file comment): its residual estimate fell at
/// least ×2 from the previous iterate's, and overstates the bound the correction must meet by at most the
/// stiffness-to-inertia ratio a correction is trusted at. Estimates and bound in metres.
bool correctionTestApplies(double residualEstimate, double lastResidualEstimate, double bound);
/// The error left at an iterate whose Newton correction was `correction`, from the simplified Newton correction
/// −H_{k−1}⁻¹ g_k (IterateView::solveLastSystem): with θ = simplified / correction, simplified / (1 − θ); ∞ when
/// θ > kSimplifiedContractionLimit (Newton not seen in its local regime; see the file comment). Metres,
/// mass-weighted RMS.
double simplifiedErrorEstimate(double simplifiedCorrection, double correction);
/// The largest contraction θ at which simplifiedErrorEstimate trusts Newton to be in its local regime.
constexpr double kSimplifiedContractionLimit = 0.25;

/// One accepted Newton solve of a step (a whole step, or a part of a cut one), seen before the state moves on:
/// the terms still hold this solve's centres, origins and coefficients. Time-step sensitivities
/// (solvers/time_step_sensitivity.h) are carried forward from here.
struct SubstepView {
  double timeStep = 0.0;  // h of this solve
  bool bdf2 = false;      // BDF2 (else backward Euler)
  const Eigen::VectorXd* xStart = nullptr;   // x_n
  const Eigen::VectorXd* vStart = nullptr;   // v_n
  const Eigen::VectorXd* xPrev = nullptr;    // x_{n−1} (BDF2 history; meaningful when bdf2)
  const Eigen::VectorXd* vPrev = nullptr;    // v_{n−1}
  const Eigen::VectorXd* x = nullptr;        // x_{n+1}, the accepted iterate
  const SolverSummary* solve = nullptr;
  bool movedOn = false;  // accepted at the iteration cap without convergence (acceptIterationCap)
  double time = 0.0;     // t_n, the solve's start [s]
};
using SubstepObserver = std::function<void(const SubstepView&)>;

/// What one call to DynamicsSolver::step() did.
struct StepReport {
  int step = 0;           // number of completed steps after this one
  double time = 0.0;      // t at the end of the step (unchanged on failure)
  double timeStep = 0.0;  // the step's Δt
  bool success = false;
  int substeps = 0;          // Newton solves that were accepted (1 without cuts)
  int movedOn = 0;           // of them, accepted at the iteration cap without convergence (acceptIterationCap)
  double worstResidualRatio = 0.0;  // the largest final residual / residualThreshold over the accepted solves
  int stayRestarts = 0;      // solves done again from x_n, the first having ended above it or crushed (guardedEnd)
  int guardSolves = 0;       // solves on from a capped iterate whose contact guards were broken (contactGuardSolves)
  int cuts = 0;              // halvings
  int parts = 1;             // the equal parts the step was divided into up front for a moving solid (1: none)
  int newtonIterations = 0;  // over every attempt
  double assemblySeconds = 0.0, factorizationSeconds = 0.0, solveSeconds = 0.0, lineSearchSeconds = 0.0;
  std::vector<SolverSummary> solves;  // every attempt, failed ones included
  std::string message;                // why the step failed
};

class DynamicsSolver {
 public:
  /// system must be built for Dynamics or DynamicRelaxation and outlive the solver. Starts at rest in the
  /// reference configuration at t = 0 (prescribed positions applied). Throws InputError for invalid options.
  DynamicsSolver(ShellSystem& system, const DynamicsOptions& options);
  /// Leaves the objective judging prescribed motion by its displacement alone again (DynamicsOptions::duration).
  ~DynamicsSolver();
  DynamicsSolver(const DynamicsSolver&) = delete;
  DynamicsSolver& operator=(const DynamicsSolver&) = delete;

  /// Sets the state (x, v: 3N; t in s). Resets the BDF2 history.
  void setState(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double t);
  const Eigen::VectorXd& positions() const { return x_; }
  const Eigen::VectorXd& velocities() const { return v_; }
  double time() const { return t_; }
  int stepCount() const { return steps_; }

  /// Advances one Δt (cutting it when needed). On failure the state is unchanged.
  StepReport step();
  /// Sets Δt for the steps that follow (a part of another run's step taken again, solvers/step_error_check.h).
  /// Throws InputError unless finite and > 0.
  void setTimeStep(double h);
  /// The next solve starts from x (3N), prescribed positions applied, instead of the extrapolated or inertial
  /// start (another run's iterate solved on, solvers/step_error_check.h); one solve only, and setState() or
  /// restore() forgets it. Throws InputError when the size does not match or a value is not finite.
  void startNextSolveFrom(const Eigen::VectorXd& x);

  /// The whole state, BDF2 history included: restoring it continues the run bit for bit (checkpoints).
  struct Snapshot {
    Eigen::VectorXd x, v, xPrev, vPrev;
    double t = 0.0, historyStep = 0.0;
    int steps = 0;
    bool historyValid = false;
  };
  Snapshot snapshot() const { return {x_, v_, xPrev_, vPrev_, t_, historyStep_, steps_, historyValid_}; }
  /// Throws InputError when the sizes do not match the system or a value is not finite.
  void restore(const Snapshot& s);

  /// ½ Σ m_v |v_v|².
  double kineticEnergy() const;
  /// The potential terms' energy (elastic, gravity, loads) at the current positions.
  double potentialEnergy();

  const DynamicsOptions& options() const { return options_; }
  NewtonSolver& newton() { return newton_; }
  /// Forgets what the Newton solver carries from step to step (NewtonSolver::forgetHistory): the next step is
  /// solved as a new solver would solve it. Call it where a run may be resumed from (a checkpoint), so the
  /// resumed run repeats the uninterrupted one bit for bit. restore() calls it; setState() forgets only the
  /// factor prepared for the old state, and keeps how recent starts went (the next start's cost depends on it).
  void forgetSolverHistory() { newton_.forgetHistory(); }
  /// Called after every accepted solve (SubstepView); empty: none. A step that fails after an accepted part
  /// restores the state and reports failure (the observer has then seen parts of a step that did not happen).
  void setSubstepObserver(SubstepObserver observer) { observer_ = std::move(observer); }
  ShellSystem& system() { return system_; }

 private:
  /// Advances h, first dividing it into halves down to depth planned, then cutting a failed part.
  bool advance(double h, int depth, int planned, bool allowBdf2, StepReport& report);
  /// The halvings a step of h needs up front for the moving solids (ShellContact::solidSweep); -1 when more
  /// than maxCuts (report.message says why).
  int plannedHalvings(double h, StepReport& report) const;
  bool attempt(double h, bool bdf2, StepReport& report);

  ShellSystem& system_;
  DynamicsOptions options_;
  NewtonSolver newton_;
  double massDamping_;
  Eigen::VectorXd x_, v_;
  double t_ = 0.0;
  int steps_ = 0;
  // BDF2 history: the state one full step back.
  Eigen::VectorXd xPrev_, vPrev_;
  double historyStep_ = 0.0;
  bool historyValid_ = false;
  Eigen::VectorXd nextStart_;  // startNextSolveFrom(); empty: none
  SubstepObserver observer_;
};

struct DynamicsResult {
  bool completed = false;  // the whole duration was simulated
  bool stopped = false;    // the callback asked to stop
  int steps = 0;
  double time = 0.0;
  int newtonIterations = 0;
  int cuts = 0;
  int movedOn = 0;  // substeps accepted unconverged at the iteration cap
  int stayRestarts = 0;  // solves done again from the previous positions (DynamicsOptions::guardedEnd)
  int guardSolves = 0;   // solves on from a capped iterate with broken contact guards (contactGuardSolves)
  std::vector<std::string> activeTerms;
  std::string message;
};

/// Called after every successful step; return false to stop cleanly.
using StepCallback = std::function<bool(const StepReport&, DynamicsSolver&)>;

/// Runs `duration` seconds (rounded to whole steps) from the solver's current state. Stops at the first step
/// that fails even after its cuts (the state stays at the last good step).
DynamicsResult simulate(DynamicsSolver& solver, double duration, const StepCallback& callback = {});

}  // namespace jetshell
