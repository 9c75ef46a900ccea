#include "tools/fit/dynamic_fit_problem.h"

#include "tools/fit/fit_report.h"
#include "tools/fit/fit_setup.h"
#include "fit_test_util.h"
#include "core/mesh_io.h"
#include "../../solvers/test_problems.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

using namespace jetshell;

namespace {

std::string example(const std::string& name) { return std::string(JETSHELL_SOURCE_DIR) + "/examples/" + name; }

/// The swinging strip example with its parameters replaced (names, initial values; bounds a factor 100 either
/// side) and the scene changed.
FitFile swingingStrip(const std::vector<std::pair<std::string, double>>& parameters,
                      const std::function<void(nlohmann::json&)>& editScene = {}) {
  std::ifstream in(example("fit_swinging_strip.json"));
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, true, true);
  j["parameters"] = nlohmann::json::array();
  for (const auto& [name, initial] : parameters)
    j["parameters"].push_back({{"actor", "strip"}, {"name", name}, {"initial", initial},
                               {"lower", initial / 100.0}, {"upper", initial * 100.0}, {"logScale", true}});
  if (editScene) editScene(j["scene"]);
  // Only the observations within the (possibly shortened) run.
  nlohmann::json kept = nlohmann::json::array();
  for (const nlohmann::json& o : j["observations"])
    if (o["time"].get<double>() <= j["scene"]["analysis"]["duration"].get<double>() + 1e-12) kept.push_back(o);
  j["observations"] = kept;
  return fitFromJson(j, std::string(JETSHELL_SOURCE_DIR) + "/examples", "fit_swinging_strip.json");
}

/// Central differences of the misfit of whole dynamic runs against the forward-sensitivity gradient.
void checkGradient(FitProblem& p, const Eigen::VectorXd& q) {
  const FitEvaluation g = p.evaluate(q, FitDerivatives::Gradient);
  REQUIRE(g.ok);
  CHECK(g.derivativesExact);
  const FitEvaluation j = p.evaluate(q, FitDerivatives::Jacobian);
  REQUIRE(j.ok);
  CHECK((j.jacobian.transpose() * j.residuals - g.gradient).norm() <= 1e-12 * g.gradient.norm());
  test::checkAgainstCentralDifferences(p, q, g.gradient, 1e-5, "forward sensitivities");
}

}  // namespace

TEST_CASE("dynamic fit: the example's observations are the forward model's at the scene's values", "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  FitSetup setup(loadFitFile(example("fit_swinging_strip.json")));
  FitProblem& p = setup.problem();
  REQUIRE(p.levelName() == "time");
  Eigen::VectorXd truth(2);
  truth << 0.8, 0.2;
  const FitEvaluation e = p.evaluate(truth, FitDerivatives::None);
  REQUIRE(e.ok);
  // The example gives 13 digits; Newton's steps converge to 1e-11 x the force scale, and runs whose Newton
  // iterations take other paths (another linear solver) agree to ~1e-11 m over these 16 steps.
  INFO("largest residual at the truth: " << e.residuals.lpNorm<Eigen::Infinity>() << " m");
  CHECK(e.residuals.lpNorm<Eigen::Infinity>() <= 1e-9);
}

TEST_CASE("dynamic fit: the forward-sensitivity gradient of a BDF2 run matches central differences of whole runs",
          "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  FitSetup setup(loadFitFile(example("fit_swinging_strip.json")));
  Eigen::VectorXd q(2);
  q << 1.3, 0.27;
  checkGradient(setup.problem(), q);
}

TEST_CASE("dynamic fit: gradients through backward Euler with stiffness damping, gravity and bending scales",
          "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  FitSetup setup(swingingStrip({{"stiffnessDampingCoefficient", 0.002}, {"gravityScale", 1.1}, {"bendingBeta", 4e-5}},
                               [](nlohmann::json& scene) {
                                 scene["analysis"]["integrator"] = "backwardEuler";
                                 scene["analysis"]["duration"] = 0.05;
                                 scene["actors"][0]["material"]["stiffnessDampingCoefficient"] = 0.001;
                               }));
  Eigen::VectorXd q(3);
  q << 0.002, 1.1, 4e-5;
  checkGradient(setup.problem(), q);
}

TEST_CASE("dynamic fit: gradients with respect to a load scale under a load ramp", "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  FitSetup setup(swingingStrip({{"loadScale", 1.5}, {"density", 0.25}}, [](nlohmann::json& scene) {
    scene["analysis"]["duration"] = 0.05;
    scene["analysis"]["loadRampTime"] = 0.02;
    scene["actors"][0]["loads"] = nlohmann::json::parse(
        R"([{ "select": { "group": "right" }, "force": [0, 1e-4, -2e-4], "distribution": "edgeLength" }])");
  }));
  Eigen::VectorXd q(2);
  q << 1.5, 0.25;
  checkGradient(setup.problem(), q);
}

TEST_CASE("dynamic fit: gradients with respect to the scale of one named load among others", "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  nlohmann::json loads = nlohmann::json::parse(R"([
      { "select": { "group": "right" }, "force": [0, 0, -2e-4], "distribution": "edgeLength" },
      { "name": "pull", "select": { "group": "right" }, "force": [1e-3, 1e-4, 0], "distribution": "edgeLength" }])");
  FitFile file = swingingStrip({{"loadScale", 1.5}}, [&](nlohmann::json& scene) {
    scene["analysis"]["duration"] = 0.04;
    scene["actors"][0]["loads"] = loads;
  });
  file.parameters[0].load = "pull";
  FitSetup setup(file);
  Eigen::VectorXd q(1);
  q << 1.5;
  checkGradient(setup.problem(), q);
  // At scale 1 the split leaves the loads as they were: the same run as with no fitted load.
  FitFile plain = swingingStrip({{"density", 0.2}}, [&](nlohmann::json& scene) {
    scene["analysis"]["duration"] = 0.04;
    scene["actors"][0]["loads"] = loads;
  });
  FitSetup reference(plain);
  Eigen::VectorXd one(1), rho(1);
  one << 1.0;
  rho << 0.2;
  const FitEvaluation a = setup.problem().evaluate(one, FitDerivatives::None);
  const FitEvaluation b = reference.problem().evaluate(rho, FitDerivatives::None);
  REQUIRE(a.ok);
  REQUIRE(b.ok);
  CHECK((a.residuals - b.residuals).norm() <= 1e-12 * (1.0 + b.residuals.norm()));
}

TEST_CASE("dynamic fit: Levenberg-Marquardt recovers the mass damping and density of the swinging strip to 1e-6",
          "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  const FitFile file = loadFitFile(example("fit_swinging_strip.json"));
  FitSetup setup(file);
  const FitResult r = runFit(setup.problem(), setup.variables(), file.options);
  INFO(r.termination << " " << r.message << ", " << r.counters.evaluations << " evaluations, q = " << r.q.transpose());
  REQUIRE(r.success);
  CHECK(std::abs(r.q[0] / 0.8 - 1.0) <= 1e-6);
  CHECK(std::abs(r.q[1] / 0.2 - 1.0) <= 1e-6);
  CHECK(r.inexactDerivativeEvaluations == 0);
  FitReportInputs in{&setup.problem(), &r, setup.groupLabels(), "fit_swinging_strip.json", file.description};
  const nlohmann::json j = fitReportJson(in);
  CHECK(j["gradient_status"] == "exact");
  CHECK(j["level_kind"] == "time");
  CHECK(j["cost"]["time_steps"] == r.counters.timeSteps);
}

TEST_CASE("dynamic fit: the density is recovered to 1e-6 from the whole shape at one time (an OBJ)", "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  // The target: the strip's shape at t = 0.04 s from the forward model at the scene's values (ρ_A = 0.2).
  const auto shortRun = [](nlohmann::json& scene) { scene["analysis"]["duration"] = 0.04; };
  FitSetup truth(swingingStrip({{"density", 0.2}}, shortRun));
  Eigen::VectorXd rho(1);
  rho << 0.2;
  const FitEvaluation e = truth.problem().evaluate(rho, FitDerivatives::None);
  REQUIRE(e.ok);
  const std::filesystem::path dir = test::scratchDirectory("dynamic_shape_fit");
  std::filesystem::create_directories(dir);
  {
    std::ofstream obj(dir / "strip_0.04.obj");
    obj << std::setprecision(17);
    writeObj(obj, unflatten(e.equilibria.back()), truth.model().world.F);
  }
  std::ifstream in(example("fit_swinging_strip.json"));
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, true, true);
  shortRun(j["scene"]);
  j["parameters"] = nlohmann::json::parse(
      R"([{ "actor": "strip", "name": "density", "initial": 0.5, "lower": 0.01, "upper": 10, "logScale": true }])");
  j["observations"] = nlohmann::json::parse(R"([{ "type": "shape", "actor": "strip", "time": 0.04, "obj": "strip_0.04.obj" }])");
  const FitFile file = fitFromJson(j, dir.string(), "shape_fit.json");
  FitSetup setup(file);
  REQUIRE(setup.problem().numResiduals() == 3 * 63);
  const FitResult r = runFit(setup.problem(), setup.variables(), file.options);
  INFO(r.termination << " " << r.message << ", " << r.counters.evaluations << " evaluations, q = " << r.q.transpose());
  REQUIRE(r.success);
  CHECK(std::abs(r.q[0] / 0.2 - 1.0) <= 1e-6);
}

TEST_CASE("dynamic fit: derivatives through steps accepted at the iteration cap are reported as approximate",
          "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  // The page's preset: a few Newton iterations per step, moving on unconverged.
  const FitFile file = swingingStrip({{"massDampingCoefficient", 2.0}}, [](nlohmann::json& scene) {
    scene["solver"]["maxIterations"] = 2;
    scene["solver"]["acceptIterationCap"] = true;
    scene["analysis"]["duration"] = 0.03;
  });
  FitSetup setup(file);
  Eigen::VectorXd q(1);
  q << 2.0;
  const FitEvaluation e = setup.problem().evaluate(q, FitDerivatives::Gradient);
  REQUIRE(e.ok);
  CHECK_FALSE(e.derivativesExact);
  CHECK(setup.problem().counters().inexactDerivativeSolves > 0);
  FitOptions o = file.options;
  o.maxEvaluations = 2;
  const FitResult r = runFit(setup.problem(), setup.variables(), o);
  CHECK(r.inexactDerivativeEvaluations > 0);
  FitReportInputs in{&setup.problem(), &r, setup.groupLabels(), "", ""};
  CHECK_THAT(fitReportJson(in)["gradient_status"].get<std::string>(), Catch::StartsWith("approximate"));
}

TEST_CASE("dynamic fit: a parameter with no term to set in the scene is rejected with its pointer", "[fit][dynamic]") {
  testing::SingleThread single;  // tens of elements: threads only add barriers
  // No stiffness damping in the example's scene (β_R = 0 builds no damping term).
  CHECK_THROWS_WITH(FitSetup(swingingStrip({{"stiffnessDampingCoefficient", 0.01}})),
                    Catch::StartsWith("/parameters/0/name") && Catch::Contains("no effect"));
  // No applied load to scale.
  CHECK_THROWS_WITH(FitSetup(swingingStrip({{"loadScale", 1.0}})),
                    Catch::StartsWith("/parameters/0/name") && Catch::Contains("no effect"));
}
