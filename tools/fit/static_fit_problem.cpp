#include "tools/fit/static_fit_problem.h"

#include "core/mesh.h"
#include "solvers/adjoint.h"

#include <cmath>
#include <sstream>

namespace jetshell {

StaticFitProblem::StaticFitProblem(Objective& objective, LoadFactorHooks loads, Eigen::VectorXd rest,
                                   ParameterMapping mapping, std::vector<double> levels,
                                   std::vector<ObservedCoordinate> observed, LoadSteppingOptions options)
    : objective_(objective),
      loads_(std::move(loads)),
      rest_(std::move(rest)),
      mapping_(std::move(mapping)),
      levels_(std::move(levels)),
      observed_(std::move(observed)),
      options_(std::move(options)),
      sensitivity_(std::make_unique<EquilibriumSensitivity>(objective)) {
  if (rest_.size() != objective_.numDofs()) throw InputError("fit: the rest state has the wrong size");
  if (mapping_.numParameters < 1 || !mapping_.map) throw InputError("fit: no parameter to fit");
  if (levels_.empty()) throw InputError("fit: no observed load level");
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    if (!std::isfinite(levels_[k])) throw InputError("fit: a load level is not finite");
    if (k > 0 && !(levels_[k] > levels_[k - 1])) throw InputError("fit: load levels must increase");
  }
  checkObserved(observed_, static_cast<int>(levels_.size()), objective_.numDofs());
  // A fit reads the equilibria at the observed levels only, over thousands of solves; the jump check's energy
  // evaluations cost about 13% of its time on examples/fit_synthetic_plate.json (jetshell bench fit).
  options_.detectJumps = false;
}

StaticFitProblem::~StaticFitProblem() = default;

FitEvaluation StaticFitProblem::evaluate(const Eigen::VectorXd& q, FitDerivatives derivatives) {
  FitEvaluation out;
  const int Q = numParameters();
  Eigen::MatrixXd dvdq;
  if (!applyParameters(objective_, mapping_, q, derivatives, out, dvdq)) return out;

  const int M = numResiduals();
  if (derivatives == FitDerivatives::Jacobian) out.jacobian = Eigen::MatrixXd::Zero(M, Q);
  if (derivatives != FitDerivatives::None) out.gradient = Eigen::VectorXd::Zero(Q);

  // One load path through every observed level (solvers/statics.h lands on each): level 0, when observed, is one
  // solve at λ = 0 from the rest state (every load, the weight and prescribed motion ramp with λ, so it is the
  // unloaded state); the path continues from there.
  Eigen::VectorXd x = rest_;
  out.equilibria.assign(levels_.size(), Eigen::VectorXd());
  auto count = [&](const StaticsResult& r) {
    ++counters_.fullSolves;
    counters_.newtonIterations += r.newtonIterations;
    for (const LoadStepResult& s : r.steps) counters_.newtonFactorizations += s.summary.numericFactorizations;
    for (const SolverSummary& s : r.failedSolves) counters_.newtonFactorizations += s.numericFactorizations;
  };
  auto failed = [&](const StaticsResult& r, double level) {
    std::ostringstream m;
    m << "the static solve to load factor " << level << " failed: " << r.message;
    out.message = m.str();
    return out;
  };
  std::size_t first = 0;
  if (levels_[0] == 0.0) {
    LoadSteppingOptions o = options_;
    o.startLoadFactor = o.targetLoadFactor = 0.0;
    o.levels.clear();
    const StaticsResult r = solveStatics(objective_, loads_, x, o);
    count(r);
    if (!r.completed) return failed(r, 0.0);
    out.equilibria[0] = x;
    first = 1;
  }
  if (first < levels_.size()) {
    LoadSteppingOptions o = options_;
    o.startLoadFactor = 0.0;
    o.targetLoadFactor = levels_.back();
    o.levels.assign(levels_.begin() + static_cast<std::ptrdiff_t>(first), levels_.end());
    std::size_t next = first;
    const StaticsResult r = solveStatics(objective_, loads_, x, o, [&](const LoadStepResult& s) {
      if (s.atLevel && next < levels_.size()) out.equilibria[next++] = s.x;
      return true;
    });
    count(r);
    if (!r.completed) return failed(r, levels_.back());
    if (next != levels_.size()) {
      out.message = "the load path did not stop on every observed level";
      return out;
    }
  }
  if (!computeResiduals(out)) return out;

  if (derivatives != FitDerivatives::None) {
    for (std::size_t k = 0; k < levels_.size(); ++k) {
      const Eigen::VectorXd& xk = out.equilibria[k];
      loads_.set(levels_[k]);
      const int factorizationsBefore = sensitivity_->factorizations(), solvesBefore = sensitivity_->solves();
      if (!sensitivity_->factor(xk)) {
        std::ostringstream m;
        m << "derivatives at load factor " << levels_[k] << ": " << sensitivity_->message();
        out.message = m.str();
        return out;
      }
      // ∂g/∂q = ∂g/∂v · dv/dq: Q columns, whatever the number of term parameters.
      const Eigen::MatrixXd mixed = sensitivity_->mixedDerivatives(xk, mapping_.termParameters) * dvdq;
      if (derivatives == FitDerivatives::Gradient) {
        Eigen::VectorXd dfdx = Eigen::VectorXd::Zero(xk.size());
        for (int i = 0; i < M; ++i) {
          const ObservedCoordinate& o = observed_[static_cast<std::size_t>(i)];
          if (o.level == static_cast<int>(k)) dfdx[o.dof] += std::sqrt(o.weight) * out.residuals[i];
        }
        out.gradient += adjointGradient(*sensitivity_, dfdx, mixed);
      } else {
        const Eigen::MatrixXd S = forwardSensitivities(*sensitivity_, mixed);
        for (int i = 0; i < M; ++i) {
          const ObservedCoordinate& o = observed_[static_cast<std::size_t>(i)];
          if (o.level == static_cast<int>(k)) out.jacobian.row(i) = std::sqrt(o.weight) * S.row(o.dof);
        }
      }
      counters_.sensitivityFactorizations += sensitivity_->factorizations() - factorizationsBefore;
      counters_.sensitivitySolves += sensitivity_->solves() - solvesBefore;
    }
    if (derivatives == FitDerivatives::Jacobian) out.gradient = out.jacobian.transpose() * out.residuals;
    if (!out.gradient.allFinite()) {
      out.message = "non-finite derivatives";
      return out;
    }
  }
  out.ok = true;
  return out;
}

}  // namespace jetshell
