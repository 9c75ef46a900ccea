#include "tools/scene/scene_edge_rules.h"

#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_problem.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

/// A 10 × 1 strip (E h³/12 = 100 per width, ν = 0) on 20 × 2 quads, clamped at x = 0, with a small end force:
/// the linear cantilever, tip deflection F L³ / (3 E I).
nlohmann::json strip(const std::string& clamp) {
  return nlohmann::json::parse(R"({
    "gravity": [0, 0, 0],
    "actors": [{
      "type": "shell", "name": "strip",
      "shape": { "generator": "rectangle", "width": 10.0, "height": 1.0, "nx": 20, "ny": 2 },
      "material": { "youngsModulus": 1.2e6, "poissonRatio": 0.0, "thickness": 0.1, "volumeDensity": 0 },
      "hasGravity": false, "colliderType": "None",
      "fixed": [ { "select": { "group": "left" }, "clampRotation": true } ],
      "loads": [ { "select": { "group": "right" }, "force": [0, 0, 4e-4], "distribution": "edgeLength" } ],
      "probes": [ { "name": "tip", "select": { "nearest": [10, 0.5, 0] } } ]
    }],
    "analysis": { "type": "static", "loadSteps": 1 },
    "solver": { "residualTolerance": 1e-10 },
    "outputs": { "vtu": false, "probesCsv": false, "png": false, "plots": false },
    "edgeRules": { "clamp": ")" + clamp + R"(" }
  })");
}

double tipDeflection(const std::string& clamp) {
  const Scene scene = sceneFromJson(strip(clamp), ".");
  RunOptions o;
  o.outputDirectory = (test::scratchDirectory("edge_rule_tests") / clamp).string();
  fs::remove_all(o.outputDirectory);
  o.pictures = false;
  const RunResult r = runScene(scene, o);
  REQUIRE(r.summary.converged);
  std::ifstream in(fs::path(o.outputDirectory) / "summary.json");
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str())["probes"]["tip"][2].get<double>();
}

}  // namespace

TEST_CASE("scene edge rules: the clamped vertices of every actor are gathered", "[scene]") {
  const Scene scene = sceneFromJson(strip("mirrored_clamp"), ".");
  const SceneModel model = buildSceneModel(scene);
  const ShellProblem problem = shellProblemFromScene(scene, model);
  const std::vector<char> clamped = clampedVerticesOf(problem);
  REQUIRE(static_cast<int>(clamped.size()) == model.numVertices());
  int count = 0;
  for (int v = 0; v < model.numVertices(); ++v)
    if (clamped[static_cast<std::size_t>(v)]) {
      ++count;
      CHECK(model.world.V(v, 0) == 0.0);
    }
  CHECK(count == 3);
}

TEST_CASE("scene edge rules: a run clamps with the scene's clamp rule (linear cantilever)", "[scene]") {
  const double exact = 4e-4 * 1000.0 / (3.0 * 100.0);
  // Measured (VALIDATION.md, linear cantilever 20 × 2): mirrored 1.00125 × exact, reference normal 1.233 ×.
  const double mirrored = tipDeflection("mirrored_clamp");
  CHECK(std::abs(mirrored / exact - 1.0) < 0.002);
  const double reference = tipDeflection("reference_clamp");
  CHECK(reference / exact > 1.1);  // the first-order rule is really the one applied when asked for
}

TEST_CASE("scene edge rules: the pinched hemisphere's two symmetry cuts take the symmetry-plane rule", "[scene]") {
  // A quarter model: every boundary edge on x = 0 or y = 0 keeps its mid-edge normal in that plane; the hole's
  // rim and the equator stay free (moment-free).
  const Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/pinched_hemisphere.json");
  const SceneModel model = buildSceneModel(scene);
  const ShellProblem problem = shellProblemFromScene(scene, model);
  ShellSystem system(problem, AnalysisKind::Statics);
  addSceneEdgeRules(scene, problem, system);
  REQUIRE(system.bending);
  const Topology& topo = system.topology();
  const TriMesh& mesh = system.mesh();
  int cut = 0, free = 0;
  for (int e = 0; e < topo.numEdges(); ++e) {
    if (!topo.isBoundaryEdge(e)) continue;
    const int a = topo.edges(e, 0), b = topo.edges(e, 1);
    const bool onCut = (std::abs(mesh.V(a, 0)) < 1e-9 && std::abs(mesh.V(b, 0)) < 1e-9) ||
                       (std::abs(mesh.V(a, 1)) < 1e-9 && std::abs(mesh.V(b, 1)) < 1e-9);
    INFO("edge " << a << "-" << b);
    CHECK(system.bending->edgeRule(e) == (onCut ? EdgeRule::SymmetryPlane : EdgeRule::SecondOrderFree));
    (onCut ? cut : free) += 1;
  }
  CHECK(cut == 2 * 12);  // 12 rings along each cut
  CHECK(free > 0);
  // At rest the ruled bending energy is zero (the rule's origin is taken at the rest shape).
  CHECK(std::abs(system.bending->evaluate(system.restPositions(), {}, {})) <= 1e-12);
}

TEST_CASE("scene edge rules: bad edge rules are rejected with their JSON pointer", "[scene]") {
  auto reject = [](const nlohmann::json& rules, const std::string& pointer) {
    nlohmann::json scene = strip("mirrored_clamp");
    scene["edgeRules"] = rules;
    INFO(rules.dump());
    CHECK_THROWS_WITH(sceneFromJson(scene, "."), Catch::StartsWith(pointer));
  };
  reject({{"free", "hinged"}}, "/edgeRules/free");
  reject({{"free", "mirrored_clamp"}}, "/edgeRules/free");  // a clamp is no free edge
  reject({{"clamp", "symmetry_plane"}}, "/edgeRules/clamp");
  reject({{"clamp", 3}}, "/edgeRules/clamp");
  reject({{"symmetryPlanes", {{{"normal", {0, 0, 0}}}}}}, "/edgeRules/symmetryPlanes/0/normal");
  reject({{"symmetryPlanes", {{{"point", {0, 0}}}}}}, "/edgeRules/symmetryPlanes/0/point");
  reject({{"symmetryPlanes", {{{"normal", {0, 1, 0}}, {"offset", 1}}}}}, "/edgeRules/symmetryPlanes/0");
  reject({{"symmetryPlanes", nlohmann::json::array()}, {"mirror", true}}, "/edgeRules");
  reject({{"symmetryPlanes", std::vector<nlohmann::json>(17, {{"normal", {0, 1, 0}}})}}, "/edgeRules/symmetryPlanes");
}

TEST_CASE("scene edge rules: the bending stiffness damping takes the same rules as the bending term", "[scene]") {
  // Rayleigh damping is β_R times the same stiffness, so its boundary edges close the same way.
  nlohmann::json json = strip("mirrored_clamp");
  json["actors"][0]["material"]["stiffnessDampingCoefficient"] = 0.01;
  json["analysis"] = {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.01}};
  const Scene scene = sceneFromJson(json, ".");
  const SceneModel model = buildSceneModel(scene);
  const ShellProblem problem = shellProblemFromScene(scene, model);
  ShellSystem system(problem, AnalysisKind::Dynamics);
  addSceneEdgeRules(scene, problem, system);
  REQUIRE(system.bending);
  REQUIRE(system.stiffnessDamping.bending);
  int clamped = 0, free = 0;
  for (int e = 0; e < system.topology().numEdges(); ++e) {
    if (!system.topology().isBoundaryEdge(e)) continue;
    CHECK(system.stiffnessDamping.bending->edgeRule(e) == system.bending->edgeRule(e));
    clamped += system.bending->edgeRule(e) == EdgeRule::MirroredClamp;
    free += system.bending->edgeRule(e) == EdgeRule::SecondOrderFree;
  }
  CHECK(clamped == 2);
  CHECK(free > 0);
}
