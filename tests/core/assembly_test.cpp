#include "tests/test_util.h"
#include "core/assembly.h"
#include "core/element_loop.h"
#include "core/mesh_generators.h"
#include "energies/shell/shell_terms.h"

#include <catch2/catch.hpp>

#include <cstring>
#include <random>
#include <set>

using namespace jetshell;
using namespace jetshell::test;

namespace {

/// Dense reference: Σ_e Pₑᵀ Hₑ Pₑ with Pₑ selecting the element's vertices (absent ones dropped).
Eigen::MatrixXd referenceAssembly(const StencilTable& t, const std::vector<Eigen::MatrixXd>& blocks, int n) {
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int e = 0; e < t.size(); ++e) {
    const int* ids = t.element(e);
    for (int a = 0; a < t.width; ++a)
      for (int b = 0; b < t.width; ++b)
        if (ids[a] >= 0 && ids[b] >= 0) A.block<3, 3>(3 * ids[a], 3 * ids[b]) += blocks[e].block<3, 3>(3 * a, 3 * b);
  }
  return A;
}

Eigen::MatrixXd mirrored(const Eigen::SparseMatrix<double>& upper) {
  const Eigen::MatrixXd U(upper);
  Eigen::MatrixXd full = U + U.transpose();
  full.diagonal() -= U.diagonal();
  return full;
}

bool sameBits(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
  return a.nonZeros() == b.nonZeros() &&
         std::memcmp(a.valuePtr(), b.valuePtr(), sizeof(double) * static_cast<std::size_t>(a.nonZeros())) == 0;
}

/// Whether A's values are what setZero() leaves: zero, and 1 on the diagonal of each fixed dof.
bool valuesAsSetZero(const HessianAssembler& A, const std::vector<char>& fixed) {
  const Eigen::SparseMatrix<double>& m = A.matrix();
  for (Eigen::Index j = 0; j < m.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(m, j); it; ++it) {
      const double expected = it.row() == j && fixed[static_cast<std::size_t>(j)] ? 1.0 : 0.0;
      if (it.value() != expected) return false;
    }
  return true;
}

struct ShellFixture {
  TriMesh mesh;
  Topology topology;
  ShellReference reference;
  EnergyTermPtr membrane, bending;
  Eigen::VectorXd x;
  explicit ShellFixture(int nx, int ny) : mesh(makeRectangleGrid(1.0, 0.7, nx, ny)) {
    topology = buildTopology(mesh);
    reference = computeReference(mesh, topology);
    membrane = makeMembraneTerm(mesh, reference, 3.0, 4.0);
    bending = makeBendingTerm(mesh, topology, reference, 0.3, 0.5);
    x = flatten(mesh.V);
    for (int v = 0; v < mesh.numVertices(); ++v) x[3 * v + 2] = 0.1 * std::sin(5.0 * x[3 * v]) * std::cos(3.0 * x[3 * v + 1]);
  }
  /// Energy of both terms; gradient and Hessian into g and A (A's values zeroed first).
  double evaluate(HessianAssembler& A, int slotM, int slotB, Eigen::VectorXd& g, const EvalOptions& o) {
    A.setZero();
    g.setZero(x.size());
    return membrane->evaluate(x, {&g, &A, slotM}, o) + bending->evaluate(x, {&g, &A, slotB}, o);
  }
};

}  // namespace

TEST_CASE("assembly: the pattern is built once and value-only refills give identical bits") {
  ScopedThreads serial(1);
  ShellFixture s(4, 3);
  HessianAssembler A;
  const int slotM = A.addStencils(s.membrane->stencils());
  const int slotB = A.addStencils(s.bending->stencils());
  A.finalize(s.mesh.numVertices());
  const std::uint64_t version = A.patternVersion();
  const int* inner = A.matrix().innerIndexPtr();
  Eigen::VectorXd g;
  const double e1 = s.evaluate(A, slotM, slotB, g, EvalOptions{});
  const Eigen::SparseMatrix<double> first = A.matrix();
  // A different configuration in between, then the first again.
  const Eigen::VectorXd x0 = s.x;
  s.x += 0.05 * Eigen::VectorXd::Ones(s.x.size());
  s.evaluate(A, slotM, slotB, g, EvalOptions{});
  s.x = x0;
  const double e2 = s.evaluate(A, slotM, slotB, g, EvalOptions{});
  CHECK(e1 == e2);
  CHECK(sameBits(first, A.matrix()));
  CHECK(A.patternVersion() == version);
  CHECK(A.matrix().innerIndexPtr() == inner);  // no reallocation
  CHECK(A.matrix().nonZeros() == first.nonZeros());
  CHECK_THROWS_AS(A.addStencils(s.membrane->stencils()), std::logic_error);
}

TEST_CASE("assembly: the same bits with 1 and 2 OpenMP threads") {
  ShellFixture s(24, 16);  // 768 faces: above the serial threshold, so both loops really run in parallel
  REQUIRE(s.mesh.numFaces() >= kParallelMinElements);
  REQUIRE(s.bending->stencils().size() >= kParallelMinElements);
  HessianAssembler A;
  const int slotM = A.addStencils(s.membrane->stencils());
  const int slotB = A.addStencils(s.bending->stencils());
  A.finalize(s.mesh.numVertices());
  for (DerivativePath path : {DerivativePath::AutoDiff, DerivativePath::Analytic}) {
    EvalOptions o;
    o.path = path;
    o.projection = PsdProjection::Clamp;
    Eigen::VectorXd g1, g2;
    double e1, e2;
    Eigen::SparseMatrix<double> h1;
    {
      ScopedThreads one(1);
      e1 = s.evaluate(A, slotM, slotB, g1, o);
      h1 = A.matrix();
    }
    {
      ScopedThreads two(2);
      e2 = s.evaluate(A, slotM, slotB, g2, o);
    }
    CHECK(e1 == e2);
    CHECK(std::memcmp(g1.data(), g2.data(), sizeof(double) * static_cast<std::size_t>(g1.size())) == 0);
    CHECK(sameBits(h1, A.matrix()));
  }
}

TEST_CASE("assembly: matches the dense sum of element blocks, with repeated and absent vertices") {
  // Elements of width 3 with a repeated vertex (two local vertices on one global vertex) and an absent one.
  StencilTable t;
  t.width = 3;
  t.ids = {0, 1, 2,   // ordinary
           3, 3, 1,   // vertex 3 twice: off-diagonal local entries land on a global diagonal block
           2, -1, 0,  // an absent vertex
           4, 2, 4};
  const int n = 5;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::MatrixXd> blocks;
  for (int e = 0; e < t.size(); ++e) {
    Eigen::MatrixXd B(9, 9);
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j) B(i, j) = u(rng);
    blocks.push_back(B + B.transpose());
  }
  HessianAssembler A;
  const int slot = A.addStencils(t);
  A.finalize(n);
  for (int e = 0; e < t.size(); ++e) A.addElementHessian(slot, e, blocks[e].data());
  const Eigen::MatrixXd expected = referenceAssembly(t, blocks, n);
  CHECK((mirrored(A.matrix()) - expected).norm() <= 1e-14 * expected.norm());
  // Only the upper triangle is stored.
  const Eigen::MatrixXd U(A.matrix());
  CHECK(U.triangularView<Eigen::StrictlyLower>().toDenseMatrix().norm() == 0.0);
}

TEST_CASE("assembly: fixed dofs produce identity rows and columns") {
  ScopedThreads serial(1);
  ShellFixture s(3, 2);
  std::vector<char> fixed;
  for (int d = 0; d < 3 * s.mesh.numVertices(); ++d) fixed.push_back(d < 3 || d == 3 * 5 + 2);  // vertex 0, z of 5
  HessianAssembler A;
  const int slotM = A.addStencils(s.membrane->stencils());
  const int slotB = A.addStencils(s.bending->stencils());
  A.finalize(s.mesh.numVertices(), fixed);
  Eigen::VectorXd g;
  s.evaluate(A, slotM, slotB, g, EvalOptions{});
  const Eigen::MatrixXd H = mirrored(A.matrix());
  HessianAssembler free;
  const int fM = free.addStencils(s.membrane->stencils());
  const int fB = free.addStencils(s.bending->stencils());
  free.finalize(s.mesh.numVertices());
  s.evaluate(free, fM, fB, g, EvalOptions{});
  const Eigen::MatrixXd Hfree = mirrored(free.matrix());
  for (int d = 0; d < H.rows(); ++d) {
    INFO("dof " << d);
    if (fixed[d]) {
      Eigen::VectorXd unit = Eigen::VectorXd::Unit(H.rows(), d);
      CHECK(H.row(d).transpose() == unit);
      CHECK(H.col(d) == unit);
    } else {
      for (int c = 0; c < H.cols(); ++c)
        if (!fixed[c]) REQUIRE(H(d, c) == Hfree(d, c));
    }
  }
  CHECK_THROWS_AS(free.finalize(2, std::vector<char>(5, 0)), std::invalid_argument);
}

TEST_CASE("assembly: setZero leaves every value of a large pattern as it should, on 1 and 2 threads") {
  // Large enough for the zeroing to be split over the threads, with a value count no thread count divides evenly.
  ShellFixture s(60, 60);
  std::vector<char> fixed(static_cast<std::size_t>(3 * s.mesh.numVertices()), 0);
  for (std::size_t d = 0; d < fixed.size(); d += 7) fixed[d] = 1;
  HessianAssembler A;
  A.addStencils(s.membrane->stencils());
  A.addStencils(s.bending->stencils());
  A.finalize(s.mesh.numVertices(), fixed);
  REQUIRE(A.matrix().nonZeros() >= HessianAssembler::kParallelZeroValues);
  REQUIRE(A.matrix().nonZeros() % 2 != 0);
  for (int threads : {1, 2}) {
    ScopedThreads t(threads);
    std::fill(A.matrix().valuePtr(), A.matrix().valuePtr() + A.matrix().nonZeros(), 7.0);
    A.setZero();
    CHECK(valuesAsSetZero(A, fixed));
  }
}

TEST_CASE("assembly: colouring separates elements that share a vertex") {
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, 5, 4);
  const Topology topo = buildTopology(mesh);
  StencilTable t;
  t.width = 6;
  t.ids.assign(topo.bendingStencil.data(), topo.bendingStencil.data() + topo.bendingStencil.size());
  const std::vector<std::vector<int>> colors = colorElements(t, mesh.numVertices());
  std::vector<int> seen(static_cast<std::size_t>(t.size()), 0);
  for (const std::vector<int>& color : colors) {
    std::set<int> used;
    for (int e : color) {
      ++seen[e];
      for (int k = 0; k < t.width; ++k) {
        const int v = t.element(e)[k];
        if (v >= 0) CHECK(used.insert(v).second);
      }
    }
  }
  for (int count : seen) CHECK(count == 1);
}

TEST_CASE("assembly: a grow-only pattern keeps its version while re-declared pairs fit, and grows or prunes "
          "otherwise") {
  // Six vertices: a fixed base element (0,1,2) and moving "contact" pairs.
  const int n = 6;
  const StencilTable base{3, {0, 1, 2}};
  auto pairs = [](std::vector<int> ids) { return StencilTable{2, std::move(ids)}; };
  auto declare = [&](HessianAssembler& A, const StencilTable& contact) {
    A.clearStencils();
    const int slotBase = A.addStencils(base);
    const int slotContact = A.addStencils(contact);
    A.finalize(n);
    return std::pair<int, int>{slotBase, slotContact};
  };
  // Assembles unit element blocks and compares with the dense sum over the declared elements.
  auto checkValues = [&](HessianAssembler& A, std::pair<int, int> slots, const StencilTable& contact) {
    A.setZero();
    const Eigen::MatrixXd hb = Eigen::MatrixXd::Constant(9, 9, 1.0) + Eigen::MatrixXd::Identity(9, 9);
    const Eigen::MatrixXd hc = Eigen::MatrixXd::Constant(6, 6, 0.5) + Eigen::MatrixXd::Identity(6, 6);
    A.addElementHessian(slots.first, 0, hb.data());
    for (int e = 0; e < contact.size(); ++e) A.addElementHessian(slots.second, e, hc.data());
    Eigen::MatrixXd expected = referenceAssembly(base, {hb}, n);
    expected += referenceAssembly(contact, std::vector<Eigen::MatrixXd>(contact.size(), hc), n);
    CHECK((mirrored(A.matrix()) - expected).cwiseAbs().maxCoeff() == 0.0);
  };

  HessianAssembler A;
  A.setGrowOnly(true, 1.0);
  const StencilTable c1 = pairs({3, 4});
  auto slots = declare(A, c1);
  const std::uint64_t v1 = A.patternVersion();
  const Eigen::Index nnz1 = A.matrix().nonZeros();
  CHECK(A.patternBuilds() == 1);
  checkValues(A, slots, c1);

  // The pair leaves contact: the pattern is kept (its entries are stored zeros), no new version.
  const StencilTable none = pairs({});
  slots = declare(A, none);
  CHECK(A.patternVersion() == v1);
  CHECK(A.matrix().nonZeros() == nnz1);
  CHECK(A.patternReuses() == 1);
  CHECK(A.patternPairs() > A.usedPairs());
  checkValues(A, slots, none);

  // It comes back, in the other order: still the same pattern.
  const StencilTable c1r = pairs({4, 3});
  slots = declare(A, c1r);
  CHECK(A.patternVersion() == v1);
  checkValues(A, slots, c1r);

  // A new pair: the pattern grows to the union (both pairs stored).
  const StencilTable c2 = pairs({0, 5});
  slots = declare(A, c2);
  CHECK(A.patternVersion() > v1);
  CHECK(A.patternBuilds() == 2);
  CHECK(A.matrix().nonZeros() > nnz1);
  checkValues(A, slots, c2);
  const std::uint64_t v2 = A.patternVersion();
  slots = declare(A, c1);
  CHECK(A.patternVersion() == v2);
  checkValues(A, slots, c1);

  // With no slack for stale pairs, growth prunes to the exact pattern.
  HessianAssembler B;
  B.setGrowOnly(true, 0.0);
  declare(B, c1);
  declare(B, none);  // kept: no growth, so no pruning either
  CHECK(B.patternBuilds() == 1);
  slots = declare(B, c2);
  CHECK(B.patternBuilds() == 2);
  CHECK(B.patternPairs() == B.usedPairs());
  checkValues(B, slots, c2);

  // Off (the default): every finalize builds the exact pattern.
  HessianAssembler C;
  declare(C, c1);
  const std::uint64_t c1Version = C.patternVersion();
  declare(C, c1);
  CHECK(C.patternVersion() > c1Version);
  CHECK(C.patternPairs() == C.usedPairs());
}

TEST_CASE("assembly: replacing one slot's stencils gives the pattern and the bits of declaring every slot again") {
  // A shell (membrane, bending) with two fixed dofs, and a moving "contact" slot of pairs between distant
  // vertices (a repeated vertex included), re-declared several times, exact and grow-only.
  ShellFixture f(7, 5);
  const int n = f.mesh.numVertices();
  std::vector<char> fixed(static_cast<std::size_t>(3 * n), 0);
  fixed[4] = fixed[3 * (n - 1)] = 1;
  const std::vector<StencilTable> contacts = {
      {2, {0, n - 1, 3, 20}}, {2, {}}, {2, {5, 30, 0, n - 1, 11, 11}}, {2, {n - 2, 1}}, {2, {5, 30, 0, n - 1}}};
  const Eigen::MatrixXd hc = Eigen::MatrixXd::Constant(6, 6, 0.25) + Eigen::MatrixXd::Identity(6, 6);
  for (bool growOnly : {false, true}) {
    HessianAssembler replaced, declared;
    replaced.setGrowOnly(growOnly, 1.0);
    declared.setGrowOnly(growOnly, 1.0);
    int slotM = replaced.addStencils(f.membrane->stencils());
    int slotB = replaced.addStencils(f.bending->stencils());
    const int slotC = replaced.addStencils(contacts[0]);
    replaced.finalize(n, fixed);
    for (const StencilTable& c : contacts) {
      replaced.replaceStencils(slotC, c);
      replaced.finalize(n, fixed);
      // The previous iteration's values are gone, whether the pattern is new or kept (grow-only).
      CHECK(valuesAsSetZero(replaced, fixed));
      declared.clearStencils();
      slotM = declared.addStencils(f.membrane->stencils());
      slotB = declared.addStencils(f.bending->stencils());
      declared.addStencils(c);
      declared.finalize(n, fixed);
      CHECK(replaced.patternPairs() == declared.patternPairs());
      Eigen::VectorXd g1, g2;
      const EvalOptions o{DerivativePath::Analytic, PsdProjection::None};
      f.evaluate(replaced, slotM, slotB, g1, o);
      f.evaluate(declared, slotM, slotB, g2, o);
      for (int e = 0; e < c.size(); ++e) {
        replaced.addElementHessian(slotC, e, hc.data());
        declared.addElementHessian(slotC, e, hc.data());
      }
      const Eigen::SparseMatrix<double>& a = replaced.matrix();
      const Eigen::SparseMatrix<double>& b = declared.matrix();
      REQUIRE(a.nonZeros() == b.nonZeros());
      CHECK(std::memcmp(a.outerIndexPtr(), b.outerIndexPtr(), sizeof(int) * static_cast<std::size_t>(a.cols() + 1)) == 0);
      CHECK(std::memcmp(a.innerIndexPtr(), b.innerIndexPtr(), sizeof(int) * static_cast<std::size_t>(a.nonZeros())) == 0);
      CHECK(sameBits(a, b));
    }
    // A slot kept so far is replaced too (fewer bending hinges, then all again): its adjacency is rebuilt.
    StencilTable fewer = f.bending->stencils();
    fewer.ids.resize(fewer.ids.size() / 2 / static_cast<std::size_t>(fewer.width) * static_cast<std::size_t>(fewer.width));
    for (const StencilTable& b : {fewer, f.bending->stencils()}) {
      replaced.replaceStencils(slotB, b);
      replaced.finalize(n, fixed);
      declared.clearStencils();
      declared.addStencils(f.membrane->stencils());
      declared.addStencils(b);
      declared.addStencils(contacts.back());
      declared.finalize(n, fixed);
      CHECK(replaced.patternPairs() == declared.patternPairs());
      CHECK(replaced.usedPairs() == declared.usedPairs());
      const Eigen::SparseMatrix<double>& a = replaced.matrix();
      const Eigen::SparseMatrix<double>& c = declared.matrix();
      REQUIRE(a.nonZeros() == c.nonZeros());
      CHECK(std::memcmp(a.innerIndexPtr(), c.innerIndexPtr(), sizeof(int) * static_cast<std::size_t>(a.nonZeros())) == 0);
    }
    CHECK(replaced.patternPairs() > 0);
    CHECK_THROWS_AS(replaced.replaceStencils(slotC, StencilTable{3, {0, 1, 2}}), std::invalid_argument);
    CHECK_THROWS_AS(replaced.replaceStencils(7, contacts[0]), std::out_of_range);
  }
}
