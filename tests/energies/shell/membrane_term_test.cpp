#include "core/mesh_generators.h"
#include "core/topology.h"
#include "energies/shell/reference_state.h"
#include "energies/shell/shell_terms.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

using namespace jetshell;
using jetshell::test::denseHessian;

namespace {

struct Sheet {
  TriMesh mesh = makeRectangleGrid(1.0, 0.8, 3, 2);
  Topology topology = buildTopology(mesh);
  ShellReference reference = computeReference(mesh, topology);
  EnergyTermPtr term = makeMembraneTerm(mesh, reference, 0.4, 0.9);
  Eigen::VectorXd rest = flatten(mesh.V);
};

double smallestEigenvalue(const Eigen::MatrixXd& H) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues().minCoeff();
}

}  // namespace

TEST_CASE("membrane: the clamp projection clamps the stress term; exact in tension, positive semi-definite in "
          "compression") {
  Sheet s;
  EvalOptions exact, clamped;
  clamped.projection = PsdProjection::Clamp;
  Eigen::VectorXd g;
  double e = 0.0;

  // Stretched by 10% in both directions: every face in tension, so clamping changes nothing.
  Eigen::VectorXd stretched = 1.1 * s.rest;
  const Eigen::MatrixXd He = denseHessian(*s.term, stretched, exact, g, e);
  const Eigen::MatrixXd Hc = denseHessian(*s.term, stretched, clamped, g, e);
  CHECK((Hc - He).norm() <= 1e-12 * He.norm());

  // Compressed by 20% along x and bent out of plane: the exact Hessian is indefinite, the clamped one is not.
  Eigen::VectorXd squeezed = s.rest;
  for (int v = 0; v < s.mesh.numVertices(); ++v) {
    squeezed[3 * v] *= 0.8;
    squeezed[3 * v + 2] += 0.05 * std::sin(3.0 * s.mesh.V(v, 0));
  }
  const Eigen::MatrixXd He2 = denseHessian(*s.term, squeezed, exact, g, e);
  const Eigen::MatrixXd Hc2 = denseHessian(*s.term, squeezed, clamped, g, e);
  const double scale = He2.cwiseAbs().maxCoeff();
  REQUIRE(smallestEigenvalue(He2) < -1e-3 * scale);
  CHECK(smallestEigenvalue(Hc2) >= -1e-12 * scale);
  // Only the stress term changed: the clamped Hessian still agrees with the exact one on rigid motions (both
  // annihilate a translation).
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(s.rest.size());
  for (int v = 0; v < s.mesh.numVertices(); ++v) shift[3 * v + 1] = 1.0;
  CHECK((Hc2 * shift).norm() <= 1e-12 * scale * shift.norm());

  // The AD path projects the whole 9×9 block: also positive semi-definite.
  EvalOptions adClamped = clamped;
  adClamped.path = DerivativePath::AutoDiff;
  CHECK(smallestEigenvalue(denseHessian(*s.term, squeezed, adClamped, g, e)) >= -1e-12 * scale);
}
