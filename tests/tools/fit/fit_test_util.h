// Shared check of the fit tests: a fit's misfit gradient against central differences of whole forward runs.
#pragma once

#include "tools/fit/fit_problem.h"

#include <catch2/catch.hpp>

#include <cmath>

namespace jetshell::test {

/// Each component of `gradient` (dmisfit/dq at q) within 1e-6 relative of the central difference with step
/// relativeStep·q_i, each side one whole evaluation of the problem (solves from the rest state).
inline void checkAgainstCentralDifferences(FitProblem& p, const Eigen::VectorXd& q, const Eigen::VectorXd& gradient,
                                           double relativeStep, const char* what) {
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    const double h = relativeStep * q[i];
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += h;
    qm[i] -= h;
    const FitEvaluation fp = p.evaluate(qp, FitDerivatives::None), fm = p.evaluate(qm, FitDerivatives::None);
    REQUIRE(fp.ok);
    REQUIRE(fm.ok);
    const double fd = (fp.misfit - fm.misfit) / (2.0 * h);
    INFO("parameter " << i << ": " << what << " " << gradient[i] << ", central difference " << fd);
    REQUIRE(std::abs(fd) > 0.0);
    CHECK(std::abs(fd - gradient[i]) <= 1e-6 * std::abs(fd));
  }
}

}  // namespace jetshell::test
