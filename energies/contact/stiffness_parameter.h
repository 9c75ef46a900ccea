// A contact term whose energy is linear in a penalty stiffness k, exposed as the differentiable parameter
// "penaltyStiffness" (core/term.h): ∂E/∂k = E(k = 1) and ∂²E/∂x∂k = ∇E(k = 1), both from the term's own
// (dual-number) evaluation, never from finite differences. Input: the functor and a pointer to the k it reads
// (held in state the functor shares, which outlives the term).
#pragma once

#include "core/mesh.h"
#include "energies/element_energy_term.h"

#include <cmath>
#include <string>
#include <vector>

namespace jetshell {

template <typename Functor>
class StiffnessParameterTerm : public ElementEnergyTerm<Functor> {
 public:
  StiffnessParameterTerm(std::string name, StencilTable stencils, int numVertices, Functor functor, double* stiffness)
      : ElementEnergyTerm<Functor>(std::move(name), std::move(stencils), numVertices, std::move(functor), false,
                                   false),
        k_(stiffness) {}

  std::vector<std::string> parameterNames() const override { return {"penaltyStiffness"}; }
  std::vector<double> parameterValues() const override { return {*k_}; }
  void setParameterValues(const std::vector<double>& values) override {
    if (values.size() != 1) throw InputError("term '" + this->name() + "': one parameter value expected");
    if (!(std::isfinite(values[0]) && values[0] >= 0.0))
      throw InputError("term '" + this->name() + "': penaltyStiffness must be finite and >= 0");
    *k_ = values[0];
  }
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override {
    const double k = *k_;
    *k_ = 1.0;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    EvalRequest request;
    request.gradient = &g;
    EvalOptions options;
    options.path = DerivativePath::AutoDiff;
    double e = 0.0;
    try {
      e = this->evaluate(x, request, options);
    } catch (...) {
      *k_ = k;
      throw;
    }
    *k_ = k;
    out.energy = Eigen::VectorXd::Constant(1, e);
    out.mixed = g;
  }

 private:
  double* k_;
};

}  // namespace jetshell
