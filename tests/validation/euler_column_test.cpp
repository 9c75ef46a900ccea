// The Euler column of examples/euler_column.json buckles past its critical load, by dynamic relaxation, load
// control and arc length: three whole runs (943 relaxation steps, 2.3 s in CI's Release build), which the
// sanitizer pass leaves out (scripts/test.sh, sanitizeExclude), so a file of its own, which that pass does not
// build (CMakeLists.txt, JETSHELL_LONG_ONLY_TESTS); the relaxation's saddle test covers the same code there.
#include "example_run.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace jetshell;
using test::ExampleRun;
using test::runExample;

namespace {

/// The inextensible elastica's tip deflection for examples/euler_column.json (P = 1.6 P_cr, L 10): the modulus k
/// with K(k) = (π/2)·√1.6 (bisection on std::comp_ellint_1, which rises with k), and δ = 2 k L / K(k) = 8.0085.
double eulerColumnElastica() {
  const double K = 0.5 * M_PI * std::sqrt(1.6);
  double lo = 0.0, hi = 1.0 - 1e-12;
  for (int i = 0; i < 100; ++i) (std::comp_ellint_1(0.5 * (lo + hi)) < K ? lo : hi) = 0.5 * (lo + hi);
  return 2.0 * lo * 10.0 / K;
}

/// A static run of the Euler column that switched branches once at the critical load and reached the elastica.
void checkSwitchedToElastica(const ExampleRun& run, double elastica) {
  const RunResult& r = run.result;
  REQUIRE(r.summary.converged);
  const nlohmann::json& switches = r.summary.extra.at("branch_switches");
  REQUIRE(switches.size() == 1);
  // The critical load π² EI / 4L² = 2.467, λ = 0.617 of the end force 4; the mesh's own within 0.2%.
  CHECK(switches[0].at("stable_load_factor").get<double>() == Approx(0.6169).epsilon(0.002));
  REQUIRE(run.probes.size() >= 10);
  CHECK(run.probes.back()[2] == Approx(1.0).margin(1e-12));  // the last row is λ = 1
  const double w = std::abs(run.probes.back()[5]);
  INFO("tip deflection " << w << ", elastica " << elastica);
  CHECK(std::abs(w - elastica) / elastica < 0.003);  // measured 0.17% (8.0224)
}

}  // namespace

TEST_CASE("scene accuracy: the Euler column leaves the straight saddle and buckles to the elastica within 0.3%",
          "[validation]") {
  const test::ScopedThreads serial(1);
  const double elastica = eulerColumnElastica();
  REQUIRE(elastica == Approx(8.0085).epsilon(1e-4));
  SECTION("by dynamic relaxation (the example)") {
    const ExampleRun run = runExample("euler_column");
    const RunResult& r = run.result;
    REQUIRE(r.summary.converged);
    CHECK(r.summary.extra.at("saddle_escapes").get<int>() >= 1);  // the relaxation reached the straight saddle
    CHECK(r.summary.extra.at("unstable_equilibria").get<int>() == 0);
    REQUIRE(!run.probes.empty());
    const double w = std::abs(run.probes.back()[5]);
    INFO("tip deflection " << w << ", elastica " << elastica);
    CHECK(std::abs(w - elastica) / elastica < 0.003);  // measured 0.17% (8.0224)
  }
  // The example as a static analysis in 10 load steps under `control`.
  auto staticColumn = [](const std::string& control) {
    return runExample(
        "euler_column",
        [&](Scene& s) {
          s.analysis.type = AnalysisType::Static;
          s.analysis.loadSteps = 10;
          s.analysis.pathControl.type = control;
        },
        "_" + control);
  };
  SECTION("by load control, switching branches at the bifurcation") {
    const ExampleRun run = staticColumn("load");
    checkSwitchedToElastica(run, elastica);
    CHECK(run.result.summary.extra.at("unstable_equilibria").get<int>() == 0);
  }
  SECTION("by arc length, switching branches at the bifurcation") {
    const ExampleRun run = staticColumn("arcLength");
    checkSwitchedToElastica(run, elastica);
    CHECK(run.result.summary.extra.at("bifurcation_points").empty());  // switched, not passed
  }
}
