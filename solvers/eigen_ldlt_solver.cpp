// Eigen's SimplicialLDLT (AMD ordering) on the upper triangle: the fallback that needs nothing beyond Eigen.
// analyzePattern once per pattern version; the shift goes through setShift (it factors H + δI). A factor with a
// non-positive D is rejected so that the Newton direction stays a descent direction.
#include "solvers/linear_solver.h"
#include "solvers/timer.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

namespace jetshell {
namespace {

class EigenLdltSolver : public LinearSolver {
 public:
  explicit EigenLdltSolver(const LinearSolverOptions& options) : LinearSolver(options) {}
  std::string name() const override { return "ldlt"; }

 protected:
  bool factorProvesDefiniteness() const override { return true; }  // attempt() fails on a non-positive pivot
  Attempt attempt(const Eigen::SparseMatrix<double>& upper, bool analyze, double shift, const Eigen::VectorXd& b,
                  Eigen::VectorXd& x, LinearSolveReport& report) override {
    Timer timer;
    if (analyze) ldlt_.analyzePattern(upper);
    ldlt_.setShift(shift);
    ldlt_.factorize(upper);
    const bool factored = ldlt_.info() == Eigen::Success;
    bool positive = factored;
    if (factored) {
      const Eigen::VectorXd& D = ldlt_.vectorD();
      for (Eigen::Index i = 0; i < D.size() && positive; ++i) positive = D[i] > 0.0;  // NaN fails too
    }
    report.factorizationSeconds += timer.seconds();
    if (!factored) {
      report.message = "SimplicialLDLT: zero pivot";
      return Attempt::NotPositiveDefinite;
    }
    if (!positive) {
      report.message = "SimplicialLDLT: non-positive pivot";
      return Attempt::NotPositiveDefinite;
    }
    timer.reset();
    x = ldlt_.solve(b);
    report.solveSeconds += timer.seconds();
    return Attempt::Ok;
  }

 private:
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper, Eigen::AMDOrdering<int>> ldlt_;
};

}  // namespace

std::unique_ptr<LinearSolver> makeEigenLdltSolver(const LinearSolverOptions& options) {
  return std::make_unique<EigenLdltSolver>(options);
}

}  // namespace jetshell
