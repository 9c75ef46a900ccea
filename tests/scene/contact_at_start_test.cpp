// Layers that start in contact (tools/scene/contact_at_start.h): point-cloud samples that interact and lie nearer
// at t = 0 than their radii's sum, so the penalty pushes them apart before anything else moves. Two 20 × 20 cloths
// put 2 mm over one another, shifted 1 cm, held 17 J of contact energy at the start with no word from the reader.
#include "tools/scene/contact_at_start.h"
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

/// A 1 m cloth of 20 × 20 quads (edge 5 cm) with point-cloud samples of radius r, moved by `translation`.
Json layer(const std::string& name, const Json& translation, double r) {
  return {{"type", "shell"},
          {"name", name},
          {"shape", {{"generator", "rectangle"}, {"width", 1.0}, {"height", 1.0}, {"nx", 20}, {"ny", 20}}},
          {"worldFromLocalTransform", {{"translation", translation}}},
          {"material", {{"youngsModulus", 1e5}, {"poissonRatio", 0.3}, {"thickness", 0.001}, {"volumeDensity", 300}}},
          {"colliderType", "PointCloud"},
          {"pointCloudCollider", {{"radius", r}}}};
}

std::vector<std::string> startWarnings(const Json& actors) {
  const Json j = {{"actors", actors}, {"analysis", {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}}}};
  const Scene scene = sceneFromJson(j, ".");
  const SceneModel model = buildSceneModel(scene);
  return contactAtStartWarnings(scene, model.actors);
}

}  // namespace

TEST_CASE("contact at start: two layers within their radii are named, layers apart not", "[contact]") {
  // Every sample of 'b' lies 0.0143 m from its twin in 'a', within 2 × 0.01 m.
  const std::vector<std::string> overlapping =
      startWarnings({layer("a", {0, 0, 0}, 0.01), layer("b", {0.01, 0.01, 0.002}, 0.01)});
  REQUIRE(overlapping.size() == 1);
  CHECK(overlapping[0] == "shell actors 'a' and 'b' start in contact: 441 pairs of point-cloud samples lie nearer "
                          "than their radii's sum, the nearest 0.0143 m apart against 0.02 m; the penalty pushes "
                          "them apart in the first steps (start the samples at least 0.02 m apart, or take smaller "
                          "radii)");
  // 2.5 cm apart: beyond 2 cm. The scene model carries the warning too (run --check and a run print it).
  CHECK(startWarnings({layer("a", {0, 0, 0}, 0.01), layer("b", {0, 0, 0.025}, 0.01)}).empty());
  const Json j = {{"actors", {layer("a", {0, 0, 0}, 0.01), layer("b", {0.01, 0.01, 0.002}, 0.01)}},
                  {"analysis", {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}}}};
  const std::vector<std::string> all = buildSceneModel(sceneFromJson(j, ".")).warnings;
  CHECK(std::find(all.begin(), all.end(), overlapping[0]) != all.end());
}

TEST_CASE("contact at start: a self-contact whose exclusion lets rest neighbours within 2r push is named",
          "[contact]") {
  Json cloth = layer("cloth", {0, 0, 0}, 0.05);
  cloth["pointCloudCollider"]["selfContact"] = true;
  CHECK(startWarnings(Json::array({cloth})).empty());  // the default ratio, 1.5: no rest pair within 2r interacts
  cloth["pointCloudCollider"]["selfContactExclusionRatio"] = 0.2;
  const std::vector<std::string> w = startWarnings(Json::array({cloth}));
  REQUIRE(w.size() == 1);
  CHECK(w[0].rfind("shell actor 'cloth' starts in contact with itself: ", 0) == 0);
  CHECK(w[0].find("the nearest 0.05 m apart against 0.1 m") != std::string::npos);
  CHECK(w[0].find("or a selfContactExclusionRatio of at least 1)") != std::string::npos);
}
