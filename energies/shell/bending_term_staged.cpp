// The bending term's staged evaluator (BendingTerm::setStaged). Per stencil f (the face's vertices 0, 1, 2, then
// the opposite vertex across each edge i as 3 + i):
//   e0 = x1 − x0, e1 = x2 − x0 (leaves)
//   per face g of the stencil (f and its neighbours): n_g = UnitNormal(FaceCross(g's own e0, e1)), one composed
//     stage (6 -> 3) cached per face
//   per edge i: m_i = MeanNormal(n_A, n_B) in the edge's face order (cached per edge), or GhostMean(n_f) under
//     the edge's rule on a boundary edge; n̄_i = Kelvin(m_i), cached per edge
//   b = SecondForm(e0, e1, n̄0, n̄1, n̄2); energy = BendingDensity(b), minimized over the face's moment-free
//     boundary edges' normals when it has any (second_order_free; a quadratic in b, closed form)
// The stages are energies/shell/shell_stages.h; their values, Jacobians and Hessians and the chain rule between
// them come from the framework (core/stage_chain.h), on the Jets or, on the analytic path, the stages' checked
// twins. Nothing here differentiates.
#include "energies/shell/bending_term.h"

namespace jetshell {
namespace {

constexpr std::int8_t kOwnVertices[3] = {0, 1, 2};

}  // namespace

void BendingTerm::setStaged(bool staged) {
  staged_ = staged;
  if (staged) resizeStages();
}

void BendingTerm::resizeStages() {
  const int nf = static_cast<int>(F_.rows()), ne = topo_.numEdges();
  normals_.resize(nf);
  meanNormals_.resize(ne);
  midEdgeNormals_.resize(ne);
}

void BendingTerm::bindStages() {
  ghostMean_.rules = &rules_;
  ghostMean_.data = &ruleData_;
  density_.ref = &ref_;
  density_.alpha = alpha_;
  density_.beta = beta_;
  density_.scale = energyScale();
  density_.minimized = &minimized_;
  density_.ruledQuadratic = &ruledQuadratic_;
}

int BendingTerm::stagedFaceNormal(StageChain<6>& chain, int face, const std::int8_t* local) {
  return chain.stage(normals_, face, {chain.difference(local[0], local[1]), chain.difference(local[0], local[2])});
}

int BendingTerm::buildSecondForm(StageChain<6>& chain, int f) {
  const int nf = stagedFaceNormal(chain, f, kOwnVertices);
  int nbar[3];
  for (int i = 0; i < 3; ++i) {
    const int e = topo_.faceEdges(f, i);
    const int g = topo_.faceNeighbors(f, i);
    int m;
    if (g >= 0) {
      const int ng = stagedFaceNormal(chain, g, neighborLocal_[f].data() + 3 * i);
      // The edge's own face order, so that both stencils of the edge give its cache the same input.
      m = topo_.edgeFaces(e, 0) == f ? chain.stage(meanNormals_, e, {nf, ng}) : chain.stage(meanNormals_, e, {ng, nf});
    } else {
      m = chain.stage(ghostMean_, e, {nf});
    }
    nbar[i] = chain.stage(midEdgeNormals_, e, {m});
  }
  return chain.stage(SecondFormStage(), f, {chain.difference(0, 1), chain.difference(0, 2), nbar[0], nbar[1], nbar[2]});
}

double BendingTerm::evaluateStaged(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) {
  // The analytic twin of a face with moment-free edges reads its ruled quadratic (the Jets differentiate the
  // minimized density itself).
  if (options.path != DerivativePath::AutoDiff && (request.gradient != nullptr || request.hessian != nullptr))
    updateRuledQuadratics(false);
  bindStages();
  return elements_.evaluate(table_, schedule_, x, request, options, elementEnergy_, [&](StageChain<6>& chain, int f) {
    chain.energy(density_, f, {buildSecondForm(chain, f)});
  });
}

void BendingTerm::stagedCurvatureOrigin(const Eigen::VectorXd& xOrigin) {
  // From the very stages evaluateStaged() runs, so that κ vanishes at the origin to the bit.
  bindStages();
  elements_.nodeValues(
      table_, xOrigin, [&](StageChain<6>& chain, int f) { return buildSecondForm(chain, f); },
      [&](int f, const StageChain<6>& chain, int b) {
        ref_.secondFundamentalForm[f] = {chain.value(b, 0), chain.value(b, 1), chain.value(b, 2)};
      });
}

}  // namespace jetshell
