#include "solvers/indefinite_factor.h"

#include <algorithm>
#include <cmath>

namespace jetshell {

bool IndefiniteFactor::factorize(const Eigen::SparseMatrix<double>& upper, std::uint64_t patternVersion) {
  if (!analyzed_ || patternVersion != version_) {
    ldlt_.analyzePattern(upper);
    version_ = patternVersion;
    analyzed_ = true;
    ++analyses_;
  }
  ldlt_.factorize(upper);
  if (ldlt_.info() != Eigen::Success) {
    message_ = "LDLT: zero pivot (the tangent stiffness is singular)";
    return false;
  }
  const Eigen::VectorXd& D = ldlt_.vectorD();
  double largest = 0.0;
  for (Eigen::Index i = 0; i < D.size(); ++i) {
    if (!std::isfinite(D[i]) || D[i] == 0.0) {
      message_ = "LDLT: zero or non-finite pivot";
      return false;
    }
    largest = std::max(largest, std::abs(D[i]));
  }
  negativeBelow_ = -kRoundOffPivot * largest;
  negative_ = static_cast<int>((D.array() < negativeBelow_).count());
  return true;
}

bool IndefiniteFactor::negativeCurvatureDirection(Eigen::VectorXd& d) const {
  if (negative_ == 0) return false;
  const Eigen::VectorXd& D = ldlt_.vectorD();
  Eigen::VectorXd z = (D.array() < negativeBelow_).cast<double>().matrix();
  ldlt_.matrixU().solveInPlace(z);  // Lᵀ z = u
  d = ldlt_.permutationPinv() * z;
  return d.allFinite();
}

bool IndefiniteFactor::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  x = ldlt_.solve(b);
  return x.allFinite();
}

}  // namespace jetshell
