#include "tools/fit/fit_setup.h"

#include "tools/fit/fit_report.h"
#include "fit_test_util.h"
#include "validation/self_weight_elastica.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <filesystem>

using namespace jetshell;

namespace {

std::string examplePath(const std::string& name) { return std::string(JETSHELL_SOURCE_DIR) + "/examples/" + name; }

}  // namespace

TEST_CASE("fit: the adjoint gradient of a shell fit matches central differences of whole solves", "[fit]") {
  FitSetup setup(loadFitFile(examplePath("fit_synthetic_plate.json")));
  FitProblem& p = setup.problem();
  Eigen::VectorXd q(4);
  q << 200.0, 500.0, 3e-5, 5e-5;
  const FitEvaluation g = p.evaluate(q, FitDerivatives::Gradient);
  REQUIRE(g.ok);
  const FitEvaluation j = p.evaluate(q, FitDerivatives::Jacobian);
  REQUIRE(j.ok);
  CHECK((g.gradient - j.gradient).norm() <= 1e-8 * g.gradient.norm());
  test::checkAgainstCentralDifferences(p, q, g.gradient, 1e-4, "adjoint");
}

TEST_CASE("fit: Levenberg-Marquardt recovers lambda, mu, alpha, beta of the synthetic plate to 1e-6", "[fit]") {
  const FitFile file = loadFitFile(examplePath("fit_synthetic_plate.json"));
  FitSetup setup(file);
  const FitResult r = runFit(setup.problem(), setup.variables(), file.options);
  INFO(r.termination << " " << r.message << ", " << r.counters.evaluations << " evaluations, q = " << r.q.transpose());
  REQUIRE(r.success);
  const double truth[4] = {300.0, 400.0, 2e-5, 7e-5};
  for (int i = 0; i < 4; ++i) CHECK(std::abs(r.q[i] / truth[i] - 1.0) <= 1e-6);
  REQUIRE(r.uncertainty.available);
  CHECK(r.uncertainty.correlation.diagonal().isApproxToConstant(1.0, 1e-12));

  FitReportInputs in{&setup.problem(), &r, setup.groupLabels(), "fit_synthetic_plate.json", file.description};
  const nlohmann::json j = fitReportJson(in);
  CHECK(j["parameters"].size() == 4);
  CHECK(j["history"].size() == r.history.size());
  CHECK(j["cost"]["full_solves"] == r.counters.fullSolves);
  const std::string dir = test::scratchDirectory("fit_report_test").string();
  std::vector<std::string> notes;
  const std::vector<std::string> files = writeFitReport(in, dir, false, notes);
  CHECK(std::filesystem::exists(dir + "/fit.json"));
}

TEST_CASE("fit: the cloth overhang's fitted flexural rigidity matches the self-weight elastica's", "[fit]") {
  // examples/fit_cloth_overhang.json: a 50 mm strip whose tip chord drops 41.5°; D = β per width (α = 0).
  const FitFile file = loadFitFile(examplePath("fit_cloth_overhang.json"));
  FitSetup setup(file);
  const FitResult r = runFit(setup.problem(), setup.variables(), file.options);
  INFO(r.termination << " " << r.message << ", q = " << r.q.transpose());
  REQUIRE(r.success);
  const double pi = 3.14159265358979323846;
  const double elastica = validation::rigidityForChordAngle(0.05, file.material.shell.density * 9.81, 41.5 * pi / 180.0);
  // Measured −0.011% on the examplePath's 40 × 4 mesh with the mirrored clamp (18.6% with the reference-normal
  // clamp, FITTING.md); the target is 1%.
  CHECK(std::abs(r.q[0] / elastica - 1.0) < 2e-4);
}
