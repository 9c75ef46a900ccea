// Every example scene runs its first two steps (3.2 s in CI's Release build): a run the sanitizer pass leaves out
// (scripts/test.sh, sanitizeExclude, says why), so it has a file of its own, which that pass does not build
// (CMakeLists.txt, JETSHELL_LONG_ONLY_TESTS).
#include "tools/output/vtu.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

using namespace jetshell;
namespace fs = std::filesystem;

TEST_CASE("run: every example runs its first steps and writes its outputs") {
  for (const auto& entry : fs::directory_iterator(fs::path(JETSHELL_SOURCE_DIR) / "examples")) {
    if (entry.path().extension() != ".json") continue;
    if (entry.path().filename().string().rfind("fit_", 0) == 0) continue;  // fit files (FITTING.md): tests/tools/fit
    INFO(entry.path().string());
    Scene scene = loadSceneFile(entry.path().string());
    scene.outputs.frameStride = 1;
    RunOptions o;
    o.outputDirectory = (test::scratchDirectory("run_examples") / entry.path().stem()).string();
    o.stepLimit = 2;
    o.pictures = false;
    const RunResult r = runScene(scene, o);
    CHECK(r.stepLimitReached);
    CHECK(!r.interrupted);
    CHECK(r.summary.steps == 2);
    CHECK(r.summary.newtonIterations > 0);
    const nlohmann::json s = json::parseFile((fs::path(o.outputDirectory) / "summary.json").string(), "summary");
    for (const char* key : {"converged", "termination", "steps", "newton_iterations", "wall_seconds", "active_terms",
                            "probes", "final_residual", "residual_tolerance", "force_scale"})
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
