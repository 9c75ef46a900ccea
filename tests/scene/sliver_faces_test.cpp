// Sliver faces (tools/scene/sliver_faces.h): a 1 m strip 0.2 mm wide on 20 × 20 quads ran with no word from the
// reader and stalled after 5 steps in its line search.
#include "tools/scene/sliver_faces.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

using namespace jetshell;
using Json = nlohmann::json;

namespace {

std::vector<std::string> sliverWarnings(const Json& shape) {
  const Json j = {{"gravity", {0, 0, -9.81}},
                  {"actors",
                   {{{"type", "shell"},
                     {"name", "strip"},
                     {"shape", shape},
                     {"material",
                      {{"youngsModulus", 1e6}, {"poissonRatio", 0.3}, {"thickness", 0.0005}, {"volumeDensity", 300}}},
                     {"colliderType", "None"}}}},
                  {"analysis", {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}}}};
  const Scene scene = sceneFromJson(j, ".");
  return sliverFaceWarnings(scene, buildSceneModel(scene).actors);
}

Json strip(double width) {
  return {{"generator", "rectangle"}, {"width", width}, {"height", 1.0}, {"nx", 20}, {"ny", 20}};
}

}  // namespace

TEST_CASE("sliver faces: faces lower than a thousandth of their longest edge are named, others not", "[scene]") {
  // 0.2 mm across in 20 quads: faces 1e-5 m by 0.05 m, their height 2e-4 of their longest edge (the diagonal).
  const std::vector<std::string> narrow = sliverWarnings(strip(0.0002));
  REQUIRE(narrow.size() == 1);
  CHECK_THAT(narrow[0], Catch::StartsWith("shell actor 'strip': 800 of its 800 faces are slivers, lower than 0.001 "
                                          "of their longest edge (the thinnest, face "));
  CHECK_THAT(narrow[0], Catch::Contains(", 0.0002 of its 0.05 m edge): Newton slows down on such faces or stalls"));
  // 1 cm across: faces of height 1e-2 of their edge run well; not named.
  CHECK(sliverWarnings(strip(0.01)).empty());
  // One sliver among good faces: a needle 1e-4 high on a 1 m edge beside a right triangle.
  const Json mesh = {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, -1e-4, 0}}},
                     {"faces", {{0, 1, 2}, {0, 3, 1}}}};
  const std::vector<std::string> one = sliverWarnings(mesh);
  REQUIRE(one.size() == 1);
  CHECK_THAT(one[0], Catch::StartsWith("shell actor 'strip': 1 of its 2 faces are slivers, lower than 0.001 of their "
                                       "longest edge (the thinnest, face 1 counted from 0, 0.0001 of its 1 m edge)"));
}
