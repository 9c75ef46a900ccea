#include "solvers/indefinite_factor.h"

#include <algorithm>
#include <cmath>

namespace jetshell {

bool IndefiniteFactor::factorize(const Eigen::SparseMatrix<double>& upper, std::uint64_t patternVersion) {
  using Status = CholmodFactor::Status;
  factorized_ = false;
  if (upper.rows() == 0) {  // nothing to factor (CHOLMOD refuses an empty matrix): no pivot, no direction
    negative_ = 0;
    empty_ = factorized_ = true;
    return true;
  }
  empty_ = false;
  if (!analyzed_ || patternVersion != version_) {
    analyzed_ = false;
    if (ldlt_.analyze(upper) != Status::Ok) {
      message_ = ldlt_.message();
      return false;
    }
    version_ = patternVersion;
    analyzed_ = true;
    ++analyses_;
  }
  if (ldlt_.factorizeLdlt(upper) != Status::Ok) {
    message_ = ldlt_.message() + " (the tangent stiffness is singular)";
    return false;
  }
  const Eigen::VectorXd& D = ldlt_.pivots();
  const double largest = D.size() > 0 ? D.cwiseAbs().maxCoeff() : 0.0;
  negativeBelow_ = -kRoundOffPivot * largest;
  negative_ = static_cast<int>((D.array() < negativeBelow_).count());
  factorized_ = true;
  return true;
}

bool IndefiniteFactor::negativeCurvatureDirection(Eigen::VectorXd& d) {
  if (!factorized_ || negative_ == 0 || empty_) return false;
  const Eigen::VectorXd u = (ldlt_.pivots().array() < negativeBelow_).cast<double>().matrix();
  return ldlt_.solveUnitTransposed(u, d) == CholmodFactor::Status::Ok && d.allFinite();
}

bool IndefiniteFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (factorized_ && empty_) {
    x.resize(0);
    return b.size() == 0;
  }
  return factorized_ && ldlt_.solve(b, x) == CholmodFactor::Status::Ok && x.allFinite();
}

}  // namespace jetshell
