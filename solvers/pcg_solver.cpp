// Preconditioned conjugate gradients on the symmetric matrix stored as its upper triangle, for systems too
// large to factor. Preconditioners: Jacobi (1/H_ii), block-Jacobi (the inverse 3×3 vertex blocks) and
// incomplete Cholesky (Eigen::IncompleteCholesky, AMD-ordered; its pattern analysis is redone only when the
// pattern version changes) and the lagged Cholesky factor (CHOLMOD, of an earlier Hessian: successive Newton
// Hessians of a time-stepped cloth differ little, so a few CG iterations with an old factor replace most
// factorizations; when CG needs more than lagRefactorIterations, the current Hessian is factored and CG
// restarts) and the one-ring factor (CHOLMOD, of the Hessian's one-ring part with the dropped entries'
// magnitudes on the diagonal, solvers/one_ring_pattern.h: refactored every solve at about a tenth of the full
// factor's flops, its pattern analysed once per pattern version). Products with H run on the OpenMP threads
// (solvers/symmetric_product.h). Negative curvature (pᵀHp <= 0) reports "not positive definite", which the base class answers with
// a diagonal shift.
#include "solvers/cholmod_factor.h"
#include "solvers/linear_solver.h"
#include "solvers/one_ring_pattern.h"
#include "solvers/symmetric_product.h"
#include "solvers/timer.h"

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/OrderingMethods>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace jetshell {
namespace {

class PcgSolver : public LinearSolver {
 public:
  explicit PcgSolver(const LinearSolverOptions& options) : LinearSolver(options), factor_(options.ordering, options.blasThreads) {}
  FactorStatistics factorStatistics() const override { return factor_.statistics(); }
  std::string name() const override {
    return std::string("pcg+") + toString(options().preconditioner);
  }

 protected:
  Attempt attempt(const Eigen::SparseMatrix<double>& upper, bool analyze, double shift, const Eigen::VectorXd& b,
                  Eigen::VectorXd& x, LinearSolveReport& report) override {
    if (options().preconditioner == Preconditioner::LaggedCholesky) return laggedAttempt(upper, analyze, shift, b, x, report);
    Timer timer;
    const bool ready = setUpPreconditioner(upper, analyze, shift, report);
    report.factorizationSeconds += timer.seconds();
    if (!ready) return Attempt::NotPositiveDefinite;

    timer.reset();
    const Attempt a = iterate(upper, shift, b, x, options().cgMaxIterations, report);
    report.solveSeconds += timer.seconds();
    return a;
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
    const Attempt f = refactor(upper, shift, report);
    if (f != Attempt::Ok) return f;
    timer.reset();
    const int before = report.cgIterations;
    a = iterate(upper, shift, b, x, options().cgMaxIterations, report);
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
        using Status = CholmodFactor::Status;
        if (!options().oneRing || options().oneRing->empty())
          throw std::invalid_argument("one_ring_cholesky preconditioner without the mesh's adjacency");
        // The plan follows H's pattern: re-planned whenever that pattern is new (analyze), values gathered always.
        if (analyze || !oneRingPlan_.planned()) oneRingPlan_.plan(*options().oneRing, H);
        const Eigen::SparseMatrix<double>& oneRing = oneRingPlan_.apply(H);
        // The one-ring part's pattern is the mesh's: contact pairs between distant vertices change H's pattern
        // but not this one, so the analysis is redone only when the filtered pattern itself changed. Its
        // pattern follows H's alone, so it is compared only when H's pattern is new.
        const bool samePattern =
            factor_.analyzed() && (!analyze || sameSparsity(oneRing, analyzedPattern_));
        if (!samePattern) {
          if (factor_.analyze(oneRing) != Status::Ok) {
            report.message = factor_.message();
            return false;
          }
          analyzedPattern_ = oneRing;
        } else if (analyze) {
          report.analysisReused = true;
        }
        ++report.numericFactorizations;
        if (factor_.factorize(oneRing, shift) != Status::Ok) {
          report.message = "one-ring factor: " + factor_.message();
          return false;
        }
        return true;
      }
      case Preconditioner::LaggedCholesky: break;  // laggedAttempt
    }
    return false;
  }

  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
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
      case Preconditioner::LaggedCholesky:
      case Preconditioner::OneRingCholesky:
        if (factor_.solve(r, z) != CholmodFactor::Status::Ok) z = r;
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

  Attempt iterate(const Eigen::SparseMatrix<double>& H, double shift, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                  int maxIterations, LinearSolveReport& report) {
    const double bNorm = b.norm();
    x.setZero(b.size());
    if (bNorm == 0.0) return Attempt::Ok;
    Eigen::VectorXd r = b, z, p, Ap(b.size());
    precondition(r, z);
    p = z;
    double rz = r.dot(z);
    const double target = relativeTolerance() * bNorm;
    for (int k = 1; k <= maxIterations; ++k) {
      product_.apply(H, p, Ap);
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
    s << "CG did not reach relative residual " << relativeTolerance() << " in " << maxIterations
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
  Eigen::SparseMatrix<double> analyzedPattern_;  // the one-ring matrix the factor was last analysed for
  CholmodFactor factor_;
  SymmetricProduct product_;
};

}  // namespace

std::unique_ptr<LinearSolver> makePcgSolver(const LinearSolverOptions& options) {
  return std::make_unique<PcgSolver>(options);
}

}  // namespace jetshell
