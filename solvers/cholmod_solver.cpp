// CHOLMOD supernodal LLᵀ (solvers/cholmod_factor.h): cholmod_analyze once per pattern version,
// cholmod_factorize_p per solve with the regularizing shift as its β (it factors H + βI, no matrix copy).
#include "solvers/cholmod_factor.h"
#include "solvers/linear_solver.h"
#include "solvers/timer.h"

namespace jetshell {
namespace {

class CholmodSolver : public LinearSolver {
 public:
  explicit CholmodSolver(const LinearSolverOptions& options) : LinearSolver(options), factor_(options.ordering, options.blasThreads) {}
  std::string name() const override { return "cholmod"; }
  FactorStatistics factorStatistics() const override { return factor_.statistics(); }

 protected:
  bool factorProvesDefiniteness() const override { return true; }  // LLᵀ fails on a non-positive pivot
  Attempt attempt(const Eigen::SparseMatrix<double>& upper, bool analyze, double shift, const Eigen::VectorXd& b,
                  Eigen::VectorXd& x, LinearSolveReport& report) override {
    using Status = CholmodFactor::Status;
    Timer timer;
    if (analyze && factor_.analyze(upper) != Status::Ok) {
      report.factorizationSeconds += timer.seconds();
      report.message = factor_.message();
      return Attempt::Fatal;
    }
    const Status f = factor_.factorize(upper, shift);
    report.factorizationSeconds += timer.seconds();
    ++report.numericFactorizations;
    if (f != Status::Ok) {
      report.message = factor_.message();
      return f == Status::NotPositiveDefinite ? Attempt::NotPositiveDefinite : Attempt::Fatal;
    }
    timer.reset();
    const Status s = factor_.solve(b, x);
    report.solveSeconds += timer.seconds();
    if (s != Status::Ok) {
      report.message = factor_.message();
      return Attempt::Fatal;
    }
    return Attempt::Ok;
  }
  bool solveWithFactor(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    return factor_.factorized() && factor_.solve(b, x) == CholmodFactor::Status::Ok;
  }

 private:
  CholmodFactor factor_;
};

}  // namespace

std::unique_ptr<LinearSolver> makeCholmodSolver(const LinearSolverOptions& options) {
  return std::make_unique<CholmodSolver>(options);
}

}  // namespace jetshell
