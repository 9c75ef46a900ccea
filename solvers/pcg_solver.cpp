// Preconditioned conjugate gradients on the symmetric matrix stored as its upper triangle, for systems too
// large to factor. Preconditioners: Jacobi (1/H_ii), block-Jacobi (the inverse 3×3 vertex blocks) and
// incomplete Cholesky (Eigen::IncompleteCholesky, AMD-ordered; its pattern analysis is redone only when the
// pattern version changes) and the lagged Cholesky factor (CHOLMOD, of an earlier Hessian: successive Newton
// Hessians of a time-stepped cloth differ little, so a few CG iterations with an old factor replace most
// factorizations; when CG needs more than lagRefactorIterations, the current Hessian is factored and CG
// restarts) and the one-ring factor (CHOLMOD, of the Hessian's one-ring part with the dropped entries'
// magnitudes on the diagonal, solvers/one_ring_pattern.h: refactored every solve at about a tenth of the full
// factor's flops, its pattern analysed once per pattern version; on a bisected mesh one factor per half, the
// halves factored and applied side by side, solvers/split_factor.h). Products with H run on the OpenMP threads
// (solvers/symmetric_product.h). Negative curvature (pᵀHp <= 0) reports "not positive definite", which the base class answers with
// a diagonal shift.
#include "solvers/cholmod_factor.h"
#include "solvers/linear_solver.h"
#include "solvers/one_ring_pattern.h"
#include "solvers/split_factor.h"
#include "solvers/symmetric_product.h"
#include "solvers/timer.h"

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/OrderingMethods>

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace jetshell {
namespace {

class PcgSolver : public LinearSolver {
 public:
  explicit PcgSolver(const LinearSolverOptions& options)
      : LinearSolver(options), factor_(options.ordering, options.blasThreads), ring_(options.ordering, options.blasThreads) {
    if (options.oneRing) ring_.setPartition(options.oneRing->vertexParts());
  }
  FactorStatistics factorStatistics() const override {
    return options().preconditioner == Preconditioner::OneRingCholesky ? ring_.statistics() : factor_.statistics();
  }
  std::string name() const override {
    return std::string("pcg+") + toString(options().preconditioner);
  }

 protected:
  Attempt attempt(const Eigen::SparseMatrix<double>& upper, bool analyze, double shift, const Eigen::VectorXd& b,
                  Eigen::VectorXd& x, LinearSolveReport& report) override {
    if (options().preconditioner == Preconditioner::LaggedCholesky) return laggedAttempt(upper, analyze, shift, b, x, report);
    Timer timer;
    const bool usePrepared = takePrepared(upper, shift, analyze, report);
    if (!usePrepared) {
      const bool ready = setUpPreconditioner(upper, analyze, shift, report);
      report.factorizationSeconds += timer.seconds();
      if (!ready) return Attempt::NotPositiveDefinite;
    }
    if (narrowValid_) updateWideLag(upper, !usePrepared);

    timer.reset();
    const int budget = options().cgDirectAfter > 0 ? std::min(options().cgDirectAfter, options().cgMaxIterations)
                                                   : options().cgMaxIterations;
    const Attempt a = iterate(upper, shift, b, x, budget, report);
    report.solveSeconds += timer.seconds();
    if (a != Attempt::Failed || budget == options().cgMaxIterations) return a;
    return directAttempt(upper, shift, b, x, report);
  }

  /// LinearSolverOptions::cgDirectAfter: CG spent its budget, so the preconditioner does not capture this
  /// matrix (measured: a crushed shirt's projected Hessian took 5,895 iterations under the one-ring factor).
  /// The whole matrix is factored (CHOLMOD, analysed once per pattern version) and CG restarts with that
  /// factor, which solves it in an iteration or two.
  Attempt directAttempt(const Eigen::SparseMatrix<double>& upper, double shift, const Eigen::VectorXd& b,
                        Eigen::VectorXd& x, LinearSolveReport& report) {
    using Status = CholmodFactor::Status;
    const Timer timer;
    if (!factor_.analyzed() || directVersion_ != solvingPatternVersion()) {
      if (factor_.analyze(upper) != Status::Ok) {
        report.factorizationSeconds += timer.seconds();
        report.message = factor_.message();
        return Attempt::Fatal;
      }
      directVersion_ = solvingPatternVersion();
    }
    report.factorizationSeconds += timer.seconds();
    return solveWithFreshFactor(upper, shift, b, x, report, true);
  }

 public:
  std::function<void()> preparePreconditioner(const Eigen::SparseMatrix<double>& upper,
                                              std::uint64_t patternVersion, bool factorAhead) override {
    prepared_ = false;
    narrowValid_ = false;
    if (options().preconditioner != Preconditioner::OneRingCholesky || !options().oneRing ||
        options().oneRing->empty() || upper.rows() != 3 * options().oneRing->numVertices())
      return {};
    // A new pattern is planned here and its first solve sets up from the whole matrix (so does the first solve
    // after forgetPreparationHistory).
    bool recordOnly = !factorAhead || recordOnlyNext_;
    recordOnlyNext_ = false;
    if (!oneRingPlan_.planned() || planVersion_ != patternVersion) {
      planOneRing(upper, patternVersion);  // the coming solve finds it
      recordOnly = true;
    }
    const Eigen::SparseMatrix<double>& narrow = oneRingPlan_.apply(upper);
    const auto nnz = static_cast<std::size_t>(narrow.nonZeros());
    narrowValues_.assign(narrow.valuePtr(), narrow.valuePtr() + nnz);
    narrowValid_ = true;
    if (recordOnly) return {};
    preparedMatrix_ = narrow;
    if (wideLag_.size() == nnz) {
      double* v = preparedMatrix_.valuePtr();
      for (std::size_t q = 0; q < nnz; ++q) v[q] += wideLag_[q];
    }
    preparedVersion_ = patternVersion;
    return [this] {
      const Timer timer;
      preparedAnalyzed_ = ringChanged_ || !ring_.analyzed();
      preparedMessage_.clear();
      preparedOk_ = factorOneRing(preparedMatrix_, 0.0, preparedMessage_);
      preparedSeconds_ = timer.seconds();
      prepared_ = true;
    };
  }

  bool iterateWithLastPreconditioner(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& b,
                                     Eigen::VectorXd& x, double relativeTolerance,
                                     LinearSolveReport& report) override {
    return iterate(upper, 0.0, b, x, options().cgMaxIterations, report, relativeTolerance) == Attempt::Ok;
  }

  void discardPrepared() override {
    narrowValid_ = false;
    prepared_ = false;
  }
  void forgetPreparationHistory() override {
    discardPrepared();
    wideLag_.clear();
    recordOnlyNext_ = true;
  }

 private:
  /// Whether this attempt uses the factor prepared during assembly (shift 0, the same pattern, and the prepared
  /// factorization succeeded). Consumes it either way.
  bool takePrepared(const Eigen::SparseMatrix<double>& upper, double shift, bool analyze, LinearSolveReport& report) {
    if (!prepared_) return false;
    prepared_ = false;
    if (shift != 0.0 || preparedVersion_ != solvingPatternVersion() || upper.rows() != preparedMatrix_.rows())
      return false;
    ++report.numericFactorizations;
    report.preparedPreconditioner = true;
    report.preparedSeconds = preparedSeconds_;
    if (!preparedOk_) return false;  // the whole one-ring part is factored instead, at once
    if (analyze) report.analysisReused = !preparedAnalyzed_;
    return true;
  }

  /// The wide terms' one-ring part of this solve's H (its one-ring part minus the narrow part gathered by
  /// preparePreconditioner), for the next prepared preconditioner.
  /// gathered: the plan's result already holds upper's one-ring part (the set-up just filtered it).
  void updateWideLag(const Eigen::SparseMatrix<double>& upper, bool gathered) {
    narrowValid_ = false;
    if (!oneRingPlan_.planned() || planVersion_ != solvingPatternVersion()) return;
    const Eigen::SparseMatrix<double>& full = gathered ? oneRingPlan_.result() : oneRingPlan_.apply(upper);
    const std::size_t nnz = narrowValues_.size();
    if (static_cast<std::size_t>(full.nonZeros()) != nnz) return;
    wideLag_.resize(nnz);
    const double* v = full.valuePtr();
    for (std::size_t q = 0; q < nnz; ++q) wideLag_[q] = v[q] - narrowValues_[q];
  }

  /// Plans the one-ring filter for H's pattern (version). A filtered pattern other than the analysed one asks
  /// for a new analysis and drops the wide terms' lagged part.
  void planOneRing(const Eigen::SparseMatrix<double>& H, std::uint64_t version) {
    oneRingPlan_.plan(*options().oneRing, H);
    planVersion_ = version;
    const Eigen::SparseMatrix<double>& ring = oneRingPlan_.apply(H);
    if (!ring_.analyzed() || !sameSparsity(ring, analyzedPattern_)) {
      ringChanged_ = true;
      wideLag_.clear();
    }
  }

  /// Factors the one-ring matrix (+ shift), analysing its pattern first when it changed.
  bool factorOneRing(const Eigen::SparseMatrix<double>& oneRing, double shift, std::string& message) {
    using Status = SplitFactor::Status;
    if (ringChanged_ || !ring_.analyzed()) {
      if (ring_.analyze(oneRing) != Status::Ok) {
        message = ring_.message();
        return false;
      }
      analyzedPattern_ = oneRing;
      ringChanged_ = false;
    }
    if (ring_.factorize(oneRing, shift) != Status::Ok) {
      message = "one-ring factor: " + ring_.message();
      return false;
    }
    return true;
  }

 private:
  /// CG preconditioned by the lagged factor; refactors (current H + shift) when the factor is missing, the
  /// pattern changed, or CG with the old factor does not converge within lagRefactorIterations.
  Attempt laggedAttempt(const Eigen::SparseMatrix<double>& upper, bool analyze, double shift,
                        const Eigen::VectorXd& b, Eigen::VectorXd& x, LinearSolveReport& report) {
    using Status = CholmodFactor::Status;
    Timer timer;
    if ((analyze || !factor_.analyzed()) && factor_.analyze(upper) != Status::Ok) {
      report.factorizationSeconds += timer.seconds();
      report.message = factor_.message();
      return Attempt::Fatal;
    }
    const bool fresh = analyze || !factor_.factorized();
    report.factorizationSeconds += timer.seconds();
    if (fresh) {
      const Attempt f = refactor(upper, shift, report);
      if (f != Attempt::Ok) return f;
    }
    timer.reset();
    Attempt a = iterate(upper, shift, b, x, fresh ? options().cgMaxIterations : options().lagRefactorIterations, report);
    report.solveSeconds += timer.seconds();
    if (a != Attempt::Failed || fresh) return a;
    // The old factor no longer preconditions well: factor the current Hessian and solve again.
    return solveWithFreshFactor(upper, shift, b, x, report, false);
  }

  /// Factors the current matrix into factor_ (already analysed for its pattern) and runs CG again with that
  /// factor, the earlier iterations counted in. `direct`: counted as a cgDirectAfter fallback.
  Attempt solveWithFreshFactor(const Eigen::SparseMatrix<double>& upper, double shift, const Eigen::VectorXd& b,
                               Eigen::VectorXd& x, LinearSolveReport& report, bool direct) {
    const Attempt f = refactor(upper, shift, report);
    if (f != Attempt::Ok) return f;
    if (direct) ++report.directFallbacks;
    const Timer timer;
    const int before = report.cgIterations;
    withFactor_ = true;
    const Attempt a = iterate(upper, shift, b, x, options().cgMaxIterations, report);
    withFactor_ = false;
    report.cgIterations += before;
    report.solveSeconds += timer.seconds();
    return a;
  }

  Attempt refactor(const Eigen::SparseMatrix<double>& upper, double shift, LinearSolveReport& report) {
    using Status = CholmodFactor::Status;
    const Timer timer;
    const Status f = factor_.factorize(upper, shift);
    report.factorizationSeconds += timer.seconds();
    ++report.numericFactorizations;
    if (f == Status::Ok) return Attempt::Ok;
    report.message = factor_.message();
    return f == Status::NotPositiveDefinite ? Attempt::NotPositiveDefinite : Attempt::Fatal;
  }

  bool setUpPreconditioner(const Eigen::SparseMatrix<double>& H, bool analyze, double shift,
                           LinearSolveReport& report) {
    const Eigen::Index n = H.rows();
    switch (options().preconditioner) {
      case Preconditioner::Jacobi: {
        inverseDiagonal_.resize(n);
        const Eigen::VectorXd d = H.diagonal();
        for (Eigen::Index i = 0; i < n; ++i) {
          const double di = d[i] + shift;
          if (!(di > 0.0)) {
            report.message = "non-positive diagonal entry " + std::to_string(i);
            return false;
          }
          inverseDiagonal_[i] = 1.0 / di;
        }
        return true;
      }
      case Preconditioner::BlockJacobi: {
        if (n % 3 != 0) throw std::invalid_argument("block-Jacobi needs 3 dofs per vertex");
        inverseBlocks_.resize(static_cast<std::size_t>(n / 3));
        for (Eigen::Index v = 0; v < n / 3; ++v) {
          Eigen::Matrix3d B = Eigen::Matrix3d::Zero();
          for (int c = 0; c < 3; ++c) {
            for (Eigen::SparseMatrix<double>::InnerIterator it(H, 3 * v + c); it; ++it) {
              if (it.row() >= 3 * v && it.row() <= 3 * v + c) {
                B(it.row() - 3 * v, c) = it.value();
                B(c, it.row() - 3 * v) = it.value();
              }
            }
          }
          B.diagonal().array() += shift;
          Eigen::LLT<Eigen::Matrix3d> llt(B);
          if (llt.info() != Eigen::Success) {
            report.message = "vertex block " + std::to_string(v) + " is not positive definite";
            return false;
          }
          inverseBlocks_[static_cast<std::size_t>(v)] = llt.solve(Eigen::Matrix3d::Identity());
        }
        return true;
      }
      case Preconditioner::IncompleteCholesky: {
        const Eigen::SparseMatrix<double>* M = &H;
        if (shift != 0.0) {
          Eigen::SparseMatrix<double> I(H.rows(), H.cols());
          I.setIdentity();
          shifted_ = H + shift * I;
          M = &shifted_;
        }
        if (analyze || shift != 0.0 || !icAnalyzed_) {
          ic_.analyzePattern(*M);
          icAnalyzed_ = shift == 0.0;
        }
        ic_.factorize(*M);
        if (ic_.info() != Eigen::Success) {
          report.message = "incomplete Cholesky failed";
          return false;
        }
        return true;
      }
      case Preconditioner::OneRingCholesky: {
        if (!options().oneRing || options().oneRing->empty())
          throw std::invalid_argument("one_ring_cholesky preconditioner without the mesh's adjacency");
        // The plan follows H's pattern: re-planned whenever that pattern is new, values gathered always.
        if (!oneRingPlan_.planned() || planVersion_ != solvingPatternVersion()) planOneRing(H, solvingPatternVersion());
        const Eigen::SparseMatrix<double>& oneRing = oneRingPlan_.apply(H);
        if (analyze && !ringChanged_ && ring_.analyzed()) report.analysisReused = true;
        ++report.numericFactorizations;
        return factorOneRing(oneRing, shift, report.message);
      }
      case Preconditioner::LaggedCholesky: break;  // laggedAttempt
    }
    return false;
  }

  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
    if (withFactor_ || options().preconditioner == Preconditioner::LaggedCholesky) {
      if (factor_.solve(r, z) != CholmodFactor::Status::Ok) z = r;
      return;
    }
    switch (options().preconditioner) {
      case Preconditioner::Jacobi:
        z = inverseDiagonal_.cwiseProduct(r);
        return;
      case Preconditioner::BlockJacobi:
        z.resize(r.size());
        for (std::size_t v = 0; v < inverseBlocks_.size(); ++v) {
          const Eigen::Index i = 3 * static_cast<Eigen::Index>(v);
          z.segment<3>(i) = inverseBlocks_[v] * r.segment<3>(i);
        }
        return;
      case Preconditioner::IncompleteCholesky:
        z = ic_.solve(r);
        return;
      case Preconditioner::LaggedCholesky: return;  // above
      case Preconditioner::OneRingCholesky:
        if (ring_.solve(r, z) != SplitFactor::Status::Ok) z = r;
        return;
    }
  }

  static bool sameSparsity(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
    if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros()) return false;
    const auto n = static_cast<std::size_t>(a.cols() + 1);
    const auto nnz = static_cast<std::size_t>(a.nonZeros());
    return std::equal(a.outerIndexPtr(), a.outerIndexPtr() + n, b.outerIndexPtr()) &&
           std::equal(a.innerIndexPtr(), a.innerIndexPtr() + nnz, b.innerIndexPtr());
  }

  /// CG to relative residual `tolerance` (≤ 0: relativeTolerance()).
  Attempt iterate(const Eigen::SparseMatrix<double>& H, double shift, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                  int maxIterations, LinearSolveReport& report, double tolerance = 0.0) {
    if (!(tolerance > 0.0)) tolerance = relativeTolerance();
    const double bNorm = b.norm();
    x.setZero(b.size());
    if (bNorm == 0.0) return Attempt::Ok;
    Eigen::VectorXd r = b, z, p, Ap(b.size());
    precondition(r, z);
    p = z;
    double rz = r.dot(z);
    const double target = tolerance * bNorm;
    for (int k = 1; k <= maxIterations; ++k) {
      product_.apply(H, p, Ap, solvingPatternVersion());
      Ap += shift * p;
      const double pAp = p.dot(Ap);
      report.cgIterations = k;
      if (!(pAp > 0.0)) {
        report.message = std::isfinite(pAp) ? "negative curvature in CG" : "non-finite value in CG";
        return Attempt::NotPositiveDefinite;
      }
      const double alpha = rz / pAp;
      x += alpha * p;
      r -= alpha * Ap;
      if (r.norm() <= target) return Attempt::Ok;
      precondition(r, z);
      const double rzNew = r.dot(z);
      p = z + (rzNew / rz) * p;
      rz = rzNew;
    }
    std::ostringstream s;
    s << "CG did not reach relative residual " << tolerance << " in " << maxIterations
      << " iterations";
    report.message = s.str();
    return Attempt::Failed;
  }

  Eigen::VectorXd inverseDiagonal_;
  std::vector<Eigen::Matrix3d> inverseBlocks_;
  Eigen::IncompleteCholesky<double, Eigen::Upper, Eigen::AMDOrdering<int>> ic_;
  bool icAnalyzed_ = false;
  Eigen::SparseMatrix<double> shifted_;
  OneRingPlan oneRingPlan_;
  std::uint64_t planVersion_ = 0;  // H's pattern version the plan was made for
  bool ringChanged_ = false;       // the planned one-ring pattern is not the analysed one
  Eigen::SparseMatrix<double> analyzedPattern_;  // the one-ring matrix the factor was last analysed for
  // Preconditioning ahead (preparePreconditioner): the narrow terms' one-ring values of the coming solve, the
  // wide terms' one-ring part of the last solve (same positions), and the prepared matrix and its outcome.
  std::vector<double> narrowValues_, wideLag_;
  bool narrowValid_ = false;
  bool recordOnlyNext_ = false;  // the next preparation only records (forgetPreparationHistory)
  Eigen::SparseMatrix<double> preparedMatrix_;
  std::uint64_t preparedVersion_ = 0;
  bool prepared_ = false, preparedOk_ = false, preparedAnalyzed_ = false;
  double preparedSeconds_ = 0.0;
  std::string preparedMessage_;  // why the prepared factorization failed
  CholmodFactor factor_;  // the lagged factor, or the whole matrix's after CG spent cgDirectAfter iterations
  std::uint64_t directVersion_ = 0;    // the pattern version factor_ was analysed for in directAttempt
  bool withFactor_ = false;            // CG runs with factor_ (solveWithFreshFactor)
  SplitFactor ring_;      // the one-ring factor
  SymmetricProduct product_;
};

}  // namespace

std::unique_ptr<LinearSolver> makePcgSolver(const LinearSolverOptions& options) {
  return std::make_unique<PcgSolver>(options);
}

}  // namespace jetshell
