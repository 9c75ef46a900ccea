#include "core/mesh_generators.h"
#include "core/vertex_block_term.h"
#include "energies/shell/bending_term.h"
#include "energies/shell/membrane_term.h"
#include "energies/shell/reference_state.h"
#include "energies/shell/shell_terms.h"
#include "solvers/shell_system.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

using namespace jetshell;
using namespace jetshell::test;

namespace {

/// Two rectangles stacked: `first` (3 × 2 quads) then `second` (2 × 2 quads, moved and tilted).
struct TwoMeshes {
  TriMesh first = makeRectangleGrid(0.3, 0.2, 3, 2), second = makeRectangleGrid(0.2, 0.2, 2, 2);
  TriMesh stacked;
  TwoMeshes() {
    second.V.col(0).array() += 0.5;
    second.V.col(2) = 0.1 * second.V.col(0);
    stacked.V.resize(first.numVertices() + second.numVertices(), 3);
    stacked.V << first.V, second.V;
    stacked.F.resize(first.numFaces() + second.numFaces(), 3);
    stacked.F << first.F, (second.F.array() + first.numVertices()).matrix();
  }
  /// The second mesh's faces over the stacked vertices (what each actor's terms were built on before).
  TriMesh secondOverStacked() const {
    return {stacked.V, (second.F.array() + first.numVertices()).matrix()};
  }
};

Eigen::VectorXd deformed(const TriMesh& m) {
  Eigen::VectorXd x = flatten(m.V);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += 0.02 * std::sin(1.7 * static_cast<double>(i) + 0.3);
  return x;
}

void checkSame(EnergyTerm& block, EnergyTerm& stacked, const Eigen::VectorXd& x, const EvalOptions& o) {
  const DenseDerivatives a = evaluateDense(block, x, o), b = evaluateDense(stacked, x, o);
  CHECK(a.energy == Approx(b.energy).epsilon(1e-13));
  CHECK((a.gradient - b.gradient).norm() <= 1e-12 * b.gradient.norm());
  CHECK((a.hessian - b.hessian).norm() <= 1e-12 * b.hessian.norm());
}

}  // namespace

TEST_CASE("vertex block term: a term on an actor's own vertices equals the same term over the stacked ones") {
  const TwoMeshes m;
  const int first = m.first.numVertices(), n = m.second.numVertices();
  const Eigen::VectorXd x = deformed(m.stacked);
  const TriMesh over = m.secondOverStacked();
  const Topology localTopology = buildTopology(m.second), stackedTopology = buildTopology(over);
  const ShellReference localReference = computeReference(m.second, localTopology),
                       stackedReference = computeReference(over, stackedTopology);

  auto membrane = std::make_shared<MembraneTerm>(m.second, localReference, 300.0, 400.0);
  VertexBlockTerm membraneBlock(membrane, first, n);
  MembraneTerm membraneStacked(over, stackedReference, 300.0, 400.0);
  auto bending = std::make_shared<BendingTerm>(m.second, localTopology, localReference, 2e-5, 7e-5);
  VertexBlockTerm bendingBlock(bending, first, n);
  BendingTerm bendingStacked(over, stackedTopology, stackedReference, 2e-5, 7e-5);
  for (DerivativePath path : {DerivativePath::Analytic, DerivativePath::AutoDiff})
    for (PsdProjection projection : {PsdProjection::None, PsdProjection::Clamp}) {
      EvalOptions o;
      o.path = path;
      o.projection = projection;
      checkSame(membraneBlock, membraneStacked, x, o);
      checkSame(bendingBlock, bendingStacked, x, o);
    }

  // The stencils are the inner ones shifted; the parameters and their derivatives are the inner term's, with
  // the mixed derivative's rows in the block.
  const StencilTable inner = bending->stencils(), outer = bendingBlock.stencils();
  REQUIRE(inner.ids.size() == outer.ids.size());
  for (std::size_t k = 0; k < inner.ids.size(); ++k)
    CHECK(outer.ids[k] == (inner.ids[k] < 0 ? -1 : inner.ids[k] + first));
  REQUIRE(bendingBlock.parameterNames() == bendingStacked.parameterNames());
  ParameterDerivatives a, b;
  bendingBlock.evaluateParameterDerivatives(x, a);
  bendingStacked.evaluateParameterDerivatives(x, b);
  CHECK((a.energy - b.energy).norm() <= 1e-13 * b.energy.norm());
  REQUIRE(a.mixed.rows() == x.size());
  CHECK((a.mixed - b.mixed).norm() <= 1e-12 * b.mixed.norm());
  CHECK(a.mixed.topRows(3 * first).norm() == 0.0);
  bendingBlock.setParameterValues({4e-5, 7e-5});
  CHECK(bending->parameterValues()[0] == 4e-5);

  CHECK_THROWS_WITH(bendingBlock.evaluate(x.head(3 * first + 3), EvalRequest{}, EvalOptions{}),
                    Catch::Contains("do not hold vertices"));
  CHECK_THROWS_AS(VertexBlockTerm(nullptr, 0, 1), InputError);
  CHECK_THROWS_AS(VertexBlockTerm(bending, -1, n), InputError);
}

TEST_CASE("vertex block term: actors of different materials give the objective of their terms over the stacked "
          "mesh, with masses and clamps in their blocks") {
  const TwoMeshes m;
  const int first = m.first.numVertices();
  ShellProblem p;
  p.mesh = m.stacked;
  p.gravity = {0, 0, -9.81};
  for (int a = 0; a < 2; ++a) {
    ShellActorPart part;
    part.name = a == 0 ? "a" : "b";
    part.mesh = a == 0 ? m.first : m.second;
    part.firstVertex = a == 0 ? 0 : first;
    part.material.membraneLambda = a == 0 ? 300.0 : 100.0;
    part.material.membraneMu = a == 0 ? 400.0 : 150.0;
    part.material.bendingAlpha = a == 0 ? 2e-5 : 1e-5;
    part.material.bendingBeta = a == 0 ? 7e-5 : 3e-5;
    part.material.density = a == 0 ? 0.2 : 0.5;
    part.pointCloud = false;
    if (a == 1) {  // clamp the second actor's left edge
      part.clampedVertices.assign(static_cast<std::size_t>(m.second.numVertices()), 0);
      for (int v = 0; v < m.second.numVertices(); ++v)
        if (m.second.V(v, 0) < 0.5 + 1e-9) part.clampedVertices[static_cast<std::size_t>(v)] = 1;
    }
    p.actors.push_back(part);
  }
  ShellSystem system(p, AnalysisKind::Dynamics);
  REQUIRE(system.bendingTerms.size() == 2);
  CHECK(system.bendingBlocks[1].firstVertex == first);
  CHECK(system.bendingBlocks[1].mesh->numVertices() == m.second.numVertices());

  // The same energy from terms built over the stacked vertices, one per actor (the layout before).
  const Eigen::VectorXd x = deformed(m.stacked);
  double expected = 0.0;
  Eigen::VectorXd masses = Eigen::VectorXd::Zero(m.stacked.numVertices());
  for (int a = 0; a < 2; ++a) {
    const ShellActorPart& part = p.actors[static_cast<std::size_t>(a)];
    const TriMesh over = a == 0 ? TriMesh{m.stacked.V, m.first.F} : m.secondOverStacked();
    const Topology t = buildTopology(over);
    const ShellReference r = computeReference(over, t);
    MembraneTerm membrane(over, r, part.material.membraneLambda, part.material.membraneMu);
    BendingTerm bending(over, t, r, part.material.bendingAlpha, part.material.bendingBeta);
    if (a == 1) {
      std::vector<char> clamped(static_cast<std::size_t>(m.stacked.numVertices()), 0);
      for (std::size_t v = 0; v < part.clampedVertices.size(); ++v) clamped[first + v] = part.clampedVertices[v];
      bending.setClampedBoundary(clamped);
    }
    expected += membrane.evaluate(x, EvalRequest{}, EvalOptions{}) + bending.evaluate(x, EvalRequest{}, EvalOptions{});
    masses += lumpedMass(over, r, part.material.density);
  }
  CHECK((system.vertexMass() - masses).norm() <= 1e-15 * masses.norm());
  double elastic = 0.0;
  for (const char* name : {"membrane/a", "bending/a", "membrane/b", "bending/b"}) {
    const EnergyTermPtr t = system.objective().term(name);
    REQUIRE(t);
    elastic += t->evaluate(x, EvalRequest{}, EvalOptions{});
  }
  CHECK(elastic == Approx(expected).epsilon(1e-13));
}
