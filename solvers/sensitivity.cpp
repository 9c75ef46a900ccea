#include "solvers/sensitivity.h"

#include "core/mesh.h"
#include "solvers/cholmod_factor.h"

#include <algorithm>
#include <cmath>

namespace jetshell {
namespace {

struct Located {
  EnergyTermPtr term;
  int index = -1;
};

Located locate(const Objective& objective, const TermParameter& p) {
  Located l;
  l.term = objective.term(p.term);
  if (!l.term) throw InputError("parameter '" + p.term + "." + p.name + "': no active term named '" + p.term + "'");
  const std::vector<std::string> names = l.term->parameterNames();
  const auto it = std::find(names.begin(), names.end(), p.name);
  if (it == names.end()) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InputError("parameter '" + p.term + "." + p.name + "': term '" + p.term + "' has no parameter '" + p.name +
                     "' (it has: " + (list.empty() ? "none" : list) + ")");
  }
  l.index = static_cast<int>(it - names.begin());
  return l;
}

}  // namespace

double termParameterValue(const Objective& objective, const TermParameter& p) {
  const Located l = locate(objective, p);
  return l.term->parameterValues()[static_cast<std::size_t>(l.index)];
}

void setTermParameterValue(Objective& objective, const TermParameter& p, double value) {
  const Located l = locate(objective, p);
  std::vector<double> values = l.term->parameterValues();
  values[static_cast<std::size_t>(l.index)] = value;
  l.term->setParameterValues(values);
}

EquilibriumSensitivity::EquilibriumSensitivity(Objective& objective)
    : objective_(objective), factor_(std::make_unique<CholmodFactor>()) {}

EquilibriumSensitivity::~EquilibriumSensitivity() = default;

bool EquilibriumSensitivity::factor(const Eigen::VectorXd& x) {
  factored_ = false;
  EvalOptions exact;
  exact.projection = PsdProjection::None;
  exact.hessianModel = HessianModel::Exact;
  Eigen::VectorXd g;
  objective_.evaluate(x, &g, true, exact);
  const HessianAssembler& a = objective_.assembler();
  if (!analyzed_ || analyzedVersion_ != a.patternVersion()) {
    if (factor_->analyze(a.matrix()) != CholmodFactor::Status::Ok) {
      message_ = "symbolic analysis failed: " + factor_->message();
      return false;
    }
    analyzed_ = true;
    analyzedVersion_ = a.patternVersion();
  }
  ++factorizations_;
  const CholmodFactor::Status s = factor_->factorize(a.matrix(), 0.0);
  if (s == CholmodFactor::Status::NotPositiveDefinite) {
    message_ = "the Hessian at the equilibrium is not positive definite (an unstable or critical equilibrium: its "
               "parameter derivatives are undefined)";
    return false;
  }
  if (s != CholmodFactor::Status::Ok) {
    message_ = "factorization failed: " + factor_->message();
    return false;
  }
  factored_ = true;
  message_.clear();
  return true;
}

Eigen::VectorXd EquilibriumSensitivity::solve(const Eigen::VectorXd& b) {
  if (!factored_) throw InputError("EquilibriumSensitivity::solve: no factor (call factor() first)");
  Eigen::VectorXd rhs = b;
  objective_.zeroFixed(rhs);
  Eigen::VectorXd y;
  ++solves_;
  if (factor_->solve(rhs, y) != CholmodFactor::Status::Ok || !y.allFinite())
    throw InputError("EquilibriumSensitivity::solve: " + factor_->message());
  objective_.zeroFixed(y);
  return y;
}

Eigen::MatrixXd EquilibriumSensitivity::mixedDerivatives(const Eigen::VectorXd& x,
                                                         const std::vector<TermParameter>& parameters) const {
  Eigen::MatrixXd mixed = Eigen::MatrixXd::Zero(x.size(), static_cast<Eigen::Index>(parameters.size()));
  // One evaluation per distinct term, whatever the number of its parameters asked for.
  std::vector<std::string> done;
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const Located l = locate(objective_, parameters[k]);
    if (std::find(done.begin(), done.end(), parameters[k].term) != done.end()) continue;
    done.push_back(parameters[k].term);
    ParameterDerivatives d;
    l.term->evaluateParameterDerivatives(x, d);
    for (std::size_t j = k; j < parameters.size(); ++j) {
      if (parameters[j].term != parameters[k].term) continue;
      const Located lj = locate(objective_, parameters[j]);
      mixed.col(static_cast<Eigen::Index>(j)) = d.mixed.col(lj.index);
    }
  }
  for (Eigen::Index c = 0; c < mixed.cols(); ++c) {
    Eigen::VectorXd col = mixed.col(c);
    objective_.zeroFixed(col);
    mixed.col(c) = col;
  }
  return mixed;
}

}  // namespace jetshell
