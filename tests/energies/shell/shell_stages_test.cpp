#include "energies/shell/shell_stages.h"

#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <random>

using namespace jetshell;

namespace {

template <typename S>
void randomInput(std::mt19937_64& rng, double* z) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < S::kInputs; ++i) z[i] = u(rng);
}

}  // namespace

TEST_CASE("shell stages: the densities' kept quadratics are their Jets' Hessians at every input", "[stages]") {
  // The density is a quadratic in b per face: the Hessian its term keeps (from Jets at one b, without the area
  // scale) must be the Jets' Hessian at any other b, and the stage hands it out only when told it is kept.
  std::mt19937_64 rng(5);
  ShellReference ref;
  ref.area = {0.37};
  ref.inverseMetric = {{0.95, -0.2, 1.15}};
  ref.secondFundamentalForm = {{0.3, -0.1, 0.2}};
  std::vector<std::array<bool, 3>> minimized = {{false, false, false}};
  std::vector<Eigen::Matrix3d> quadratic(1);
  BendingDensityStage bending{&ref, 0.3, 0.7, 2.0, &minimized, &quadratic};
  for (int rule = 0; rule < 2; ++rule) {
    minimized[0] = {rule == 1, false, false};  // the page's density, then one moment-free edge minimized out
    StageDerivativesOf<BendingDensityStage> atRest;
    const double b0[3] = {0.3, -0.1, 0.2};
    stageDerivativesFromJets(bending, b0, 0, 2, atRest);
    quadratic[0] = atRest.hessians[0] / (2.0 * 0.37);
    Eigen::Matrix3d H;
    bending.quadratic = nullptr;
    CHECK_FALSE(bending.quadraticHessian(0, H));
    CHECK(quadraticHessianDiscrepancy(bending, b0, 0) == 0.0);  // nothing kept: nothing to compare
    bending.quadratic = &quadratic;
    for (int trial = 0; trial < 10; ++trial) {
      double z[3];
      randomInput<BendingDensityStage>(rng, z);
      // Measured 0 (a quadratic's nested Jets give the same Hessian at every input); a stale matrix (other moduli
      // or rule) shows at O(1).
      CHECK(quadraticHessianDiscrepancy(bending, z, 0) <= 1e-12);
      // The order-2 derivatives on the Jets then take it: the same as the nested Jets'.
      StageDerivativesOf<BendingDensityStage> kept, jets;
      evaluateStage(bending, z, 0, 2, DerivativePath::AutoDiff, kept);
      stageDerivativesFromJets(bending, z, 0, 2, jets);
      CHECK(kept.value[0] == Approx(jets.value[0]).epsilon(1e-14).margin(1e-15));  // first- and second-order Jets round apart
      CHECK((kept.jacobian - jets.jacobian).norm() <= 1e-14 * jets.jacobian.norm());
      CHECK((kept.hessians[0] - jets.hessians[0]).norm() <= 1e-12 * jets.hessians[0].norm());
    }
    BendingDensityStage stale = bending;
    stale.alpha = 0.6;
    double z[3] = {0.1, 0.2, -0.3};
    CHECK(quadraticHessianDiscrepancy(stale, z, 0) > 1e-3);
  }
  // The membrane's density, quadratic in the metric, the same way.
  ref.metric = {{1.1, 0.2, 0.9}};
  std::vector<Eigen::Matrix3d> membraneQuadratic(1);
  MembraneDensityStage membrane{&ref, 3.0, 4.0, 2.0};
  const double a0[3] = {1.0, 0.1, 1.2};
  StageDerivativesOf<MembraneDensityStage> atA0;
  stageDerivativesFromJets(membrane, a0, 0, 2, atA0);
  membraneQuadratic[0] = atA0.hessians[0] / (2.0 * 0.37);
  CHECK(quadraticHessianDiscrepancy(membrane, a0, 0) == 0.0);  // nothing kept yet
  membrane.quadratic = &membraneQuadratic;
  for (int trial = 0; trial < 10; ++trial) {
    double z[3];
    randomInput<MembraneDensityStage>(rng, z);
    CHECK(quadraticHessianDiscrepancy(membrane, z, 0) <= 1e-12);
  }
  membrane.mu = 1.0;
  CHECK(quadraticHessianDiscrepancy(membrane, a0, 0) > 1e-3);
}

TEST_CASE("shell stages: the twins equal the Jets and the constant-Hessian declarations hold", "[stages]") {
  std::mt19937_64 rng(11);
  // A one-face reference for the energy stages, with a moved origin so that the densities' gradients are not 0.
  ShellReference ref;
  ref.area = {0.37};
  ref.metric = {{1.1, 0.2, 0.9}};
  ref.inverseMetric = {{0.95, -0.2, 1.15}};
  ref.secondFundamentalForm = {{0.3, -0.1, 0.2}};
  const BendingDensityStage bending{&ref, 0.3, 0.7, 2.0};
  const MembraneDensityStage membrane{&ref, 3.0, 4.0, 2.0};
  // Edges 0..4 on the boundary with each rule, edge 5 interior.
  const std::vector<EdgeRule> edgeRules = {EdgeRule::PageFree, EdgeRule::ReferenceClamp, EdgeRule::MirroredClamp,
                                           EdgeRule::SecondOrderFree, EdgeRule::SymmetryPlane, EdgeRule::PageFree};
  std::vector<EdgeRuleData> edgeData(edgeRules.size());
  for (EdgeRuleData& d : edgeData) {
    d.reference[0] = 0.6;
    d.reference[1] = 0.0;
    d.reference[2] = 0.8;
    d.axis[0] = 1.0;
  }
  Topology topology;  // only which edges are on the boundary matters here
  topology.edgeFaces.resize(6, 2);
  topology.edgeFaces << 0, -1, 1, -1, 2, -1, 3, -1, 4, -1, 5, 6;
  const EdgeMeanStage edgeMean{&edgeRules, &edgeData, &topology};
  for (int trial = 0; trial < 20; ++trial) {
    double z[15];
    // Twins, relative to the Jets' largest entry (measured <= 4e-16; limit 1e-12). The unit normal's and the
    // Kelvin inversion's include their weighted-Hessian twins Σ_k w_k ∇²y_k (and the face normal's contracted
    // Hessian on the analytic path goes through the unit normal's).
    STATIC_REQUIRE(HasWeightedHessianTwin<UnitNormalStage>::value);
    STATIC_REQUIRE(HasWeightedHessianTwin<KelvinStage>::value);
    // The pullback twins (Jᵀw) are checked by the same discrepancies; these stages declare them.
    STATIC_REQUIRE(HasPullbackTwin<FaceCrossStage>::value);
    STATIC_REQUIRE(HasPullbackTwin<UnitNormalStage>::value);
    STATIC_REQUIRE(HasPullbackTwin<FaceNormalStage>::value);
    STATIC_REQUIRE(HasPullbackTwin<EdgeMeanStage>::value);
    STATIC_REQUIRE(HasPullbackTwin<KelvinStage>::value);
    STATIC_REQUIRE(HasPullbackTwin<SecondFormStage>::value);
    randomInput<UnitNormalStage>(rng, z);
    CHECK(stageTwinDiscrepancy(UnitNormalStage(), z, 0) <= 1e-12);
    randomInput<FaceNormalStage>(rng, z);
    CHECK(composedStageDiscrepancy(FaceNormalStage(), z, 0, DerivativePath::AutoDiff) <= 1e-12);
    CHECK(composedStageDiscrepancy(FaceNormalStage(), z, 0, DerivativePath::Analytic) <= 1e-12);
    randomInput<KelvinStage>(rng, z);
    CHECK(stageTwinDiscrepancy(KelvinStage(), z, 0) <= 1e-12);
    randomInput<BendingDensityStage>(rng, z);
    CHECK(stageTwinDiscrepancy(bending, z, 0) <= 1e-12);
    CHECK(stageTwinDiscrepancy(membrane, z, 0) <= 1e-12);
    // Bilinear and linear stages: their Hessians are the same everywhere (exactly: small integer entries).
    randomInput<SecondFormStage>(rng, z);
    CHECK(constantHessianDiscrepancy(SecondFormStage(), z, 0) == 0.0);
    CHECK(constantHessianDiscrepancy(FaceCrossStage(), z, 0) == 0.0);
    // The edge mean is affine in the normals on interior edges and under every boundary rule.
    for (int e = 0; e < static_cast<int>(edgeRules.size()); ++e) CHECK(affineDiscrepancy(edgeMean, z, e) == 0.0);
    // The twins of the edge mean (on the interior edge, and its rule's Jets on each boundary edge), of the second
    // fundamental form, of the cross product and of the metric.
    for (int e = 0; e < static_cast<int>(edgeRules.size()); ++e) CHECK(stageTwinDiscrepancy(edgeMean, z, e) <= 1e-15);
    CHECK(stageTwinDiscrepancy(SecondFormStage(), z, 0) <= 1e-15);
    CHECK(stageTwinDiscrepancy(FaceCrossStage(), z, 0) <= 1e-15);
    CHECK(constantHessianDiscrepancy(MetricStage(), z, 0) == 0.0);
    CHECK(stageTwinDiscrepancy(MetricStage(), z, 0) <= 1e-15);
  }
  CHECK_FALSE(constantStageHessians<SecondFormStage>().zero);
}

TEST_CASE("shell stages: the StVK quadratic's value and gradient are the same bits with and without its Hessian",
          "[stages]") {
  // A Newton step that skips its Hessian compares its residual with one that assembled it: the densities' first-
  // order twins must give the gradient the second-order ones give.
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const double P[3] = {1.0 + 0.5 * u(rng), 0.3 * u(rng), 1.0 + 0.5 * u(rng)};
    const double d[3] = {u(rng), u(rng), 1e-9 * u(rng)};
    double W1, W2;
    Eigen::Vector3d g1, g2;
    Eigen::Matrix3d H;
    analytic::stvkQuadratic(P, 0.3, 0.35, d, W1, g1);
    analytic::stvkQuadratic(P, 0.3, 0.35, d, W2, g2, H);
    CHECK(W1 == W2);
    CHECK(g1 == g2);
  }
}
