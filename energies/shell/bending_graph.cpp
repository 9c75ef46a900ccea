// The bending term's energy, gradient and Hessian: the energy as a stage graph
// (core/stage_graph.h, the layers declared in bending_term.h). Per face f (vertices 0, 1, 2 of the stencil,
// then the opposite vertex across each edge i as 3 + i):
//   n_f = FaceNormal(x1 − x0, x2 − x0)                  per face, in its own vertex order
//   m_e = EdgeMean(n_A, n_B)                             per edge, in the edge's face order; on a boundary edge
//                                                        (n_A, n_A) and the edge's rule
//   n̄_e = Kelvin(m_e)                                    per edge
//   b = SecondForm(x1 − x0, x2 − x0, n̄0, n̄1, n̄2)        per stencil
//   energy = BendingDensity(b)                           per stencil; minimized over the face's moment-free
//                                                        boundary edges' normals when it has any
// The stages are energies/shell/shell_stages.h; their values, Jacobians and Hessians, and the chain rule between
// them, come from the framework (core/stage_graph_evaluator.h), on the Jets or, on the analytic path, the
// stages' checked twins. Nothing here differentiates.
#include "energies/shell/bending_term.h"

namespace jetshell {

void BendingTerm::buildGraph() {
  const int nf = static_cast<int>(F_.rows()), ne = topo_.numEdges();
  const int nv = static_cast<int>(restPositions_.size() / 3);
  graph_ = std::make_unique<Graph>(nv);
  Graph& g = *graph_;
  g.resize<0>(nf);
  for (int f = 0; f < nf; ++f) g.setInputs<0>(f, {difference(F_(f, 0), F_(f, 1)), difference(F_(f, 0), F_(f, 2))});
  g.resize<1>(ne);
  g.resize<2>(ne);
  for (int e = 0; e < ne; ++e) {
    const int fa = topo_.edgeFaces(e, 0), fb = topo_.edgeFaces(e, 1);
    g.setInputs<1>(e, {node(fa), node(fb >= 0 ? fb : fa)});
    g.setInputs<2>(e, {node(e)});
  }
  g.setElements(table_);
  for (int f = 0; f < nf; ++f) {
    g.setInputs<3>(f, {difference(F_(f, 0), F_(f, 1)), difference(F_(f, 0), F_(f, 2)), node(topo_.faceEdges(f, 0)),
                       node(topo_.faceEdges(f, 1)), node(topo_.faceEdges(f, 2))});
    g.setInputs<4>(f, {node(f)});
  }
  g.finalize();
  graphEvaluator_ = std::make_unique<StageGraphEvaluator<Graph>>(g);
}

void BendingTerm::bindStages() {
  EdgeMeanStage& mean = graph_->stage<1>();
  mean.rules = &rules_;
  mean.data = &ruleData_;
  mean.topology = &topo_;
  BendingDensityStage& density = graph_->stage<4>();
  density.ref = &ref_;
  density.alpha = alpha_;
  density.beta = beta_;
  density.scale = energyScale();
  density.minimized = &minimized_;
  density.ruledQuadratic = &ruledQuadratic_;
  density.quadratic = nullptr;
}

double BendingTerm::evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) {
  // A Gauss–Newton block Jᵀ W'' J is positive semi-definite by construction (W'' is, for every admissible material
  // and edge rule: the ruled densities are Schur complements of convex quadratics), so it is never projected.
  // Projecting it would cost an eigendecomposition per block for nothing: its rank is 3, so the Cholesky test in
  // edge space (core/psd_projection.h) fails on every one.
  if (options.hessianModel == HessianModel::GaussNewton && options.projection != PsdProjection::None) {
    EvalOptions unprojected = options;
    unprojected.projection = PsdProjection::None;
    return evaluate(x, request, unprojected);
  }
  // The analytic twin of a face with moment-free edges reads its ruled quadratic. On the Jets, a Hessian takes
  // every face's density Hessian from its ruled quadratic (itself from Jets, once per α, β and rules: the density
  // is a quadratic in b), and first-order Jets give the value and gradient (core/stage.h, per-entity quadratic).
  const bool ad = options.path == DerivativePath::AutoDiff;
  if (ad ? request.hessian != nullptr : request.gradient != nullptr || request.hessian != nullptr)
    updateRuledQuadratics(ad);
  bindStages();
  if (ad && request.hessian != nullptr) graph_->stage<4>().quadratic = &ruledQuadratic_;
  return graphEvaluator_->evaluate(x, request, options, schedule_, elementEnergy_);
}

void BendingTerm::graphCurvatureOrigin(const Eigen::VectorXd& xOrigin) {
  // From the very stages evaluate() runs, so that κ vanishes at the origin: to the bit without fused
  // multiply-adds, to round-off with them (-march=native; StageGraphEvaluator::localValues).
  bindStages();
  graphEvaluator_->localValues<3>(xOrigin, [&](int f, const double* b) {
    ref_.secondFundamentalForm[static_cast<std::size_t>(f)] = {b[0], b[1], b[2]};
  });
}

}  // namespace jetshell
