#include "tools/output/interrupt.h"
#include "tools/output/vtu.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"

#include <catch2/catch.hpp>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

fs::path freshDirectory(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "jetshell_run_tests" / name;
  fs::remove_all(dir);
  return dir;
}

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

}  // namespace

TEST_CASE("run: every example runs its first steps and writes its outputs") {
  for (const auto& entry : fs::directory_iterator(fs::path(JETSHELL_SOURCE_DIR) / "examples")) {
    if (entry.path().extension() != ".json") continue;
    INFO(entry.path().string());
    Scene scene = loadSceneFile(entry.path().string());
    scene.outputs.frameStride = 1;
    RunOptions o;
    o.outputDirectory = freshDirectory(entry.path().stem().string()).string();
    o.stepLimit = 2;
    o.pictures = false;
    const RunResult r = runScene(scene, o);
    CHECK(r.stepLimitReached);
    CHECK(!r.interrupted);
    CHECK(r.summary.steps == 2);
    CHECK(r.summary.newtonIterations > 0);
    const nlohmann::json s = readJson(fs::path(o.outputDirectory) / "summary.json");
    for (const char* key : {"converged", "termination", "steps", "newton_iterations", "wall_seconds", "active_terms", "probes",
                            "final_residual", "residual_tolerance", "force_scale"})
      CHECK(s.contains(key));
    // Every accepted solve's claim can be checked from the summary alone.
    if (s.contains("final_residual") && s["termination"] != "step_limit")
      CHECK(s["final_residual"].get<double>() <= s["residual_tolerance"].get<double>());
    if (s.contains("force_scale")) CHECK(s["force_scale"].get<double>() > 0.0);
    CHECK(s["termination"] == "step_limit");
    CHECK(s["active_terms"].size() >= 2);
    REQUIRE(!s["probes"].empty());
    for (const auto& p : s["probes"].items()) {
      REQUIRE(p.value().size() == 3);
      for (const auto& u : p.value()) CHECK(std::isfinite(u.get<double>()));
    }
    // Frames 0 (rest), 1 and 2, and a series that lists them.
    CHECK(fs::exists(fs::path(o.outputDirectory) / "frames" / "frame_00002.vtu"));
    const VtuFrame last = readVtu((fs::path(o.outputDirectory) / "frames" / "frame_00002.vtu").string());
    CHECK(last.pointData.count("displacement") == 1);
    CHECK(fs::exists(fs::path(o.outputDirectory) / "frames.pvd"));
    CHECK(fs::exists(fs::path(o.outputDirectory) / "probes.csv"));
  }
}

TEST_CASE("run: Ctrl-C stops after the current step with everything written") {
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/hanging_cloth.json");
  scene.outputs.frameStride = 100;  // the interrupted step's frame is still written
  RunOptions o;
  o.outputDirectory = freshDirectory("interrupted").string();
  o.pictures = false;
  installInterruptHandler();
  requestInterrupt();
  const RunResult r = runScene(scene, o);
  removeInterruptHandler();
  CHECK(r.interrupted);
  CHECK(r.summary.steps == 1);
  CHECK(r.summary.termination == "interrupted");
  CHECK(!r.summary.converged);
  CHECK(fs::exists(fs::path(o.outputDirectory) / "frames" / "frame_00001.vtu"));
  const nlohmann::json s = readJson(fs::path(o.outputDirectory) / "summary.json");
  CHECK(s["termination"] == "interrupted");
  for (const auto& f : fs::recursive_directory_iterator(o.outputDirectory))
    CHECK(f.path().string().find(".tmp") == std::string::npos);  // no half-written file left behind
}

TEST_CASE("run: actors with different materials each get their own elastic terms") {
  const std::string text = R"({
    "gravity": [0, 0, 0],
    "actors": [
      {"type": "shell", "name": "a", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 2, "ny": 2},
       "fixed": [{"select": {"group": "left"}}]},
      {"type": "shell", "name": "b", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 2, "ny": 2},
       "worldFromLocalTransform": {"translation": [2, 0, 0]}, "material": {"density": 2}}
    ],
    "analysis": {"type": "static"}
  })";
  const Scene scene = sceneFromJson(json::parse(text, "two.json"), ".");
  RunOptions o;
  o.outputDirectory = freshDirectory("two").string();
  // Each actor keeps its own material: one membrane and one bending term per actor.
  const RunResult r = runScene(scene, o);
  const std::vector<std::string>& terms = r.summary.activeTerms;
  CHECK(std::find(terms.begin(), terms.end(), "membrane/a") != terms.end());
  CHECK(std::find(terms.begin(), terms.end(), "membrane/b") != terms.end());
}
