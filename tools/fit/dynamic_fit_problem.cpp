#include "tools/fit/dynamic_fit_problem.h"

#include "core/mesh.h"

#include <cmath>
#include <sstream>

namespace jetshell {

DynamicFitProblem::DynamicFitProblem(ShellSystem& system, ParameterMapping mapping, DynamicsOptions options,
                                     std::function<double(double)> loadFactorAtTime, std::vector<int> steps,
                                     std::vector<ObservedCoordinate> observed)
    : system_(system),
      mapping_(std::move(mapping)),
      options_(std::move(options)),
      loadFactorAtTime_(std::move(loadFactorAtTime)),
      steps_(std::move(steps)),
      observed_(std::move(observed)),
      rest_(system.restPositions()) {
  if (system.kind() != AnalysisKind::Dynamics) throw InputError("fit: the system was not built for dynamics");
  if (mapping_.numParameters < 1 || !mapping_.map) throw InputError("fit: no parameter to fit");
  if (!loadFactorAtTime_) throw InputError("fit: no load factor function");
  if (steps_.empty()) throw InputError("fit: no observed time");
  for (std::size_t k = 0; k < steps_.size(); ++k) {
    if (steps_[k] < 1) throw InputError("fit: observed steps must be >= 1");
    if (k > 0 && !(steps_[k] > steps_[k - 1])) throw InputError("fit: observed steps must increase");
    times_.push_back(steps_[k] * options_.timeStep);
  }
  checkObserved(observed_, static_cast<int>(steps_.size()), system_.objective().numDofs());
}

DynamicFitProblem::~DynamicFitProblem() = default;

FitEvaluation DynamicFitProblem::evaluate(const Eigen::VectorXd& q, FitDerivatives derivatives) {
  FitEvaluation out;
  const int Q = numParameters();
  const bool wantDerivatives = derivatives != FitDerivatives::None;
  Eigen::MatrixXd dvdq;
  if (!applyParameters(system_.objective(), mapping_, q, derivatives, out, dvdq)) return out;

  // One run from the rest state (the solver starts there, prescribed positions applied at t = 0).
  DynamicsSolver solver(system_, options_);
  ++counters_.fullSolves;
  if (wantDerivatives) {
    if (!sensitivity_) {
      try {
        sensitivity_ = std::make_unique<TimeStepSensitivity>(system_);
      } catch (const InputError& e) {
        out.message = std::string("derivatives: ") + e.what();
        return out;
      }
    }
    sensitivity_->reset(mapping_.termParameters, dvdq);
  }
  bool sensitivityFailed = false;
  if (wantDerivatives)
    solver.setSubstepObserver([&](const SubstepView& v) {
      if (!sensitivityFailed && !sensitivity_->advance(v)) sensitivityFailed = true;
    });
  const int factorizationsBefore = wantDerivatives ? sensitivity_->factorizations() : 0;
  const int solvesBefore = wantDerivatives ? sensitivity_->solves() : 0;

  const int M = numResiduals();
  out.equilibria.assign(steps_.size(), Eigen::VectorXd());
  std::vector<Eigen::MatrixXd> observedSensitivities(wantDerivatives ? steps_.size() : 0);
  std::size_t next = 0;
  for (int step = 1; step <= steps_.back(); ++step) {
    if (system_.nodalForces) system_.nodalForces->setLoadFactor(loadFactorAtTime_(step * options_.timeStep));
    if (wantDerivatives) sensitivity_->beginStep();
    const StepReport r = solver.step();
    ++counters_.timeSteps;
    counters_.newtonIterations += r.newtonIterations;
    for (const SolverSummary& s : r.solves) counters_.newtonFactorizations += s.numericFactorizations;
    if (!r.success) {
      out.message = "the dynamic run failed: " + r.message;
      return out;
    }
    if (sensitivityFailed) {
      out.message = "derivatives: " + sensitivity_->message();
      return out;
    }
    if (wantDerivatives) sensitivity_->endStep();
    if (step == steps_[next]) {
      out.equilibria[next] = solver.positions();
      if (wantDerivatives) observedSensitivities[next] = sensitivity_->positions();
      ++next;
    }
  }
  if (!computeResiduals(out)) return out;
  if (wantDerivatives) {
    Eigen::MatrixXd J(M, Q);
    for (int i = 0; i < M; ++i) {
      const ObservedCoordinate& o = observed_[static_cast<std::size_t>(i)];
      J.row(i) = std::sqrt(o.weight) * observedSensitivities[static_cast<std::size_t>(o.level)].row(o.dof);
    }
    out.gradient = J.transpose() * out.residuals;
    if (derivatives == FitDerivatives::Jacobian) out.jacobian = std::move(J);
    counters_.sensitivityFactorizations += sensitivity_->factorizations() - factorizationsBefore;
    counters_.sensitivitySolves += sensitivity_->solves() - solvesBefore;
    counters_.inexactDerivativeSolves += sensitivity_->inexactSolves();
    out.derivativesExact = sensitivity_->inexactSolves() == 0;
    if (!out.gradient.allFinite()) {
      out.message = "non-finite derivatives";
      return out;
    }
  }
  out.ok = true;
  return out;
}

}  // namespace jetshell
