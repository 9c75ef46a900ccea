// A test-local energy term with differentiable parameters, independent of the shell terms: pretensioned
// springs on the edges of a mesh, E = Σ_e ½ k s² + ¼ c s⁴, s = ℓ − L_e, L_e = restRatio · (reference length).
// Parameters {"k", "c"}. Its value, gradient, Hessian and ∂²E/∂x∂p are written out by hand (it is a fixture
// for the sensitivity code, checked against finite differences in tests/solvers/adjoint_test.cpp).
#pragma once

#include "core/mesh.h"
#include "core/term.h"
#include "core/topology.h"

#include <Eigen/Dense>

#include <cmath>
#include <string>
#include <vector>

namespace jetshell::testing {

class ParameterizedSprings : public EnergyTerm {
 public:
  ParameterizedSprings(const TriMesh& mesh, double k, double c, double restRatio) : k_(k), c_(c) {
    const Topology t = buildTopology(mesh);
    table_.width = 2;
    for (int e = 0; e < t.numEdges(); ++e) {
      const int a = t.edges(e, 0), b = t.edges(e, 1);
      table_.ids.push_back(a);
      table_.ids.push_back(b);
      rest_.push_back(restRatio * (mesh.V.row(a) - mesh.V.row(b)).norm());
    }
  }
  std::string name() const override { return "springs"; }
  StencilTable stencils() const override { return table_; }
  std::vector<std::string> parameterNames() const override { return {"k", "c"}; }
  std::vector<double> parameterValues() const override { return {k_, c_}; }
  void setParameterValues(const std::vector<double>& v) override {
    if (v.size() != 2) throw InputError("springs: 2 parameter values expected");
    k_ = v[0];
    c_ = v[1];
  }

  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions&) override {
    double energy = 0.0;
    for (int e = 0; e < table_.size(); ++e) {
      const int a = table_.element(e)[0], b = table_.element(e)[1];
      const Eigen::Vector3d d = x.segment<3>(3 * b) - x.segment<3>(3 * a);
      const double l = d.norm(), s = l - rest_[static_cast<std::size_t>(e)];
      const Eigen::Vector3d u = d / l;
      energy += 0.5 * k_ * s * s + 0.25 * c_ * s * s * s * s;
      const double dE = k_ * s + c_ * s * s * s, d2E = k_ + 3.0 * c_ * s * s;
      if (request.gradient) {
        request.gradient->segment<3>(3 * a) -= dE * u;
        request.gradient->segment<3>(3 * b) += dE * u;
      }
      if (request.hessian) {
        const Eigen::Matrix3d K = d2E * u * u.transpose() + dE / l * (Eigen::Matrix3d::Identity() - u * u.transpose());
        Eigen::Matrix<double, 6, 6> H;
        H << K, -K, -K, K;
        request.hessian->addElementHessian(request.hessianSlot, e, H.data());
      }
    }
    return energy;
  }

  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override {
    out.energy = Eigen::VectorXd::Zero(2);
    out.mixed = Eigen::MatrixXd::Zero(x.size(), 2);
    for (int e = 0; e < table_.size(); ++e) {
      const int a = table_.element(e)[0], b = table_.element(e)[1];
      const Eigen::Vector3d d = x.segment<3>(3 * b) - x.segment<3>(3 * a);
      const double l = d.norm(), s = l - rest_[static_cast<std::size_t>(e)];
      const Eigen::Vector3d u = d / l;
      out.energy[0] += 0.5 * s * s;
      out.energy[1] += 0.25 * s * s * s * s;
      const double dk = s, dc = s * s * s;  // ∂(dE/dℓ)/∂k, ∂(dE/dℓ)/∂c
      out.mixed.block<3, 1>(3 * a, 0) -= dk * u;
      out.mixed.block<3, 1>(3 * b, 0) += dk * u;
      out.mixed.block<3, 1>(3 * a, 1) -= dc * u;
      out.mixed.block<3, 1>(3 * b, 1) += dc * u;
    }
  }

 private:
  double k_, c_;
  StencilTable table_;
  std::vector<double> rest_;
};

}  // namespace jetshell::testing
