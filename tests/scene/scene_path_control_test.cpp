#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

nlohmann::json stripScene() {
  return nlohmann::json::parse(R"({
    "gravity": [0, 0, 0],
    "actors": [{
      "type": "shell", "name": "strip",
      "shape": {"generator": "rectangle", "width": 4, "height": 1, "nx": 8, "ny": 2},
      "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.02, "volumeDensity": 100},
      "hasGravity": false,
      "fixed": [{"select": {"group": "left"}, "clampRotation": true}],
      "loads": [{"select": {"group": "right"}, "force": [0, 0, 1], "distribution": "edgeLength"}],
      "probes": [{"name": "tip", "select": {"nearest": [4, 0, 0]}}]
    }],
    "analysis": {"type": "static", "loadSteps": 4,
                 "pathControl": {"type": "displacement", "probe": "tip", "component": "z", "displacement": 0.5}},
    "outputs": {"vtu": false, "png": false, "plots": false}
  })");
}

std::string pathErrorOf(const nlohmann::json& scene) {
  try {
    buildSceneModel(sceneFromJson(scene, test::scratchDirectory("path_control_scenes").string()));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

nlohmann::json run(const Scene& scene, const std::string& name) {
  RunOptions o;
  o.outputDirectory = (test::scratchDirectory("path_control_tests") / name).string();
  fs::remove_all(o.outputDirectory);
  o.pictures = false;
  runScene(scene, o);
  std::ifstream in(fs::path(o.outputDirectory) / "summary.json");
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

}  // namespace

TEST_CASE("scene path control: displacement control drives the probe to its displacement", "[scene][path]") {
  const nlohmann::json s = run(sceneFromJson(stripScene(), "."), "displacement");
  INFO(s.dump(1));
  CHECK(s["converged"] == true);
  CHECK(s["path_control"] == "displacement");
  CHECK(s["steps"] == 4);
  CHECK(s["probes"]["tip"][2].get<double>() == Approx(0.5).epsilon(1e-9));
  CHECK(s["final_load_factor_reached"].get<double>() > 0.0);
  CHECK(s["limit_points"].empty());
  CHECK(s["bifurcation_points"].empty());  // a strip bent by an end force crosses no other branch
  CHECK(s["load_jumps"].empty());
}

TEST_CASE("scene path control: arc length takes the hinged roof through its snap-through", "[scene][path]") {
  std::ifstream in(fs::path(JETSHELL_SOURCE_DIR) / "examples" / "hinged_roof_snap_through.json");
  std::stringstream text;
  text << in.rdbuf();
  Scene scene = loadSceneFile((fs::path(JETSHELL_SOURCE_DIR) / "examples" / "hinged_roof_snap_through.json").string());
  // The example's mesh is 16 x 16; the same scene at 6 x 6 snaps through just the same, faster.
  nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, true, true);
  j["actors"][0]["shape"]["nAround"] = 6;
  j["actors"][0]["shape"]["nAlong"] = 6;
  j["outputs"] = {{"vtu", false}, {"png", false}, {"plots", false}};
  const nlohmann::json s = run(sceneFromJson(j, "."), "arc_length");
  INFO(s.dump(1));
  CHECK(s["converged"] == true);
  CHECK(s["path_control"] == "arcLength");
  CHECK(s["final_load_factor_reached"] == 1.0);
  REQUIRE(s["limit_points"].size() == 2);
  CHECK(s["limit_points"][0]["kind"] == "maximum");
  CHECK(s["limit_points"][1]["kind"] == "minimum");
  CHECK(s["limit_points"][0]["load_factor"].get<double>() > s["limit_points"][1]["load_factor"].get<double>());
  CHECK(s["load_jumps"].empty());  // every step follows the path: arc length cuts a step that jumps
  // The limit loads with two load steps (path points far apart) match ten to 1e-4: each turn is the extremum of
  // the Hermite cubic through the two path points around it, with the tangents' dλ/dp (the parabola through three
  // path points gave 0.12% and 0.75% here).
  j["analysis"]["loadSteps"] = 2;
  const nlohmann::json coarse = run(sceneFromJson(j, "."), "arc_length_coarse");
  REQUIRE(coarse["limit_points"].size() == 2);
  for (std::size_t i = 0; i < 2; ++i)
    CHECK(coarse["limit_points"][i]["load_factor"].get<double>() ==
          Approx(s["limit_points"][i]["load_factor"].get<double>()).epsilon(1e-4));
}

TEST_CASE("scene path control: arc length leaves the rest state of a sheet too soft for its first increment",
          "[scene][path]") {
  // A 1 m steel-stiff sheet 0.1 mm thick clamped along one edge, under its weight (`jetshell stress`'s
  // thickness/h_L=0.0001 cell by arc length). The start's tangent moves the free edge by 89 m in the first
  // increment (a quarter of a level): every correction from there failed, down to the smallest increment. Now the
  // first increment moves it by 5% of the sheet's size, and the path reaches the full weight.
  nlohmann::json j = nlohmann::json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{
      "type": "shell", "name": "sheet",
      "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 6, "ny": 6},
      "material": {"youngsModulus": 1e9, "poissonRatio": 0.3, "thickness": 1e-4, "volumeDensity": 1000},
      "colliderType": "None",
      "fixed": [{"select": {"group": "left"}, "clampRotation": true}],
      "probes": [{"name": "corner", "select": {"nearest": [1, 1, 0]}}]
    }],
    "analysis": {"type": "static", "loadSteps": 4, "pathControl": {"type": "arcLength", "maxSteps": 2000}},
    "solver": {"threads": 1},
    "outputs": {"vtu": false, "png": false, "plots": false}
  })");
  const nlohmann::json s = run(sceneFromJson(j, "."), "soft_start");
  INFO(s.dump(1));
  CHECK(s["converged"] == true);
  CHECK(s["final_load_factor_reached"] == 1.0);
  CHECK(s["probes"]["corner"][2].get<double>() < -0.5);  // the free edge hangs down
  CHECK(s["load_jumps"].empty());
}

TEST_CASE("scene path control: bad path controls are refused with the field's pointer", "[scene][path]") {
  auto edited = [](auto edit) {
    nlohmann::json s = stripScene();
    edit(s["analysis"]["pathControl"]);
    return pathErrorOf(s);
  };
  CHECK(edited([](nlohmann::json& c) { c["type"] = "riks"; }) ==
        "/analysis/pathControl/type: \"riks\" is not one of \"load\", \"arcLength\", \"displacement\"");
  CHECK(edited([](nlohmann::json& c) { c.erase("probe"); }) ==
        "/analysis/pathControl/probe: missing (required: the name of the probe to drive)");
  CHECK(edited([](nlohmann::json& c) { c["probe"] = "apex"; }) ==
        "/analysis/pathControl/probe = \"apex\": no probe has this name");
  CHECK(edited([](nlohmann::json& c) { c["displacement"] = 0; }) ==
        "/analysis/pathControl/displacement = 0: must be finite and non-zero");
  CHECK(edited([](nlohmann::json& c) { c["component"] = "w"; }) ==
        "/analysis/pathControl/component: \"w\" is not one of \"x\", \"y\", \"z\" (did you mean \"x\"?)");
  CHECK(edited([](nlohmann::json& c) { c["loadScaling"] = 1; }) ==
        "/analysis/pathControl/loadScaling: unknown key in a displacement path control (allowed: type, maxSteps, "
        "probe, component, displacement)");
  CHECK(edited([](nlohmann::json& c) { c = {{"type", "arcLength"}, {"maxSteps", 0}}; }) ==
        "/analysis/pathControl/maxSteps = 0: must be >= 1");
  CHECK(edited([](nlohmann::json& c) { c = {{"type", "arcLength"}, {"loadScaling", -1}}; }) ==
        "/analysis/pathControl/loadScaling = -1: must be finite and >= 0");
  // A probe on a fixed vertex cannot be driven.
  nlohmann::json s = stripScene();
  s["actors"][0]["probes"][0]["select"] = {{"nearest", {0, 0, 0}}};
  CHECK_THROWS_WITH(run(sceneFromJson(s, "."), "fixed_probe"), Catch::Contains("/analysis/pathControl/probe") &&
                                                                  Catch::Contains("fixed"));
}
