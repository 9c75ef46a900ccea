#include "tools/bench/stage_jet_width.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <set>

using namespace jetshell;

TEST_CASE("bench stage-jets: every Jet-differentiated stage of the shell at both orders, the two widths agreeing") {
  const std::vector<StageJetWidthRow> rows = benchStageJetWidth(6, 1);
  REQUIRE(rows.size() == 8);
  std::set<std::string> stages;
  for (const StageJetWidthRow& r : rows) {
    stages.insert(r.stage);
    CHECK((r.order == 1 || r.order == 2));
    CHECK(std::isfinite(r.nsPlain));
    CHECK(r.nsPlain > 0.0);
    CHECK(std::isfinite(r.nsFramework));
    CHECK(r.nsFramework > 0.0);
    CHECK(r.largestDifference <= 1e-12);
  }
  CHECK(stages == std::set<std::string>{"unit_normal", "kelvin", "bending_density", "membrane_density"});
}
