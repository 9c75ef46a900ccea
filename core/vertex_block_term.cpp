#include "core/vertex_block_term.h"

#include "core/mesh.h"

#include <utility>

namespace jetshell {

VertexBlockTerm::VertexBlockTerm(EnergyTermPtr inner, int firstVertex, int numVertices)
    : inner_(std::move(inner)), first_(firstVertex), n_(numVertices) {
  if (!inner_) throw InputError("vertex block term: no inner term");
  if (first_ < 0 || n_ < 0)
    throw InputError("vertex block term '" + inner_->name() + "': first vertex " + std::to_string(first_) +
                     " and count " + std::to_string(n_) + " must not be negative");
}

StencilTable VertexBlockTerm::stencils() const {
  StencilTable t = inner_->stencils();
  for (int& v : t.ids)
    if (v >= 0) v += first_;
  return t;
}

const Eigen::VectorXd& VertexBlockTerm::block(const Eigen::VectorXd& x) {
  if (x.size() < 3 * (static_cast<Eigen::Index>(first_) + n_))
    throw InputError("vertex block term '" + inner_->name() + "': positions of size " + std::to_string(x.size()) +
                     " do not hold vertices " + std::to_string(first_) + " to " + std::to_string(first_ + n_ - 1));
  x_ = x.segment(3 * first_, 3 * n_);
  return x_;
}

double VertexBlockTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) {
  const Eigen::VectorXd& local = block(x);
  EvalRequest r = request;
  if (request.gradient) {
    gradient_.setZero(3 * n_);
    r.gradient = &gradient_;
  }
  const double energy = inner_->evaluate(local, r, options);
  if (request.gradient) request.gradient->segment(3 * first_, 3 * n_) += gradient_;
  return energy;
}

void VertexBlockTerm::updateStencils(const Eigen::VectorXd& x) { inner_->updateStencils(block(x)); }

void VertexBlockTerm::evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) {
  ParameterDerivatives local;
  inner_->evaluateParameterDerivatives(block(x), local);
  out.energy = std::move(local.energy);
  out.mixed = Eigen::MatrixXd::Zero(x.size(), local.mixed.cols());
  out.mixed.middleRows(3 * first_, 3 * n_) = local.mixed;
}

}  // namespace jetshell
