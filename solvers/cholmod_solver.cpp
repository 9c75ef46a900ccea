// CHOLMOD supernodal LLᵀ on the assembler's upper triangle, wrapped without copying (stype = 1).
// cholmod_analyze runs once per pattern version; cholmod_factorize_p refactors the values in place and takes
// the regularizing shift as its beta (it factors H + βI), so a retry costs no matrix copy either.
#include "solvers/linear_solver.h"
#include "solvers/timer.h"

#include <cholmod.h>

#include <sstream>

namespace jetshell {
namespace {

class CholmodSolver : public LinearSolver {
 public:
  explicit CholmodSolver(const LinearSolverOptions& options) : LinearSolver(options) {
    cholmod_start(&common_);
    common_.supernodal = CHOLMOD_SUPERNODAL;
    // A non-positive-definite matrix is retried with a shift, so the partial factor is of no use.
    common_.quick_return_if_not_posdef = 1;
    common_.print = 0;
  }
  ~CholmodSolver() override {
    if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
    if (X_ != nullptr) cholmod_free_dense(&X_, &common_);
    if (Y_ != nullptr) cholmod_free_dense(&Y_, &common_);
    if (E_ != nullptr) cholmod_free_dense(&E_, &common_);
    cholmod_finish(&common_);
  }
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  std::string name() const override { return "cholmod"; }

 protected:
  Attempt attempt(const Eigen::SparseMatrix<double>& upper, bool analyze, double shift, const Eigen::VectorXd& b,
                  Eigen::VectorXd& x, LinearSolveReport& report) override {
    cholmod_sparse A = view(upper);
    Timer timer;
    if (analyze) {
      if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
      factor_ = cholmod_analyze(&A, &common_);
      if (factor_ == nullptr) {
        report.factorizationSeconds += timer.seconds();
        report.message = statusMessage("cholmod_analyze");
        return Attempt::Fatal;
      }
    }
    double beta[2] = {shift, 0.0};
    const int ok = cholmod_factorize_p(&A, beta, nullptr, 0, factor_, &common_);
    report.factorizationSeconds += timer.seconds();
    if (common_.status == CHOLMOD_NOT_POSDEF || factor_->minor < factor_->n) {
      std::ostringstream s;
      s << "not positive definite at column " << factor_->minor;
      report.message = s.str();
      return Attempt::NotPositiveDefinite;
    }
    if (!ok || common_.status < CHOLMOD_OK) {
      report.message = statusMessage("cholmod_factorize");
      return Attempt::Fatal;
    }
    timer.reset();
    cholmod_dense B;
    B.nrow = B.d = B.nzmax = static_cast<std::size_t>(b.size());
    B.ncol = 1;
    B.x = const_cast<double*>(b.data());
    B.z = nullptr;
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    const int solved = cholmod_solve2(CHOLMOD_A, factor_, &B, nullptr, &X_, nullptr, &Y_, &E_, &common_);
    if (solved) x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(X_->x), b.size());
    report.solveSeconds += timer.seconds();
    if (!solved) {
      report.message = statusMessage("cholmod_solve2");
      return Attempt::Fatal;
    }
    return Attempt::Ok;
  }

 private:
  /// A CHOLMOD view of the Eigen matrix's arrays (no copy). CHOLMOD reads but never writes A.
  static cholmod_sparse view(const Eigen::SparseMatrix<double>& m) {
    cholmod_sparse A;
    A.nrow = static_cast<std::size_t>(m.rows());
    A.ncol = static_cast<std::size_t>(m.cols());
    A.nzmax = static_cast<std::size_t>(m.nonZeros());
    A.p = const_cast<int*>(m.outerIndexPtr());
    A.i = const_cast<int*>(m.innerIndexPtr());
    A.nz = nullptr;
    A.x = const_cast<double*>(m.valuePtr());
    A.z = nullptr;
    A.stype = 1;  // upper triangle stored
    A.itype = CHOLMOD_INT;
    A.xtype = CHOLMOD_REAL;
    A.dtype = CHOLMOD_DOUBLE;
    A.sorted = 1;
    A.packed = 1;
    return A;
  }

  std::string statusMessage(const char* what) const {
    std::ostringstream s;
    s << what << " failed (CHOLMOD status " << common_.status << ")";
    return s.str();
  }

  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
  cholmod_dense* X_ = nullptr;
  cholmod_dense* Y_ = nullptr;
  cholmod_dense* E_ = nullptr;
};

}  // namespace

std::unique_ptr<LinearSolver> makeCholmodSolver(const LinearSolverOptions& options) {
  return std::make_unique<CholmodSolver>(options);
}

}  // namespace jetshell
