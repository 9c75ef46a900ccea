// Shells that start inside a solid (tools/scene/inside_solids.h). A plate modelled through a ball of radius 5 cm
// (the ball's centre on the plate) ran with no word from the reader, and its static path failed at its first
// increment: "linear solve failed: not positive definite at column 5 (6 tries: ... shift 0.0659 to 659)".
#include "tools/scene/inside_solids.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <vector>

using namespace jetshell;
using Json = nlohmann::json;

namespace {

/// A 0.4 m square plate of 16 × 16 quads (edge 2.5 cm) in z = 0, from (0, 0) to (0.4, 0.4).
Json insidePlate() {
  return {{"type", "shell"},
          {"name", "plate"},
          {"shape", {{"generator", "rectangle"}, {"width", 0.4}, {"height", 0.4}, {"nx", 16}, {"ny", 16}}},
          {"material", {{"youngsModulus", 1e7}, {"poissonRatio", 0.3}, {"thickness", 0.001}, {"volumeDensity", 1000}}},
          {"colliderType", "None"},
          {"fixed", {{{"select", {{"group", "left"}}}}}}};
}

std::vector<std::string> insideWarnings(const Json& solid) {
  const Json j = {{"gravity", {0, 0, 0}},
                  {"actors", {insidePlate(), solid}},
                  {"analysis", {{"type", "static"}, {"loadSteps", 2}}}};
  const Scene scene = sceneFromJson(j, ".");
  return insideSolidWarnings(scene, buildSceneModel(scene).actors);
}

}  // namespace

TEST_CASE("inside solids: a plate through a ball, or below its floor, is named, and one resting on a surface is not",
          "[contact]") {
  const std::vector<std::string> ball =
      insideWarnings({{"type", "sphere"}, {"name", "ball"}, {"center", {0.2, 0.2, 0.0}}, {"radius", 0.05}});
  REQUIRE(ball.size() == 1);
  CHECK(ball[0] == "shell actor 'plate' starts inside volume actor 'ball': 9 of its 289 vertices lie inside it, the "
                   "deepest 0.05 m (vertex 144, counted from 0, at (0.2, 0.2, 0)); the contact penalty pushes them "
                   "out in the first steps (start the shell and the solid apart, and move the solid in)");
  // (The 9 vertices within 5 cm of the centre; the 4 at 5 cm lie on its surface.) The ball 1 cm above the plate,
  // and a floor whose surface the plate lies on: nothing inside.
  CHECK(insideWarnings({{"type", "sphere"}, {"name", "ball"}, {"center", {0.2, 0.2, 0.06}}, {"radius", 0.05}})
            .empty());
  CHECK(insideWarnings({{"type", "plane"}, {"name", "floor"}}).empty());
  // A floor 1 mm above the plate: every vertex below it.
  const std::vector<std::string> floor =
      insideWarnings({{"type", "plane"}, {"name", "floor"}, {"point", {0, 0, 0.001}}});
  REQUIRE(floor.size() == 1);
  CHECK_THAT(floor[0], Catch::StartsWith("shell actor 'plate' starts inside volume actor 'floor': 289 of its 289 "
                                          "vertices lie inside it, the deepest 0.001 m"));
  // A box turned 45° about z is judged in its own frame: a thin box along the diagonal holds the diagonal's
  // vertices, and the same box unturned (along x, 3 cm wide about y = 0.2) holds one row.
  const Json box = {{"type", "box"},
                    {"name", "bar"},
                    {"center", {0.2, 0.2, 0.0}},
                    {"halfExtents", {0.2, 0.005, 0.01}}};
  Json turned = box;
  turned["rotation"] = {{"axis", {0, 0, 1}}, {"degrees", 45}};
  const std::vector<std::string> alongX = insideWarnings(box), diagonal = insideWarnings(turned);
  REQUIRE(alongX.size() == 1);
  REQUIRE(diagonal.size() == 1);
  CHECK_THAT(alongX[0], Catch::Contains("15 of its 289 vertices"));    // y = 0.2, 0.025 < x < 0.375 (|x − 0.2| < 0.2)
  CHECK_THAT(diagonal[0], Catch::Contains("11 of its 289 vertices"));  // x = y within 0.2 of the centre
  // The scene model carries it (run --check and a run print it).
  const Json j = {{"gravity", {0, 0, 0}},
                  {"actors", {insidePlate(), {{"type", "sphere"}, {"name", "ball"}, {"center", {0.2, 0.2, 0.0}},
                                             {"radius", 0.05}}}},
                  {"analysis", {{"type", "static"}, {"loadSteps", 2}}}};
  const std::vector<std::string> all = buildSceneModel(sceneFromJson(j, ".")).warnings;
  CHECK(std::find(all.begin(), all.end(), ball[0]) != all.end());
}
