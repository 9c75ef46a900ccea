// Sparse symmetric linear solvers for Newton steps: H d = −g with H given as its upper triangle (CSC, the
// HessianAssembler's matrix).
//
// Every solver follows the same contract:
//  - The symbolic part (ordering, elimination tree, supernodes) is redone only when the pattern version changes,
//    so one analysis serves every iteration of every step while the pattern stays the same.
//  - H must be positive definite for a descent direction. When it is not (a non-positive pivot, negative
//    curvature in CG, a singular matrix), the solver retries with H + δI, δ = 1e-8 × mean |diag H| (free dofs)
//    growing ×10 per retry, and reports the retries and the δ that worked.
//  - A solution with non-finite entries is a failure, never returned as a success.
#pragma once

#include "core/assembly.h"
#include "solvers/fill_ordering.h"
#include "solvers/one_ring_pattern.h"

#include <Eigen/Sparse>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

enum class LinearSolverType {
  Auto,       // CHOLMOD up to autoDirectMaxDofs unknowns, PCG with incomplete Cholesky above
  Cholmod,    // CHOLMOD supernodal LLᵀ
  EigenLDLT,  // Eigen::SimplicialLDLT (the fallback without SuiteSparse features)
  PCG         // preconditioned conjugate gradients
};
/// LaggedCholesky: the CHOLMOD factor of an earlier Hessian, kept across iterations and steps and refactored
/// (with the current Hessian) only when CG needs more than lagRefactorIterations with it.
/// OneRingCholesky: the CHOLMOD factor of the Hessian's one-ring part (solvers/one_ring_pattern.h), refactored
/// every solve: about a tenth of the full factor's flops on a shell Hessian (bending couples two-rings).
enum class Preconditioner { Jacobi, BlockJacobi, IncompleteCholesky, LaggedCholesky, OneRingCholesky };

LinearSolverType linearSolverTypeFromString(const std::string& name);  // auto | cholmod | ldlt | pcg
const char* toString(LinearSolverType t);
/// jacobi | block_jacobi | ic | lagged_cholesky | one_ring_cholesky
Preconditioner preconditionerFromString(const std::string& name);
const char* toString(Preconditioner p);

struct LinearSolverOptions {
  LinearSolverType type = LinearSolverType::Auto;
  Preconditioner preconditioner = Preconditioner::IncompleteCholesky;  // PCG only
  FillOrdering ordering = FillOrdering::Auto;  // CHOLMOD factors (direct and lagged preconditioner)
  int blasThreads = 1;  // threads of CHOLMOD's BLAS (solvers/cholmod_factor.h)
  /// The mesh's vertex adjacency, needed by the OneRingCholesky preconditioner (solvers/dynamics.cpp fills it
  /// from the system's mesh when it is empty, split in oneRingParts).
  std::shared_ptr<const OneRingFilter> oneRing;
  /// 2: the one-ring preconditioner of a mesh of kMinBisectedVertices or more is cut in two halves
  /// (solvers/vertex_bisection.h), factored and applied one per core (solvers/split_factor.h); 1: one factor;
  /// 0 (auto): 2 when the objective's stencils move (contact), 1 otherwise. Where stencils stay, the factor is
  /// computed during the assembly (NewtonOptions::overlapPreconditioner), so no core waits for it, and the cut
  /// only costs CG iterations (the 10k-vertex cloth: 3× as many, 0.8× the steps per second); with contact it
  /// runs alone after the assembly, and the halves put both cores on it (the T-shirt: 1.35× the steps per
  /// second, BENCHMARKS.md "Contact").
  int oneRingParts = 0;
  /// Auto chooses CHOLMOD at or below this many dofs (direct factorization of shell Hessians stays cheap on
  /// 2D meshes: nested-dissection fill grows as n log n).
  int autoDirectMaxDofs = 300000;
  double cgRelativeTolerance = 1e-10;  // ‖r‖ ≤ tol ‖b‖
  int cgMaxIterations = 20000;
  /// PCG (every preconditioner but the lagged factor): when CG has not converged after this many iterations,
  /// the whole matrix is factored and CG finishes with that factor (0: never). Time steps set 100
  /// (solvers/time_step_policy.cpp); their solves take 1-32 iterations on the T-shirt.
  int cgDirectAfter = 0;
  int lagRefactorIterations = 12;  // LaggedCholesky: refactor when CG with the old factor needs more
  /// Diagonal-shift retries before giving up (δ from 1e-8 to 1e-8·10^(n−1) times the mean diagonal).
  int maxRegularizations = 10;
};

/// How many parts the one-ring preconditioner of a system takes: oneRingParts when set (1 or 2), else (auto)
/// 2 when the objective's stencils move and 1 when they stay.
inline int oneRingPartsFor(const LinearSolverOptions& o, bool movingStencils) {
  return o.oneRingParts > 0 ? o.oneRingParts : (movingStencils ? 2 : 1);
}
/// LinearSolverOptions::oneRingParts from its name: auto (0) | 1 | 2.
int oneRingPartsFromString(const std::string& name);

/// The outcome of one solve.
struct LinearSolveReport {
  bool success = false;
  bool symbolicAnalysis = false;  // this solve (re)did the symbolic analysis
  bool analysisReused = false;    // set by a solver whose factored pattern did not change with H's pattern
  int regularizations = 0;        // retries with a diagonal shift
  double shift = 0.0;             // the δ of the successful attempt (0 = none)
  /// A direct solver factored H itself, unshifted, as LLᵀ or as LDLᵀ with a positive D: H is positive definite
  /// (a statement about the matrix solved; iterative solvers never make it).
  bool positiveDefinite = false;
  int cgIterations = 0;
  int numericFactorizations = 0;      // Cholesky factorizations done (direct, or the lagged preconditioner)
  int directFallbacks = 0;            // PCG solves finished with the whole matrix's factor (cgDirectAfter)
  double factorizationSeconds = 0.0;  // analysis + numeric factorization, or preconditioner set-up
  double solveSeconds = 0.0;          // triangular solves, or CG iterations
  /// The preconditioner was factored ahead, while the Hessian's wide terms were assembled
  /// (LinearSolver::preparePreconditioner); its time is inside the assembly's, not in factorizationSeconds.
  bool preparedPreconditioner = false;
  double preparedSeconds = 0.0;       // that factorization's own time (overlapped)
  std::string message;                // why it failed, or what was retried
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;

  /// Solves H x = b. upper: the upper triangle of the symmetric H (compressed CSC). patternVersion: changes
  /// whenever the sparsity pattern changes. fixedDof (size n or null) marks identity rows, left out of the
  /// shift's scale. maxRegularizations >= 0 overrides the options' retry count (0: report an indefinite H
  /// instead of shifting it). On failure x is left unspecified (but the report says so).
  LinearSolveReport solve(const Eigen::SparseMatrix<double>& upper, std::uint64_t patternVersion,
                          const Eigen::VectorXd& b, Eigen::VectorXd& x, const std::vector<char>* fixedDof = nullptr,
                          int maxRegularizations = -1);
  /// The same for an assembler's current matrix.
  LinearSolveReport solve(const HessianAssembler& assembler, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                          int maxRegularizations = -1) {
    return solve(assembler.matrix(), assembler.patternVersion(), b, x, &assembler.fixedDof(), maxRegularizations);
  }

  /// Solves H x = b with the factor the last successful solve() left, without assembling or factoring anything
  /// (modified Newton, NewtonOptions::reuseFactor). False, x unspecified, when the solver keeps no factor
  /// (iterative solvers), the last solve failed, or patternVersion is not the one that factor was taken on.
  bool solveWithLastFactor(std::uint64_t patternVersion, const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// Solves the last successful solve's system again for a new right-hand side, nothing assembled or factored:
  /// a direct solver with its factor, an iterative one by CG to relativeTolerance with its last preconditioner
  /// on `upper`, which must still hold that solve's matrix. False, x unspecified, when the last solve failed, was
  /// shifted, or patternVersion is not its pattern. Adds its times and CG iterations to the report.
  bool solveLastSystem(const Eigen::SparseMatrix<double>& upper, std::uint64_t patternVersion,
                       const Eigen::VectorXd& b, Eigen::VectorXd& x, double relativeTolerance,
                       LinearSolveReport& report);

  /// Preconditioning ahead of the solve, overlapped with assembly. Called while `upper` (the assembler's matrix,
  /// of pattern `patternVersion`) holds only the terms with narrow stencils (at most one triangle: membrane,
  /// inertia, vertex and pair contacts); the wide ones (bending, two-ring stencils) are still to be added. A
  /// solver that can use it copies what it needs now and, with factorAhead, returns a task that builds its
  /// preconditioner for the coming solve, to run while the wide terms are assembled; the next solve() then uses
  /// that preconditioner (at shift 0; a shifted retry sets up its own). Without factorAhead it only records, and
  /// the coming solve sets its preconditioner up from the whole matrix as usual. Returns an empty function when
  /// there is no task (the default: solvers with no use for it).
  /// The one-ring preconditioner (solvers/pcg_solver.cpp) factors the narrow part's one-ring entries plus the
  /// wide terms' one-ring part of the previous solve: the wide terms lag by one Newton iteration (at a time
  /// step's first iteration, the previous step's last) in the preconditioner only; CG still solves with the whole
  /// current Hessian, so the direction is the same to CG's tolerance. The first solve on a new pattern sets up
  /// from the whole matrix.
  virtual std::function<void()> preparePreconditioner(const Eigen::SparseMatrix<double>& upper,
                                                      std::uint64_t patternVersion, bool factorAhead) {
    (void)upper;
    (void)patternVersion;
    (void)factorAhead;
    return {};
  }
  /// Drops a prepared preconditioner not yet used (a Newton solve calls it when it ends, so a later solve of
  /// another matrix, such as a sensitivity, sets up its own).
  virtual void discardPrepared() {}
  /// Forgets also what earlier solves left for the next prepared preconditioner (the wide terms' part), and
  /// makes the next solve set its preconditioner up from its whole matrix, as a new solver's first solve does:
  /// after it the solver behaves as a new one (a time integrator calls it where a run can be resumed from a
  /// checkpoint, so the resumed run repeats the uninterrupted one bit for bit).
  virtual void forgetPreparationHistory() {}

  /// nnz(L), flops and ordering of the last symbolic analysis of a Cholesky factor (zeros when the solver has
  /// none).
  virtual FactorStatistics factorStatistics() const { return {}; }

  /// Symbolic analyses done so far (one per distinct pattern when all goes well).
  int symbolicAnalyses() const { return analyses_; }

  /// Iterative solvers: the relative residual of the next solves instead of options.cgRelativeTolerance (an
  /// inexact Newton method's forcing term, solvers/newton.h); 0 restores the options' value. Direct solvers
  /// ignore it.
  void setRelativeTolerance(double tolerance) { relativeTolerance_ = tolerance > 0.0 ? tolerance : 0.0; }
  double relativeTolerance() const {
    return relativeTolerance_ > 0.0 ? relativeTolerance_ : options_.cgRelativeTolerance;
  }

 protected:
  explicit LinearSolver(const LinearSolverOptions& options) : options_(options) {}
  const LinearSolverOptions& options() const { return options_; }
  /// The pattern version of the solve in progress (for attempt()).
  std::uint64_t solvingPatternVersion() const { return solvingVersion_; }

  /// A successful unshifted attempt() factored H itself and would have failed on an H that is not positive
  /// definite (the direct solvers; sets LinearSolveReport::positiveDefinite).
  virtual bool factorProvesDefiniteness() const { return false; }

  /// Failed: a shift may help (e.g. CG did not converge). Fatal: it will not (e.g. out of memory).
  enum class Attempt { Ok, NotPositiveDefinite, Failed, Fatal };
  /// One attempt at (H + shift·I) x = b. Implementations redo their symbolic analysis when `analyze` is true,
  /// add their phase times to the report, and put a reason into report.message when they fail.
  virtual Attempt attempt(const Eigen::SparseMatrix<double>& upper, bool analyze, double shift,
                          const Eigen::VectorXd& b, Eigen::VectorXd& x, LinearSolveReport& report) = 0;
  /// x = the last successful attempt's factor applied to b; false when the solver keeps none.
  virtual bool solveWithFactor(const Eigen::VectorXd& /*b*/, Eigen::VectorXd& /*x*/) { return false; }
  /// Iterative solvers: x from CG on upper (unshifted) to relativeTolerance, with the last successful attempt's
  /// preconditioner; false when the solver keeps none or CG does not get there.
  virtual bool iterateWithLastPreconditioner(const Eigen::SparseMatrix<double>& /*upper*/,
                                             const Eigen::VectorXd& /*b*/, Eigen::VectorXd& /*x*/,
                                             double /*relativeTolerance*/, LinearSolveReport& /*report*/) {
    return false;
  }

 private:
  /// The last solve() succeeded on the pattern patternVersion, and b is finite: its factor may be applied to b.
  bool lastFactorApplies(std::uint64_t patternVersion, const Eigen::VectorXd& b) const {
    return factorValid_ && patternVersion == analyzedVersion_ && b.allFinite();
  }

  LinearSolverOptions options_;
  std::uint64_t analyzedVersion_ = 0;
  std::uint64_t solvingVersion_ = 0;
  bool analyzed_ = false;
  bool factorValid_ = false;  // the last solve() succeeded (solveWithLastFactor)
  double factorShift_ = 0.0;  // the last successful solve()'s diagonal shift (solveLastSystem)
  int analyses_ = 0;
  double relativeTolerance_ = 0.0;
};

/// The solver for `numDofs` unknowns that `options` asks for (Auto resolved here).
std::unique_ptr<LinearSolver> makeLinearSolver(const LinearSolverOptions& options, int numDofs);

std::unique_ptr<LinearSolver> makeCholmodSolver(const LinearSolverOptions& options);
std::unique_ptr<LinearSolver> makeEigenLdltSolver(const LinearSolverOptions& options);
std::unique_ptr<LinearSolver> makePcgSolver(const LinearSolverOptions& options);

}  // namespace jetshell
