#include "solvers/linear_solver.h"

#include "core/mesh.h"
#include "solvers/timer.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace jetshell {

LinearSolverType linearSolverTypeFromString(const std::string& name) {
  if (name == "auto") return LinearSolverType::Auto;
  if (name == "cholmod") return LinearSolverType::Cholmod;
  if (name == "ldlt") return LinearSolverType::EigenLDLT;
  if (name == "pcg") return LinearSolverType::PCG;
  throw InputError("linear solver '" + name + "': expected auto, cholmod, ldlt or pcg");
}

const char* toString(LinearSolverType t) {
  switch (t) {
    case LinearSolverType::Auto: return "auto";
    case LinearSolverType::Cholmod: return "cholmod";
    case LinearSolverType::EigenLDLT: return "ldlt";
    case LinearSolverType::PCG: return "pcg";
  }
  return "?";
}

Preconditioner preconditionerFromString(const std::string& name) {
  if (name == "jacobi") return Preconditioner::Jacobi;
  if (name == "block_jacobi") return Preconditioner::BlockJacobi;
  if (name == "ic") return Preconditioner::IncompleteCholesky;
  if (name == "lagged_cholesky") return Preconditioner::LaggedCholesky;
  if (name == "one_ring_cholesky") return Preconditioner::OneRingCholesky;
  throw InputError("preconditioner '" + name +
                   "': expected jacobi, block_jacobi, ic, lagged_cholesky or one_ring_cholesky");
}

int oneRingPartsFromString(const std::string& name) {
  if (name == "auto") return 0;
  if (name == "1") return 1;
  if (name == "2") return 2;
  throw InputError("one-ring parts '" + name + "': expected auto, 1 or 2");
}

const char* toString(Preconditioner p) {
  switch (p) {
    case Preconditioner::Jacobi: return "jacobi";
    case Preconditioner::BlockJacobi: return "block_jacobi";
    case Preconditioner::IncompleteCholesky: return "ic";
    case Preconditioner::LaggedCholesky: return "lagged_cholesky";
    case Preconditioner::OneRingCholesky: return "one_ring_cholesky";
  }
  return "?";
}

namespace {

/// Mean |H_ii| over the free dofs: the scale of the regularizing shift.
double meanDiagonal(const Eigen::SparseMatrix<double>& upper, const std::vector<char>* fixedDof) {
  double sum = 0.0;
  int count = 0;
  for (int j = 0; j < upper.outerSize(); ++j) {
    if (fixedDof != nullptr && (*fixedDof)[static_cast<std::size_t>(j)]) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(upper, j); it; ++it) {
      if (it.row() == j && std::isfinite(it.value())) {
        sum += std::abs(it.value());
        ++count;
      }
    }
  }
  return count > 0 && sum > 0.0 ? sum / count : 1.0;
}

/// The failed tries of one solve, each run of tries that failed for the same reason once, with the diagonal
/// shifts it covered: "not positive definite at column 398 (11 tries: no shift, then shift 1e-08 to 100)".
std::string describeTries(const std::vector<std::pair<std::string, double>>& tries) {
  std::ostringstream s;
  for (std::size_t i = 0; i < tries.size();) {
    std::size_t j = i;
    while (j < tries.size() && tries[j].first == tries[i].first) ++j;
    s << (i > 0 ? "; " : "") << tries[i].first;
    const double from = tries[i].second, to = tries[j - 1].second;
    if (j - i > 1) {
      const double first = from == 0.0 ? tries[i + 1].second : from;
      s << " (" << (j - i) << " tries: " << (from == 0.0 ? "no shift, then shift " : "shift ") << first;
      if (to != first) s << " to " << to;
      s << ")";
    } else if (from > 0.0) {
      s << " (shift " << from << ")";
    }
    i = j;
  }
  return s.str();
}

}  // namespace

LinearSolveReport LinearSolver::solve(const Eigen::SparseMatrix<double>& upper, std::uint64_t patternVersion,
                                      const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                      const std::vector<char>* fixedDof, int maxRegularizations) {
  LinearSolveReport report;
  if (upper.rows() != upper.cols() || upper.rows() != b.size() || !upper.isCompressed())
    throw std::invalid_argument("LinearSolver::solve: H must be square, compressed and match b");
  if (!b.allFinite()) {
    report.message = "right-hand side is not finite";
    return report;
  }
  const bool analyze = !analyzed_ || patternVersion != analyzedVersion_;
  factorValid_ = false;
  solvingVersion_ = patternVersion;
  double shift = 0.0;
  std::vector<std::pair<std::string, double>> tries;  // each failed try's reason and diagonal shift
  const int maxRetries = maxRegularizations >= 0 ? maxRegularizations : options_.maxRegularizations;
  for (int k = 0; k <= maxRetries; ++k) {
    if (k > 0) {
      shift = shift == 0.0 ? 1e-8 * meanDiagonal(upper, fixedDof) : 10.0 * shift;
      report.regularizations = k;
    }
    report.message.clear();
    const Attempt a = attempt(upper, analyze && k == 0, shift, b, x, report);
    if (analyze && k == 0 && a != Attempt::Fatal) {
      report.symbolicAnalysis = !report.analysisReused;
      analyzed_ = true;
      analyzedVersion_ = patternVersion;
      if (report.symbolicAnalysis) ++analyses_;
    }
    if (a == Attempt::Ok && x.allFinite()) {
      report.success = true;
      factorValid_ = true;
      factorShift_ = shift;
      report.shift = shift;
      report.positiveDefinite = k == 0 && factorProvesDefiniteness();
      if (k > 0) {
        std::ostringstream s;
        s << "regularized with shift " << shift << " after " << k << " retr" << (k == 1 ? "y" : "ies") << " ("
          << describeTries(tries) << ")";
        report.message = s.str();
      }
      return report;
    }
    if (a == Attempt::Ok) report.message = "non-finite solution";
    tries.emplace_back(report.message.empty() ? "failed" : report.message, shift);
    if (a == Attempt::Fatal) break;
  }
  report.success = false;
  report.message = "linear solve failed: " + describeTries(tries);
  return report;
}

bool LinearSolver::solveWithLastFactor(std::uint64_t patternVersion, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!lastFactorApplies(patternVersion, b)) return false;
  return solveWithFactor(b, x) && x.allFinite();
}

bool LinearSolver::solveLastSystem(const Eigen::SparseMatrix<double>& upper, std::uint64_t patternVersion,
                                   const Eigen::VectorXd& b, Eigen::VectorXd& x, double relativeTolerance,
                                   LinearSolveReport& report) {
  if (!lastFactorApplies(patternVersion, b) || factorShift_ != 0.0 || upper.rows() != b.size()) return false;
  const Timer timer;
  const bool solved =
      solveWithFactor(b, x) || iterateWithLastPreconditioner(upper, b, x, relativeTolerance, report);
  report.solveSeconds += timer.seconds();
  return solved && x.allFinite();
}

std::unique_ptr<LinearSolver> makeLinearSolver(const LinearSolverOptions& options, int numDofs) {
  switch (options.type) {
    case LinearSolverType::Cholmod: return makeCholmodSolver(options);
    case LinearSolverType::EigenLDLT: return makeEigenLdltSolver(options);
    case LinearSolverType::PCG: return makePcgSolver(options);
    case LinearSolverType::Auto: break;
  }
  return numDofs <= options.autoDirectMaxDofs ? makeCholmodSolver(options) : makePcgSolver(options);
}

}  // namespace jetshell
