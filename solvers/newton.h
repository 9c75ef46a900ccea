// Newton's method on an Objective, with per-element PSD projection, a line search and a sparse linear solver.
//
// Convergence is judged on the residual (for time steps an iterate test may also end a solve, see below; the
// summary's convergenceTest says which held). The solve has converged when
//   - "residual": ‖g_free‖∞ ≤ residualTolerance × F, or
//   - "round_off": ‖g_free‖∞ ≤ min(round-off floor, 1e-2 F) and the Newton decrement at that iterate says nothing
//     more can be gained (below).
//  - F [N] is the objective's force scale (Objective::forceScale: the largest external nodal force, or the force of
//    the prescribed motion, or the material's force at unit strain when nothing drives the problem). It never
//    depends on the current residual. Default residualTolerance 1e-6: no free dof is out of balance by more than
//    a millionth of F.
//  - The round-off floor is the residual that rounding the positions alone may leave, 64 ε max_i (|H| |x|)_i over
//    the free dofs (a position known to ε|x| moves the force by H ε|x|): an estimate that bounds it from above
//    (measured: 300x above the residual Newton reaches on the slit ring with 128x2048 quads). A residual within
//    it is no proof of equilibrium: on fine, soft meshes a smooth residual that small still carries a real error
//    (measured on the slit ring: 0.16% of a deflection on 64x1024 quads; 11% on 96x1536 quads, where an iterate
//    at 4.17e-5 N within a floor of 4.18e-5 N passed before this rule). So it passes only with the decrement, which
//    a smooth error cannot hide. A load that moves the shell by less than its positions' round-off leaves a
//    residual above 1e-2 F: it cannot converge and says so.
// The Newton decrement ½ gᵀH⁻¹g decides nothing on its own: when it falls below decrementTolerance × F × L [J]
// (L the mean edge length), or, for an iterate within the round-off floor, below the energy's own round-off
// (1e-13 × the sum of the terms' |energies|), the full step is taken if it does not raise the energy beyond
// round-off (an iterate within the floor keeps its place unless the step stays within it too); then the residual
// decides, by either test above, and if neither holds the solve ends as Stalled, not converged.
// The summary records the final residual, the tolerance it was held to, the force scale and its source.
// The Hessian is assembled with the chosen projection (Clamp by default: each element block's negative
// eigenvalues are set to zero, so H is PSD and a shift-regularized solve yields a descent direction).
// Projection costs the quadratic rate near a solution (a stable equilibrium's element blocks can still be
// indefinite; measured: the clamped residual shrinks ×0.55 per iteration at the end of a cantilever solve,
// against squaring with the exact Hessian). So by default (exactHessianNearSolution) an iteration that follows
// a full step whose energy decrease matched the quadratic model (ratio in [0.5, 2]) tries the unprojected
// Hessian; if it is not positive definite, the projected one is reassembled for that iteration, and the next
// try waits 2, 4, 8, ... (up to 64) iterations (measured before the back-off: a Gauss–Newton static solve fell
// back 101 times in 139 iterations, each costing an extra assembly and factorization).
// Two more residual tests, off by default, for presets that state them so: absoluteResidualTolerance [N]
// (‖g_free‖∞ ≤ it) and relativeResidualTolerance (‖g_free‖∞ ≤ it × the initial residual).
// An iterate test (setIterateTest; time stepping sets one, see solvers/dynamics.h) is asked at every iterate,
// with its gradient and the fraction of the Newton direction that led there (IterateView), before the iteration
// cap and the solve; when it passes the solve ends as converged, and the
// summary's message states the test's estimate and threshold in metres.
#pragma once

#include "core/term.h"
#include "solvers/line_search.h"
#include "solvers/linear_solver.h"
#include "solvers/objective.h"
#include "solvers/solver_summary.h"
#include "solvers/symmetric_product.h"

#include <Eigen/Core>

#include <functional>
#include <memory>

namespace jetshell {

/// The largest relative tolerance a boundary accepts (residualTolerance, decrementTolerance, a relaxation's
/// tolerance): a residual of a tenth of the force scale balances nothing, and at 1 the unloaded start passes.
constexpr double kMaxRelativeTolerance = 0.1;

struct NewtonOptions {
  int maxIterations = 50;
  PsdProjection projection = PsdProjection::Clamp;
  bool exactHessianNearSolution = true;  // see the file comment; no effect with projection None
  /// Try a mostly unprojected Hessian at every iteration, not only near a solution: for time steps, whose
  /// inertia usually makes the whole Hessian positive definite although single element blocks are not. Element
  /// blocks of at most exactFirstProjectedDofs dofs are still projected (a 9×9 membrane or 6×6 contact block
  /// costs an eighth of an 18×18 bending block's eigendecomposition, and those terms carry the large negative
  /// curvature: compression, penalty repulsion); wider blocks are left as they are. Measured: projecting every
  /// block was 80% of a 10k-cloth assembly (BENCHMARKS.md). An iteration whose system is indefinite (the
  /// factorization or CG says so, or its direction does not descend) is redone with every block projected, with
  /// the back-off of the file comment. Needs exactHessianNearSolution and a projection other than None.
  bool exactHessianFirst = false;
  int exactFirstProjectedDofs = 12;  // 0: no block projected first
  /// With exactHessianFirst and exactFirstProjectedDofs > 0: an iteration that follows a full step whose energy
  /// decrease matched its model tries the whole Hessian, nothing projected (as exactHessianNearSolution does
  /// without exactHessianFirst). The small blocks' projection costs Newton its quadratic rate near a solution
  /// (measured, session 64: the stiff sheet's corrections shrank ×0.2 an iteration, the cloth's ×0.37). An
  /// indefinite try is redone with every block projected, the solve tries no more unprojected Hessians, and the
  /// next 2, 4, ... 64 solves (doubling with each such solve, halving back with each whose tries all held) try
  /// none (measured: the T-shirt fell back 44 times in 60 steps without this memory, 0.56-0.69x the steps per
  /// second; 7 times with it, 0.94x, so time steps with contact terms leave it off, solvers/dynamics.cpp).
  bool unprojectedNearSolution = true;
  /// The first iteration that may try it: a solve that ends in two (a soft cloth's, most of the time) gains
  /// nothing, and its tries fell back often enough to cost a 1,681-vertex hanging cloth 1.07-1.27x its wall time
  /// when they began at the second (BENCHMARKS.md, Dynamics, session 65).
  int unprojectedFromIteration = 2;
  /// With exactHessianFirst: the bending Hessian of the projected assembly an indefinite try falls back to (and
  /// of the back-off iterations after it). Gauss–Newton, Jᵀ W'' J, is positive semi-definite by construction and
  /// is not projected, so a fallback costs no eigendecompositions of 18×18 bending blocks: the T-shirt ran 1.12×
  /// the steps per second. It stays a choice, not the default: in 3 of 4 perturbed T-shirt runs, steps that moved
  /// on at the iteration cap ended with the potential energy spiking to 80–330 J (−5 J otherwise), which the
  /// projected exact Hessian never did (BENCHMARKS.md "Session 18").
  HessianModel fallbackBendingHessian = HessianModel::Exact;
  HessianModel bendingHessian = HessianModel::Exact;
  /// The friction terms' Hessian (core/term.h, energies/contact/contact_ramp.h). The majorizer's model lies above
  /// the friction potential, so its step does not throw a held contact past its stick region, which helps runs
  /// that move on at an iteration cap; solved to tolerance it converges linearly where contacts stick near their
  /// Coulomb limit (the exact one quadratically), hence the default.
  FrictionHessian frictionHessian = FrictionHessian::Exact;
  DerivativePath derivatives = DerivativePath::Analytic;
  LineSearchType lineSearch = LineSearchType::BacktrackingArmijo;
  int maxLineSearchEvaluations = 30;
  double armijoC1 = 1e-4;
  double wolfeC2 = 0.9;
  double residualTolerance = 1e-6;    // × force scale [N]
  double decrementTolerance = 1e-12;  // × force scale × length scale [J]: the stall test
  double absoluteResidualTolerance = 0.0;  // [N]; 0: off (presets that state one; the larger tolerance holds)
  double relativeResidualTolerance = 0.0;  // × the solve's initial residual; 0: off (the page's preset)
  LinearSolverOptions linear;
  /// Inexact Newton with an iterative linear solver: CG stops at the Eisenstat–Walker forcing term (their
  /// choice 2, γ = 0.9, exponent 2, with their safeguard) η_k = 0.9 (‖g_k‖/‖g_{k−1}‖)², clamped to
  /// [linear.cgRelativeTolerance, maxForcingTerm], starting at maxForcingTerm: loose while far from the solution,
  /// tight near it. Convergence is still judged on the true gradient (the tests above), never on CG's residual.
  /// The cap 0.01 (not EW's 0.9): a Newton iteration (assembly + factorization) costs far more than a CG
  /// iteration, so a loose first solve that costs an extra Newton iteration does not pay (BENCHMARKS.md: at
  /// 2.6k vertices a cap of 0.1 took 31 Newton iterations where 0.01 and a fixed 1e-6 took 26).
  bool adaptiveLinearTolerance = false;
  double maxForcingTerm = 0.01;
  /// With an iterate test (time steps), once one of the last kStartPassMemory solves passed its tests at the
  /// start: the start is judged on its energy and gradient alone, and its Hessian is assembled only when the
  /// tests fail there. Otherwise (and off) the start's Hessian is assembled with its gradient, so a run whose
  /// starts never pass pays no extra gradient (the tests still see every start, so the first pass is noticed).
  /// Measured (BENCHMARKS.md, Dynamics, Session 6): a settling cloth passes at the start of 68 of 300 steps, 23%
  /// of its Hessians; no step of the falling cloth does.
  bool gradientFirstStart = true;
  /// Modified Newton: an iteration first solves with the factor the last factored iteration left (kept across
  /// minimize() calls: the steps of a time integration or a relaxation), with no Hessian assembled and nothing
  /// factored, and assembles and factors only when that direction does not descend, its line search fails, or
  /// the iterate it gives has not shrunk the residual to reuseContraction × the residual before it. Convergence
  /// is judged as always, on the true gradient. Direct solvers only (others keep no factor: plain Newton).
  bool reuseFactor = false;
  double reuseContraction = 0.5;
  /// Overlap the preconditioner's factorization with the assembly (Objective::evaluate's narrow hook and
  /// LinearSolver::preparePreconditioner): the terms of narrow stencils are assembled first, then the one-ring
  /// factor of their part plus the wide terms' part from the previous iteration (at a solve's first, the previous
  /// solve's last) is computed on one thread while the wide terms (bending) are assembled on the others. The
  /// projected retry after an indefinite try factors the whole one-ring part after the assembly as before.
  /// forgetHistory() makes the solver behave as a new one (see LinearSolver::forgetPreparationHistory). Only
  /// solvers that prepare (PCG with the one-ring factor) do anything with it, only with at least two OpenMP
  /// threads (on one there is nothing to overlap with), only on a pattern already solved once, and not for
  /// objectives whose stencils follow the configuration (moving contacts: measured slower, and there the
  /// whole one-ring factor failing is what detects an indefinite Hessian; see newton.cpp). CG solves with the
  /// whole current Hessian either way.
  bool overlapPreconditioner = true;
};

/// The largest absolute entry of v (0 for an empty vector): the residual norm of the convergence tests.
double infNorm(const Eigen::VectorXd& v);
/// The largest Euclidean norm of v's 3-vectors (v stacks one per vertex; 0 for an empty vector).
double largestVertexNorm(const Eigen::VectorXd& v);

/// The outcome of an iterate test: passed, the estimate [m] and the threshold [m] it was compared with.
struct IterateTestResult {
  bool passed = false;
  double estimate = 0.0;
  double threshold = 0.0;
  const char* estimateName = "estimate";  // what the estimate is, for the summary's message
};
/// What an iterate test sees: the iterate, the objective's gradient there (fixed dofs zeroed), the iteration k,
/// and the fraction of the last Newton direction that led to it (α × the step bound: 1 for a full Newton step;
/// 0 at the start, and after a steepest-descent fallback).
/// After a full Newton step on the unprojected Hessian, solveLastSystem solves H_{k−1} y = b, the system that
/// step came from, again (LinearSolver::solveLastSystem: a direct solver's back-substitution, or CG to a relative
/// residual of kSimplifiedCorrectionTolerance with the last preconditioner; nothing assembled or factored; false
/// when it cannot, as after a shifted solve or a new pattern): −H_{k−1}⁻¹ g_k is the simplified Newton
/// correction, an estimate of the iterate's error that needs no new factor. Empty otherwise.
struct IterateView {
  const Eigen::VectorXd& x;
  const Eigen::VectorXd& gradient;
  int iteration = 0;
  double newtonStepFraction = 0.0;
  std::function<bool(const Eigen::VectorXd& b, Eigen::VectorXd& y)> solveLastSystem;
};
/// The relative residual of IterateView::solveLastSystem's CG: an error estimate needs a digit or two.
constexpr double kSimplifiedCorrectionTolerance = 1e-2;
using IterateTest = std::function<IterateTestResult(const IterateView& iterate)>;

class NewtonSolver {
 public:
  static constexpr int kStartPassMemory = 4;  // NewtonOptions::gradientFirstStart

  /// The solver keeps a reference to objective (which must outlive it) and owns the linear solver, so the
  /// symbolic analysis is shared by every minimize() on the same pattern.
  NewtonSolver(Objective& objective, const NewtonOptions& options);

  /// Minimizes from x (size 3N, in/out). Prescribed dofs keep the values x has on entry. x is only ever
  /// replaced by accepted, finite iterates: on failure it holds the last good one.
  SolverSummary minimize(Eigen::VectorXd& x);

  const NewtonOptions& options() const { return options_; }
  /// Changes the options; the linear solver (and its analysis) is kept unless its options changed.
  void setOptions(const NewtonOptions& options);
  LinearSolver& linearSolver() { return *linear_; }
  /// Forgets what earlier solves left to later ones (NewtonOptions::overlapPreconditioner's prepared factor,
  /// gradientFirstStart's memory of starts that passed, reuseFactor's factor): the next solve runs as a new
  /// solver's would. A time integrator calls it where a run can be resumed from.
  void forgetHistory() {
    linear_->forgetPreparationHistory();
    solvesSinceStartPass_ = kStartPassMemory;
    factorReusable_ = false;
    unprojectedFailures_ = 0;
    unprojectedSkips_ = 0;
  }
  /// Sets (or, with an empty function, clears) the iterate test of the following minimize() calls.
  void setIterateTest(IterateTest test) { iterateTest_ = std::move(test); }
  Objective& objective() { return objective_; }

 private:
  Objective& objective_;
  NewtonOptions options_;
  std::unique_ptr<LinearSolver> linear_;
  IterateTest iterateTest_;
  int solvesSinceStartPass_ = kStartPassMemory;  // minimize() calls since one converged without an iteration
  bool factorReusable_ = false;  // reuseFactor: the linear solver's last factor may serve the next direction
  // unprojectedNearSolution's memory: the recent solves' indefinite unprojected tries (one a solve, less one for
  // a solve whose tries all held, at most 6), and the solves left before the next try (2^failures after one).
  int unprojectedFailures_ = 0;
  int unprojectedSkips_ = 0;
  SymmetricProduct floorProduct_;  // |H| |x| for the round-off floor, on the OpenMP threads
};

}  // namespace jetshell
