#include "solvers/time_step_sensitivity.h"

#include "core/mesh.h"

#include <sstream>

namespace jetshell {

TimeStepSensitivity::TimeStepSensitivity(ShellSystem& system) : system_(system), factor_(system.objective()) {
  if (system.kind() != AnalysisKind::Dynamics)
    throw InputError("time-step sensitivities: the system was not built for dynamics");
  if (!system.contact.empty())
    throw InputError("time-step sensitivities: contact terms (lagged friction and damping data) are not "
                     "differentiated through the steps");
}

TimeStepSensitivity::~TimeStepSensitivity() = default;

void TimeStepSensitivity::reset(const std::vector<TermParameter>& parameters, const Eigen::MatrixXd& dvdq) {
  if (dvdq.rows() != static_cast<Eigen::Index>(parameters.size()))
    throw InputError("time-step sensitivities: dvdq must have one row per term parameter");
  if (dvdq.cols() < 1 || dvdq.cols() > 8) throw InputError("time-step sensitivities: 1 to 8 parameters");
  parameters_ = parameters;
  dvdq_ = dvdq;
  const Eigen::Index n = system_.objective().numDofs();
  sx_ = sv_ = sxPrev_ = svPrev_ = sxStart_ = svStart_ = Eigen::MatrixXd::Zero(n, dvdq.cols());
  inexact_ = 0;
  message_.clear();
}

void TimeStepSensitivity::beginStep() {
  sxStart_ = sx_;
  svStart_ = sv_;
}

void TimeStepSensitivity::endStep() {
  sxPrev_ = sxStart_;
  svPrev_ = svStart_;
}

bool TimeStepSensitivity::advance(const SubstepView& view) {
  const double h = view.timeStep;
  const Eigen::VectorXd& x = *view.x;
  // Not a minimizer to the residual tolerance: accepted at the iteration cap, or stopped by the time-discretization
  // rule (DynamicsOptions::updateTolerance), which ends Newton at a fraction of the truncation error.
  if (view.movedOn || !view.solve->converged() || view.solve->convergenceTest == "iterate") ++inexact_;
  // The sensitivities of the damping origin y and of the inertia centre x̃ (see the header).
  Eigen::MatrixXd sy, sPredictor;
  if (view.bdf2) {
    sy = (4.0 * sx_ - sxPrev_) / 3.0;
    sPredictor = sy + (8.0 * h / 9.0) * (sv_ - 0.25 * svPrev_);
  } else {
    sy = sx_;
    sPredictor = sx_ + h * sv_;
  }
  if (!factor_.factor(x)) {
    std::ostringstream s;
    s << "step sensitivities at t + " << h << ": " << factor_.message();
    message_ = s.str();
    return false;
  }
  Eigen::MatrixXd rhs = factor_.mixedDerivatives(x, parameters_) * dvdq_;
  if (system_.inertia) rhs += system_.inertia->centreCrossDerivatives(sPredictor);
  if (system_.massDamping) rhs += system_.massDamping->centreCrossDerivatives(sy);
  if (system_.stiffnessDamping.membrane) rhs += system_.stiffnessDamping.membrane->originCrossDerivatives(x, sy);
  if (system_.stiffnessDamping.bending) rhs += system_.stiffnessDamping.bending->originCrossDerivatives(x, sy);
  Eigen::MatrixXd next(rhs.rows(), rhs.cols());
  for (Eigen::Index j = 0; j < rhs.cols(); ++j) next.col(j) = -factor_.solve(rhs.col(j));
  const Eigen::MatrixXd velocity =
      view.bdf2 ? Eigen::MatrixXd((3.0 * next - 4.0 * sx_ + sxPrev_) / (2.0 * h)) : Eigen::MatrixXd((next - sx_) / h);
  if (!next.allFinite() || !velocity.allFinite()) {
    message_ = "non-finite step sensitivities";
    return false;
  }
  sx_ = next;
  sv_ = velocity;
  return true;
}

}  // namespace jetshell
