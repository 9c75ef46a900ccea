// A small energy term with known saddles and minima, shared by the solver tests: per vertex and coordinate c,
//   E_c = ¼ w_c (x_c² − 1)²   (a double well: minima at ±1, a maximum at 0, curvature w_c (3x_c² − 1))   if w_c > 0,
//   E_c = ½ x_c²              (a plain spring to 0)                                                        if w_c = 0.
// One single-vertex element per vertex (3×3 blocks), projected as the options ask.
#pragma once

#include "core/psd_projection.h"
#include "core/term.h"

#include <Eigen/Core>

#include <array>
#include <string>

namespace jetshell::testing {

class WellsTerm : public EnergyTerm {
 public:
  WellsTerm(int n, const std::array<double, 3>& well) : n_(n), well_(well) {}
  std::string name() const override { return "wells"; }
  StencilTable stencils() const override {
    StencilTable t;
    t.width = 1;
    for (int v = 0; v < n_; ++v) t.ids.push_back(v);
    return t;
  }
  bool zeroAtRest() const override { return false; }
  bool rigidInvariant() const override { return false; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override {
    double e = 0.0;
    for (int v = 0; v < n_; ++v) {
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      for (int c = 0; c < 3; ++c) {
        const double xi = x[3 * v + c], w = well_[static_cast<std::size_t>(c)];
        e += w > 0.0 ? 0.25 * w * (xi * xi - 1.0) * (xi * xi - 1.0) : 0.5 * xi * xi;
        if (request.gradient != nullptr) (*request.gradient)[3 * v + c] += w > 0.0 ? w * xi * (xi * xi - 1.0) : xi;
        H(c, c) = w > 0.0 ? w * (3.0 * xi * xi - 1.0) : 1.0;
      }
      if (request.hessian != nullptr) {
        projectPsd<3>(H, options.projection);
        request.hessian->addElementHessian(request.hessianSlot, v, H.data());
      }
    }
    return e;
  }

 private:
  int n_;
  std::array<double, 3> well_;
};

}  // namespace jetshell::testing
