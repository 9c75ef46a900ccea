// A term over one block of a larger problem's vertices: the inner term is built on its own mesh, vertices 0 … n−1,
// and sits on vertices first … first + n − 1 of the problem (a shell actor in a scene of several). Its data, its
// schedule and its caches grow with n, not with the problem, so a scene of many actors costs the sum of their
// sizes, not the actors times the scene.
//
// Data flow per evaluation: x (3N) → the block's 3n positions (copied) → the inner term's energy, its gradient
// (3n, added into the block of the 3N gradient) and its element Hessians, which go straight to the assembler:
// the slot's stencils are the inner ones shifted by `first`, so the assembler places every block itself. The
// parameters are the inner term's; ∂²E/∂x∂p has the inner rows in the block and zeros elsewhere.
#pragma once

#include "core/term.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace jetshell {

class VertexBlockTerm : public EnergyTerm {
 public:
  /// inner: a term over numVertices vertices; they are vertices first … first + numVertices − 1 of the problem.
  /// InputError for a null term or a negative first vertex or count.
  VertexBlockTerm(EnergyTermPtr inner, int firstVertex, int numVertices);

  const EnergyTermPtr& inner() const { return inner_; }
  int firstVertex() const { return first_; }
  int numVertices() const { return n_; }

  std::string name() const override { return inner_->name(); }
  StencilTable stencils() const override;
  bool hasAnalytic() const override { return inner_->hasAnalytic(); }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override;
  bool zeroAtRest() const override { return inner_->zeroAtRest(); }
  bool rigidInvariant() const override { return inner_->rigidInvariant(); }
  void updateStencils(const Eigen::VectorXd& x) override;
  std::uint64_t stencilVersion() const override { return inner_->stencilVersion(); }
  bool stencilsFollowConfiguration() const override { return inner_->stencilsFollowConfiguration(); }
  std::vector<std::string> parameterNames() const override { return inner_->parameterNames(); }
  std::vector<double> parameterValues() const override { return inner_->parameterValues(); }
  void setParameterValues(const std::vector<double>& values) override { inner_->setParameterValues(values); }
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override;

 private:
  /// The block's positions of x (InputError when x is too short for the block).
  const Eigen::VectorXd& block(const Eigen::VectorXd& x);

  EnergyTermPtr inner_;
  int first_, n_;
  Eigen::VectorXd x_, gradient_;  // the block's positions and gradient (reused between evaluations)
};

}  // namespace jetshell
