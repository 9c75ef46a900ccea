#include "core/mesh_io.h"
#include "tools/output/atomic_file.h"
#include "tools/output/checkpoint.h"
#include "tools/output/interrupt.h"
#include "tools/output/vtu.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

fs::path freshDirectory(const std::string& name) {
  const fs::path dir = test::scratchDirectory("run_tests") / name;
  fs::remove_all(dir);
  return dir;
}

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

std::string fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> fileLines(const fs::path& p) {
  std::istringstream in(fileBytes(p));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// A probes.csv row's fields, as numbers.
std::vector<double> csvNumbers(const std::string& line) {
  std::istringstream in(line);
  std::vector<double> values;
  for (std::string field; std::getline(in, field, ',');) values.push_back(std::stod(field));
  return values;
}

/// Runs the scene into a fresh directory `name` with Ctrl-C already pressed: it stops after its first step.
RunResult runInterrupted(const Scene& scene, const std::string& name, RunOptions& o) {
  o.outputDirectory = freshDirectory(name).string();
  o.pictures = false;
  installInterruptHandler();
  requestInterrupt();
  const RunResult r = runScene(scene, o);
  removeInterruptHandler();
  return r;
}

}  // namespace

TEST_CASE("run: Ctrl-C stops after the current step with everything written") {
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/hanging_cloth.json");
  scene.outputs.frameStride = 100;  // the interrupted step's frame is still written
  RunOptions o;
  const RunResult r = runInterrupted(scene, "interrupted", o);
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

TEST_CASE("run: a second run into the same directory leaves none of the first run's frames or pictures") {
  // Measured before: 61 frames of a whole run, then a 10-step run into the same directory: frames/ held 61 files,
  // frames.pvd listed 6, and the first run's final.png stayed beside the second run's summary.json.
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/hanging_cloth.json");
  scene.outputs.frameStride = 1;
  RunOptions o;
  o.outputDirectory = freshDirectory("second_run").string();
  o.stepLimit = 6;
  o.pictures = true;
  runScene(scene, o);
  const fs::path dir(o.outputDirectory);
  REQUIRE(fs::exists(dir / "frames" / "frame_00006.vtu"));
  REQUIRE(fs::exists(dir / "final.png"));
  std::ofstream(dir / "notes.txt") << "mine";
  o.stepLimit = 2;
  o.pictures = false;
  runScene(scene, o);
  int frames = 0;
  for (const auto& f : fs::directory_iterator(dir / "frames")) frames += f.path().extension() == ".vtu" ? 1 : 0;
  CHECK(frames == 3);  // frames 0, 1 and 2 of the second run
  CHECK_FALSE(fs::exists(dir / "final.png"));
  CHECK_FALSE(fs::exists(dir / "probes.png"));
  CHECK(fs::exists(dir / "notes.txt"));
  CHECK(fileLines(dir / "probes.csv").size() == 4);  // a header and steps 0, 1, 2
}

TEST_CASE("run: a new run does not remove the checkpoint of an interrupted run, which --resume continues",
          "[checkpoint]") {
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/hanging_cloth.json");
  scene.outputs.frameStride = 1;
  RunOptions o;
  o.checkpointEvery = 1;
  const RunResult interrupted = runInterrupted(scene, "unfinished", o);  // stops after its first step
  REQUIRE(interrupted.interrupted);
  const fs::path dir(o.outputDirectory);
  REQUIRE(fs::exists(dir / "checkpoint.cbor"));
  // A new run there would remove the checkpoint: refused, naming --resume.
  o.stepLimit = 2;
  CHECK_THROWS_WITH(runScene(scene, o), Catch::Contains("holds the checkpoint of an interrupted run, which --resume " +
                                                        o.outputDirectory + " continues"));
  CHECK(fs::exists(dir / "checkpoint.cbor"));
  // A run killed before it wrote its summary.json alike.
  fs::remove(dir / "summary.json");
  CHECK_THROWS_WITH(runScene(scene, o), Catch::Contains("a run that stopped before writing its summary.json"));
  // Resumed, it ends; a new run over a run that ended is free to start over.
  runInterrupted(scene, "unfinished", o);
  o.resume = true;
  o.stepLimit = 3;
  const RunResult resumed = runScene(scene, o);
  CHECK(resumed.stepLimitReached);
  o.resume = false;
  o.stepLimit = 2;
  CHECK(runScene(scene, o).stepLimitReached);
}

TEST_CASE("run: a static path stopped between two levels ends on a frame of its own load factor") {
  // The first increment is a quarter of a level (λ = 0.025 of 10 levels): Ctrl-C stops the path there, and the
  // final frame and probe row say λ = 0.025, not the previous level's 0 (they had: row 0 then carried the
  // displacement at 0.025).
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/cantilever_strip.json");
  REQUIRE(scene.analysis.loadSteps == 10);
  RunOptions o;
  const RunResult r = runInterrupted(scene, "static_interrupted", o);
  CHECK(r.interrupted);
  CHECK(r.summary.steps == 0);
  const nlohmann::json s = readJson(fs::path(o.outputDirectory) / "summary.json");
  CHECK(s.at("final_load_factor").get<double>() == 0.025);
  CHECK(s.at("final_load_factor_reached").get<double>() == 0.025);
  const std::vector<std::string> lines = fileLines(fs::path(o.outputDirectory) / "probes.csv");
  REQUIRE(lines.size() == 3);  // the header, λ = 0 and λ = 0.025
  CHECK(lines[1].rfind("0,0,0,0,0,0", 0) == 0);
  CHECK(lines[2].rfind("1,0.025,0.025,", 0) == 0);
  CHECK(fs::exists(fs::path(o.outputDirectory) / "frames" / "frame_00001.vtu"));
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
  // summary.json has one entry per actor, in scene order, over that actor's own vertices.
  const nlohmann::json summary = readJson(fs::path(o.outputDirectory) / "summary.json");
  // Load control reports its check of unstable equilibria (nothing to leave here). The unloaded scene is at
  // equilibrium from the start, so no factor vouched for any step and each was checked: actor b is free, and its
  // six rigid motions leave pivots of round-off size and either sign, which are not negative eigenvalues.
  CHECK(summary.at("saddle_escapes") == 0);
  CHECK(summary.at("unstable_equilibria") == 0);
  CHECK(summary.at("stability_checks") == summary.at("load_steps_solved"));
  const nlohmann::json actors = summary.at("actors");
  REQUIRE(actors.size() == 2);
  CHECK(actors[0]["name"] == "a");
  CHECK(actors[1]["name"] == "b");
  CHECK(actors[0]["vertices"] == 9);
  CHECK(actors[1]["faces"] == 8);
  CHECK(actors[0]["max_displacement"].get<double>() < 1e-9);  // no load: both stay at rest
  CHECK(actors[1]["bounding_box"]["min"][0].get<double>() == Approx(2.0));
  CHECK(actors[1]["bounding_box"]["max"][0].get<double>() == Approx(3.0));
  CHECK(actors[0]["bounding_box"]["max"][0].get<double>() == Approx(1.0));
}

TEST_CASE("run: several shell actors write one frame file per actor, each a named part of the series") {
  const std::string text = R"({
    "gravity": [0, 0, -9.81],
    "actors": [
      {"type": "shell", "name": "a", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 2, "ny": 2},
       "fixed": [{"select": {"group": "left"}}]},
      {"type": "shell", "name": "b & \"<c>\"", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 3, "ny": 2},
       "worldFromLocalTransform": {"translation": [2, 0, 0]}, "fixed": [{"select": {"group": "left"}}]},
      {"type": "plane", "name": "floor", "point": [0, 0, -5], "normal": [0, 0, 1]}
    ],
    "analysis": {"type": "static", "loadSteps": 1}
  })";
  const Scene scene = sceneFromJson(json::parse(text, "two.json"), ".");
  RunOptions o;
  o.outputDirectory = freshDirectory("two_frames").string();
  const RunResult r = runScene(scene, o);
  REQUIRE(r.lastFrame.size() == 2);
  const fs::path frames = fs::path(o.outputDirectory) / "frames";
  // The last frame (load step 1), per actor: its own vertices, faces and displacements.
  const VtuFrame a = readVtu((frames / "frame_00001_a0.vtu").string());
  const VtuFrame b = readVtu((frames / "frame_00001_a1.vtu").string());
  CHECK(a.points.rows() == 9);
  CHECK(a.triangles.rows() == 8);
  CHECK(b.points.rows() == 12);
  CHECK(b.triangles.rows() == 12);
  CHECK(b.triangles.maxCoeff() == 11);  // indices local to the actor's file
  CHECK(b.points.col(0).minCoeff() == Approx(2.0));
  REQUIRE(b.pointData.count("displacement") == 1);
  CHECK(b.pointData.at("displacement").values.size() == 36);
  double sag = 0.0;
  for (std::size_t k = 2; k < 36; k += 3) sag = std::min(sag, b.pointData.at("displacement").values[k]);
  CHECK(sag < 0.0);  // gravity bends the second actor too
  CHECK_FALSE(fs::exists(frames / "frame_00001.vtu"));
  // The series names each block after its actor (escaped), and the volumes come last.
  const std::string pvd = fileBytes(fs::path(o.outputDirectory) / "frames.pvd");
  CHECK(pvd.find("part=\"0\" name=\"a\" file=\"frames/frame_00001_a0.vtu\"") != std::string::npos);
  CHECK(pvd.find("part=\"1\" name=\"b &amp; &quot;&lt;c&gt;&quot;\" file=\"frames/frame_00001_a1.vtu\"") !=
        std::string::npos);
  CHECK(pvd.find("part=\"2\" name=\"volumes\" file=\"volumes.vtu\"") != std::string::npos);
  // The picture shows both actors.
  CHECK(fs::exists(fs::path(o.outputDirectory) / "final.png"));
}

TEST_CASE("run: past 64 shell actors a frame is one file, its actor cell array telling the actors apart") {
  // 65 one-quad actors (100,000 actors had written 300,000 files for 3 frames).
  nlohmann::json scene = {{"gravity", {0, 0, -9.81}}, {"analysis", {{"type", "static"}, {"loadSteps", 1}}}};
  for (int k = 0; k < 65; ++k)
    scene["actors"].push_back({{"type", "shell"}, {"name", "s" + std::to_string(k)},
                               {"shape",
                                {{"generator", "rectangle"}, {"width", 1}, {"height", 1}, {"nx", 1}, {"ny", 1}}},
                               {"worldFromLocalTransform", {{"translation", {2 * k, 0, 0}}}}, {"colliderType", "None"},
                               {"fixed", {{{"select", {{"group", "left"}}}}}}});
  RunOptions o;
  o.outputDirectory = freshDirectory("many_frames").string();
  o.pictures = false;
  const RunResult r = runScene(sceneFromJson(scene, "."), o);
  REQUIRE(r.lastFrame.size() == 1);
  const fs::path frames = fs::path(o.outputDirectory) / "frames";
  CHECK_FALSE(fs::exists(frames / "frame_00001_a0.vtu"));
  const VtuFrame f = readVtu((frames / "frame_00001.vtu").string());
  CHECK(f.points.rows() == 65 * 4);
  REQUIRE(f.cellData.count("actor") == 1);
  const std::vector<double>& actor = f.cellData.at("actor").values;
  REQUIRE(actor.size() == 65 * 2);
  CHECK(actor.front() == 0.0);
  CHECK(actor.back() == 64.0);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(frames)) files += entry.is_regular_file() ? 1 : 0;
  CHECK(files == 2);  // the rest state and load step 1
}

namespace {


/// Every file under dir (relative path → bytes); summary.json without its wall time.
std::map<std::string, std::string> outputFiles(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& f : fs::recursive_directory_iterator(dir)) {
    if (!f.is_regular_file()) continue;
    const std::string rel = fs::relative(f.path(), dir).string();
    if (rel == "summary.json") {
      nlohmann::json s = readJson(f.path());
      s.erase("wall_seconds");
      files[rel] = s.dump();
    } else {
      files[rel] = fileBytes(f.path());
    }
  }
  return files;
}

}  // namespace

/// Runs `scene` (dynamic, `steps` steps) whole, and again stopped after step 8 with checkpoints every 5 steps,
/// then resumed from step 5 as `--resume DIR` alone does (the checkpoints' cadence read from the checkpoint): both
/// end converged with the same Newton iterations and the same bytes in every output file, the checkpoint too.
/// Returns the resumed run's options (resume set).
RunOptions resumedBitForBit(const Scene& scene, const std::string& name, int steps, int checkpointEvery = 5,
                             int stopAfter = 8) {
  RunOptions o;
  o.pictures = false;
  o.checkpointEvery = checkpointEvery;
  o.sceneFingerprint = name;
  // Uninterrupted.
  const fs::path wholeDirectory = freshDirectory(name + "_whole");
  o.outputDirectory = wholeDirectory.string();
  const RunResult whole = runScene(scene, o);
  REQUIRE(whole.summary.converged);
  REQUIRE(whole.summary.steps == steps);
  // Stopped after step stopAfter (8: the last checkpoint is step 5), then resumed.
  o.outputDirectory = freshDirectory(name + "_resumed").string();
  o.stepLimit = stopAfter;
  const RunResult stopped = runScene(scene, o);
  REQUIRE(stopped.stepLimitReached);
  o.stepLimit = 0;
  o.resume = true;
  o.checkpointEvery = 0;
  const RunResult resumed = runScene(scene, o);
  CHECK(resumed.summary.converged);
  CHECK(resumed.summary.steps == steps);
  CHECK(resumed.summary.newtonIterations == whole.summary.newtonIterations);
  const auto a = outputFiles(wholeDirectory);
  const auto b = outputFiles(o.outputDirectory);
  REQUIRE(a.size() == b.size());
  for (const auto& [file, bytes] : a) {
    INFO(file);
    REQUIRE(b.count(file) == 1);
    CHECK(b.at(file) == bytes);
  }
  return o;
}

TEST_CASE("run: a dynamic run resumed from its checkpoint ends bit for bit as an uninterrupted one", "[checkpoint]") {
  // A small hanging cloth; BDF2, so the history of the last step must survive the restart too.
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{"type": "shell", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 5, "ny": 5},
                "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.0005, "volumeDensity": 300,
                             "massDampingCoefficient": 0.2},
                "colliderType": "None", "fixed": [{"select": [{"nearest": [0, 1, 0]}, {"nearest": [1, 1, 0]}]}],
                "probes": [{"name": "corner", "select": {"nearest": [1, 0, 0]}}]}],
    "analysis": {"type": "dynamic", "timeStep": 0.02, "duration": 0.24, "integrator": "bdf2"},
    "solver": {"threads": 1},
    "outputs": {"frameStride": 2, "obj": true}})"),
                                    ".");
  RunOptions o = resumedBitForBit(scene, "cloth", 12);
  // A hand-edited checkpoint is refused with the field, not followed into a crash or an absurd summary.
  const nlohmann::json saved = readCheckpoint(o.outputDirectory);
  auto resumeEdited = [&](const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json c = saved;
    edit(c);
    writeCheckpoint(o.outputDirectory, c);
    return runScene(scene, o);
  };
  CHECK_THROWS_WITH(resumeEdited([](nlohmann::json& c) { c["output"]["plot_rows"] = nlohmann::json::array(); }),
                    Catch::Contains("output/plot_rows: do not match plot_stride and recorded_rows"));
  CHECK_THROWS_WITH(resumeEdited([](nlohmann::json& c) { c["solver"]["steps"] = 2147483647; }),
                    Catch::Contains("solver/steps: must be a whole number in [0, 10000000]"));
  CHECK_THROWS_WITH(resumeEdited([](nlohmann::json& c) { c["solver"]["t"] = 1e308; }),
                    Catch::Contains("solver/t: must lie in [0, duration]"));
  CHECK_THROWS_WITH(resumeEdited([](nlohmann::json& c) { c["newton_iterations"] = -100; }),
                    Catch::Contains("newton_iterations: must be a whole number in [0, 1000000000]"));
  CHECK_THROWS_WITH(
      resumeEdited([](nlohmann::json& c) { c["worst_residual_over_tolerance"] = std::nan(""); }),
      Catch::Contains("worst_residual_over_tolerance: must be finite and >= 0"));
  // The last frame is drawn into final.png when no step is left: it was read from wherever the checkpoint named.
  CHECK_THROWS_WITH(resumeEdited([](nlohmann::json& c) { c["output"]["last_frame"] = {"/etc/hostname"}; }),
                    Catch::Contains("output/last_frame: must name files frames/NAME.vtu"));
  // Probe rows without their values wrote probes.csv rows short of columns.
  CHECK_THROWS_WITH(resumeEdited([](nlohmann::json& c) { c["output"]["last_row"]["u"] = nlohmann::json::array(); }),
                    Catch::Contains("output/last_row/u: must be a list of 3 numbers"));
  // A checkpoint whose last row is not where it says in probes.csv, and a probes.csv edited since the checkpoint,
  // are refused before anything is cut: the resumed run cut the file there and wrote on, or over its last row.
  CHECK_THROWS_WITH(resumeEdited([](nlohmann::json& c) {
                      c["output"]["last_row_offset"] = c["output"]["last_row_offset"].get<std::int64_t>() - 1;
                    }),
                    Catch::Contains("probes.csv: the checkpoint's last row is not where the checkpoint says"));
  writeCheckpoint(o.outputDirectory, saved);
  const fs::path probes = fs::path(o.outputDirectory) / "probes.csv";
  const std::string original = fileBytes(probes);
  const std::size_t rowTen = original.find("\n10,") + 1;
  REQUIRE(rowTen > 0);
  std::string edited = original;
  edited[original.find(',', rowTen + 3) - 1] ^= 1;  // the last digit of its time
  writeFileAtomically(probes.string(), edited);
  CHECK_THROWS_WITH(runScene(scene, o), Catch::Contains("probes.csv: does not end as at the checkpoint"));
  CHECK(fileBytes(probes) == edited);
  writeFileAtomically(probes.string(), original);
  REQUIRE(runScene(scene, o).summary.converged);
  CHECK(fileBytes(probes) == original);
  // A different scene is refused.
  o.sceneFingerprint = "another";
  CHECK_THROWS_WITH(runScene(scene, o), Catch::Contains("written for another scene"));
  // Static runs have no checkpoints.
  Scene statics = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/cantilever_strip.json");
  o.resume = false;
  o.checkpointEvery = 5;
  CHECK_THROWS_WITH(runScene(statics, o), Catch::Contains("only dynamic analyses have checkpoints"));
}

TEST_CASE("run: a settled run resumed from its checkpoint ends bit for bit, its Newton memory forgotten at the "
          "checkpoint", "[checkpoint]") {
  // A heavily damped cloth that has come to rest: some steps end at their start (no Newton iteration), which the
  // solver remembered for the next solves (how it assembles a start). The checkpointing run kept that memory
  // across the checkpoint and the resumed one started without it; from step 342 on the two differed.
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{"type": "shell", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 4, "ny": 4},
                "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.0005, "volumeDensity": 300,
                             "massDampingCoefficient": 100},
                "colliderType": "None", "fixed": [{"select": [{"nearest": [0, 1, 0]}, {"nearest": [1, 1, 0]}]}],
                "probes": [{"name": "corner", "select": {"nearest": [1, 0, 0]}}]}],
    "analysis": {"type": "dynamic", "timeStep": 0.016666666666666666, "duration": 6, "integrator": "backwardEuler"},
    "solver": {"threads": 2},
    "outputs": {"frameStride": 2000}})"),
                                    ".");
  resumedBitForBit(scene, "settled_cloth", 360, 20, 350);
}

TEST_CASE("run: a run whose grip turns by full turns resumes bit for bit", "[checkpoint]") {
  // Its residuals are judged against the grip's motion over the whole run (DynamicsOptions::duration), which a
  // resumed run must judge the same way from the scene alone.
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, 0],
    "actors": [{"type": "shell", "shape": {"generator": "rectangle", "width": 1, "height": 0.2, "nx": 10, "ny": 2},
                "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.01, "volumeDensity": 1000},
                "colliderType": "None",
                "fixed": [{"select": {"group": "left"}, "clampRotation": true},
                          {"select": {"group": "right"},
                           "rotation": {"axis": [1, 0, 0], "center": [1, 0.1, 0], "degrees": 720}}],
                "probes": [{"name": "tip", "select": {"nearest": [1, 0, 0]}}]}],
    "analysis": {"type": "dynamic", "timeStep": 0.02, "duration": 0.2, "loadRampTime": 0.2},
    "solver": {"threads": 1}})"),
                                    ".");
  resumedBitForBit(scene, "grip", 10);
}

TEST_CASE("run: a moving volume actor is drawn where its path puts it at every frame, a still one once",
          "[checkpoint]") {
  // A 1.2 × 0.6 m slab rising 0.1 m while it turns 90° about z over 0.2 s, and a floor that stays; frames at
  // t = 0, 0.1, 0.2.
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, 0],
    "actors": [{"type": "shell", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 3, "ny": 3},
                "worldFromLocalTransform": {"translation": [0, 0, 0.5]}},
               {"type": "box", "name": "lift", "center": [0.5, 0.5, 0], "halfExtents": [0.6, 0.3, 0.05],
                "keyframes": [{"time": 0.2, "translation": [0, 0, 0.1],
                               "rotation": {"axis": [0, 0, 1], "degrees": 90}}]},
               {"type": "plane", "name": "floor", "point": [0, 0, -1], "normal": [0, 0, 1]}],
    "analysis": {"type": "dynamic", "timeStep": 0.02, "duration": 0.2},
    "solver": {"threads": 1},
    "outputs": {"frameStride": 5, "obj": true}})"),
                                    ".");
  CHECK(unsupportedFeatures(scene).empty());
  RunOptions o;
  o.outputDirectory = freshDirectory("moving_volume").string();
  const RunResult r = runScene(scene, o);
  REQUIRE(r.summary.converged);
  const fs::path dir(o.outputDirectory);
  // The floor alone in volumes.vtu (volume 1 of the scene's volume actors), the slab in each frame's file.
  const VtuFrame still = readVtu((dir / "volumes.vtu").string());
  REQUIRE(still.cellData.count("volume") == 1);
  for (double id : still.cellData.at("volume").values) CHECK(id == 1.0);
  auto box = [&](int frame) {
    const VtuFrame f = readVtu((dir / "frames" / ("volumes_0000" + std::to_string(frame) + ".vtu")).string());
    for (double id : f.cellData.at("volume").values) CHECK(id == 0.0);
    return std::pair<Eigen::Vector3d, Eigen::Vector3d>(f.points.colwise().minCoeff(), f.points.colwise().maxCoeff());
  };
  const auto [lo0, hi0] = box(0);
  CHECK((lo0 - Eigen::Vector3d(-0.1, 0.2, -0.05)).norm() < 1e-12);
  CHECK((hi0 - Eigen::Vector3d(1.1, 0.8, 0.05)).norm() < 1e-12);
  const auto [lo1, hi1] = box(1);  // half way: turned 45°, risen 5 cm
  const double reach = 0.9 * std::sqrt(0.5);  // (0.6 + 0.3) / √2
  CHECK((lo1 - Eigen::Vector3d(0.5 - reach, 0.5 - reach, 0.0)).norm() < 1e-12);
  CHECK((hi1 - Eigen::Vector3d(0.5 + reach, 0.5 + reach, 0.1)).norm() < 1e-12);
  const auto [lo2, hi2] = box(2);
  CHECK((lo2 - Eigen::Vector3d(0.2, -0.1, 0.05)).norm() < 1e-12);
  CHECK((hi2 - Eigen::Vector3d(0.8, 1.1, 0.15)).norm() < 1e-12);
  // The OBJ frames have them beside them too: the floor once, the slab at each frame.
  CHECK(readObj((dir / "obj/volumes.obj").string()).V.rows() == still.points.rows());
  const TriMesh slab = readObj((dir / "obj/volumes_00002.obj").string());
  CHECK((slab.V.colwise().minCoeff().transpose() - lo2).norm() < 1e-12);
  CHECK((slab.V.colwise().maxCoeff().transpose() - hi2).norm() < 1e-12);
  const std::string pvd = fileBytes(dir / "frames.pvd");
  CHECK(pvd.find("part=\"1\" file=\"volumes.vtu\"") != std::string::npos);
  CHECK(pvd.find("part=\"2\" file=\"frames/volumes_00002.vtu\"") != std::string::npos);
  // `jetshell render DIR --frame 1` draws frame 1 with the slab where it was then.
  CHECK(readPvdFrame((dir / "frames.pvd").string(), 1) ==
        std::vector<std::string>{(dir / "frames/frame_00001.vtu").string(), (dir / "volumes.vtu").string(),
                                 (dir / "frames/volumes_00001.vtu").string()});
  CHECK(fs::exists(dir / "final.png"));
  // A run resumed from its checkpoint draws the same frames.
  resumedBitForBit(scene, "moving_volume", 10);
}

TEST_CASE("run: a static path presses a keyframed ball into a plate, drawn where it is at each level",
          "[contact][statics]") {
  // The ball (r = 2 cm) starts 1 cm above the plate and goes 4 cm down by λ = 1: half its 2 cm half-width per
  // increment allows 1 cm, so the two levels are reached in four increments; frames at λ = 0, 0.5, 1.
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, 0],
    "actors": [{"type": "shell", "name": "plate",
                "shape": {"generator": "rectangle", "width": 0.2, "height": 0.2, "nx": 12, "ny": 12},
                "material": {"youngsModulus": 1e7, "poissonRatio": 0.3, "thickness": 0.001, "volumeDensity": 1000},
                "hasGravity": false, "colliderType": "None",
                "fixed": [{"select": [{"group": "left"}, {"group": "right"}, {"group": "bottom"}, {"group": "top"}]}],
                "probes": [{"name": "centre", "select": {"nearest": [0.1, 0.1, 0]}}]},
               {"type": "sphere", "name": "ball", "center": [0.1, 0.1, 0.03], "radius": 0.02,
                "keyframes": [{"time": 1, "translation": [0, 0, -0.04]}]}],
    "analysis": {"type": "static", "loadSteps": 2},
    "solver": {"threads": 1}})"),
                                    ".");
  CHECK(unsupportedFeatures(scene).empty());
  RunOptions o;
  o.outputDirectory = freshDirectory("static_press").string();
  std::ostringstream log;
  o.log = &log;
  const RunResult r = runScene(scene, o);
  REQUIRE(r.summary.converged);
  const fs::path dir(o.outputDirectory);
  const nlohmann::json summary = readJson(dir / "summary.json");
  CHECK(summary.at("moving_solid_increment").get<double>() == 0.25);
  CHECK(summary.at("load_steps_solved").get<int>() >= 4);
  CHECK(log.str().find("a moving solid: load increments of at most 0.25") != std::string::npos);
  CHECK(log.str().find("force on 'ball' (") != std::string::npos);
  // The plate pushes the ball back up, and not sideways (its press is central).
  const nlohmann::json& force = summary.at("contact_forces").at("ball");
  CHECK(force.at(2).get<double>() > 0.0);
  CHECK(std::abs(force.at(0).get<double>()) < 1e-6 * force.at(2).get<double>());
  // The ball in each frame's volumes file, its centre where the keyframes put it at that level's λ.
  for (int frame = 0; frame <= 2; ++frame) {
    const VtuFrame f = readVtu((dir / "frames" / ("volumes_0000" + std::to_string(frame) + ".vtu")).string());
    const Eigen::Vector3d centre = 0.5 * (f.points.colwise().minCoeff() + f.points.colwise().maxCoeff()).transpose();
    CHECK((centre - Eigen::Vector3d(0.1, 0.1, 0.03 - 0.02 * frame)).norm() < 1e-12);
  }
  // Pressed to the edge of the contact band (5 mm) below the ball's lowest point, 3 cm under the rest plane.
  const double w = summary.at("probes").at("centre").at(2).get<double>();
  CHECK(w < -0.03);
  CHECK(w > -0.0351);
  // probes.csv: the force–indentation curve, one row per level. At λ = 0 the ball is 1 cm above the plate, out of
  // the contact band; the force then grows with the press, and the last row is summary.json's.
  const std::vector<std::string> lines = fileLines(dir / "probes.csv");
  REQUIRE(lines.size() == 4);  // the header, λ = 0, 0.5, 1
  CHECK(lines[0] == "step,time,load_factor,centre_ux,centre_uy,centre_uz,ball_Fx,ball_Fy,ball_Fz");
  std::vector<double> fz;
  for (std::size_t k = 1; k < lines.size(); ++k) fz.push_back(csvNumbers(lines[k]).back());
  CHECK(fz[0] == 0.0);
  CHECK(fz[1] > 0.0);
  CHECK(fz[2] > fz[1]);
  const std::vector<double> last = csvNumbers(lines.back());
  for (int c = 0; c < 3; ++c) CHECK(last[6 + static_cast<std::size_t>(c)] == force.at(c).get<double>());
}

TEST_CASE("run: a bar with rounded edges is pressed into a sheet and turned in it along a static path",
          "[contact][statics]") {
  // examples/bar_turned_in_sheet.json on a coarser sheet. With sharp edges this path ends with 20 faces pushed
  // through (4 jumps) and fails at lambda = 0.978; rounded by 1 cm it is followed level by level.
  const fs::path example = fs::path(JETSHELL_SOURCE_DIR) / "examples" / "bar_turned_in_sheet.json";
  nlohmann::json j = nlohmann::json::parse(fileBytes(example), nullptr, true, true);
  REQUIRE(j["actors"][1]["edgeRadius"] == 0.01);
  j["actors"][0]["shape"]["nx"] = 12;
  j["actors"][0]["shape"]["ny"] = 12;
  j["solver"] = {{"threads", 1}};
  const Scene scene = sceneFromJson(j, ".");
  RunOptions o;
  o.outputDirectory = freshDirectory("bar_turned").string();
  o.pictures = false;
  const RunResult r = runScene(scene, o);
  CHECK(r.summary.converged);
  const nlohmann::json summary = readJson(fs::path(o.outputDirectory) / "summary.json");
  CHECK(summary.at("final_load_factor").get<double>() == 1.0);
  CHECK(summary.at("inverted_faces").get<int>() == 0);
  CHECK(summary.at("load_jumps").empty());
  // The sheet holds the bar up: the force on it points up, and the sheet's centre hangs below the bar's bottom.
  const nlohmann::json& force = summary.at("contact_forces").at("bar");
  CHECK(force.at(2).get<double>() > 0.0);
  CHECK(std::hypot(force.at(0).get<double>(), force.at(1).get<double>()) < 1e-6 * force.at(2).get<double>());
  // The bar's bottom is at z = -0.07 at the end; the sheet sits inside the 5 mm band below it.
  CHECK(summary.at("probes").at("centre").at(2).get<double>() < -0.07);
  CHECK(summary.at("probes").at("centre").at(2).get<double>() > -0.0751);
}

TEST_CASE("run: probes.csv records the force a floor bears at every step, at rest the sheet's weight",
          "[contact][checkpoint]") {
  // A free 0.2 m square sheet (h = 1 mm, ρ = 1000: 0.392 N) laid 6 mm above a floor, just outside the 5 mm
  // contact band, falls onto it and settles under its weight; damped by its mass, it is at rest within the run.
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{"type": "shell", "name": "sheet",
                "shape": {"generator": "rectangle", "width": 0.2, "height": 0.2, "nx": 4, "ny": 4},
                "worldFromLocalTransform": {"translation": [0, 0, 0.006]},
                "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.001, "volumeDensity": 1000,
                             "massDampingCoefficient": 20},
                "colliderType": "None"},
               {"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 0, 1]}],
    "analysis": {"type": "dynamic", "timeStep": 0.02, "duration": 0.4},
    "solver": {"threads": 1}})"),
                                    ".");
  const RunOptions o = resumedBitForBit(scene, "resting", 20);
  const fs::path dir(o.outputDirectory);
  const std::vector<std::string> lines = fileLines(dir / "probes.csv");
  REQUIRE(lines.size() == 22);  // the header, t = 0 and 20 steps
  CHECK(lines[0] == "step,time,load_factor,floor_Fx,floor_Fy,floor_Fz");
  const double weight = 0.2 * 0.2 * 0.001 * 1000 * 9.81;
  CHECK(csvNumbers(lines[1]) == std::vector<double>{0, 0, 1, 0, 0, 0});  // out of the band at t = 0
  const std::vector<double> last = csvNumbers(lines.back());
  REQUIRE(last.size() == 6);
  CHECK(last[5] == Approx(-weight).epsilon(1e-4));  // the floor is pushed down by the sheet's weight
  CHECK(std::abs(last[3]) < 1e-9 * weight);
  CHECK(std::abs(last[4]) < 1e-9 * weight);
  const nlohmann::json summary = readJson(dir / "summary.json");
  CHECK(summary.at("contact_forces").at("floor").at(2).get<double>() == last[5]);
}

TEST_CASE("run: a dynamic run's rows record its ramped load factor, the first 0 and the last the ramp's at the end") {
  // The loads ramp over twice the run: the last state is at half load. Rows 0 and the last said 1.
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{"type": "shell", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 3, "ny": 3},
                "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.0005, "volumeDensity": 300},
                "colliderType": "None", "fixed": [{"select": [{"nearest": [0, 1, 0]}, {"nearest": [1, 1, 0]}]}],
                "probes": [{"name": "corner", "select": {"nearest": [1, 0, 0]}}]}],
    "analysis": {"type": "dynamic", "timeStep": 0.02, "duration": 0.1, "loadRampTime": 0.2},
    "solver": {"threads": 1}})"),
                                    ".");
  RunOptions o;
  o.pictures = false;
  o.outputDirectory = freshDirectory("ramped").string();
  REQUIRE(runScene(scene, o).summary.converged);
  const std::vector<std::string> lines = fileLines(fs::path(o.outputDirectory) / "probes.csv");
  REQUIRE(lines.size() == 7);  // the header, t = 0 and 5 steps
  for (std::size_t k = 1; k < lines.size(); ++k) {
    const std::vector<double> row = csvNumbers(lines[k]);
    INFO(lines[k]);
    CHECK(row[2] == Approx(row[1] / 0.2));
  }
  CHECK(csvNumbers(lines[1])[2] == 0.0);
  const double last = csvNumbers(lines.back())[2];
  CHECK(last == Approx(0.5));
  CHECK(readJson(fs::path(o.outputDirectory) / "summary.json").at("final_load_factor").get<double>() == last);
}

TEST_CASE("run: a checkpoint file is read only if it is a bounded regular file of shallow CBOR", "[checkpoint]") {
  const fs::path dir = freshDirectory("hostile_checkpoint");
  fs::create_directories(dir);
  const std::string path = checkpointPath(dir.string());
  CHECK_THROWS_WITH(readCheckpoint(dir.string()), path + ": no checkpoint to resume from (run with "
                                                         "--checkpoint-every N first)");
  // 2 MB of nested one-element arrays: the CBOR parser recursed once per level and overflowed the stack.
  writeFileAtomically(path, std::string(2000000, '\x81') + std::string(1, '\0'));
  CHECK_THROWS_WITH(readCheckpoint(dir.string()), path + ": not a jetshell checkpoint");
  // An array that declares 2^64 - 1 elements.
  writeFileAtomically(path, "\x9b\xff\xff\xff\xff\xff\xff\xff\xff");
  CHECK_THROWS_WITH(readCheckpoint(dir.string()), path + ": not a jetshell checkpoint");
  // /dev/zero under the checkpoint's name was read without end.
  fs::remove(path);
  fs::create_symlink("/dev/zero", path);
  CHECK_THROWS_WITH(readCheckpoint(dir.string()),
                    path + ": not a regular file (a directory, FIFO or device): cannot read it as a checkpoint");
  fs::remove(path);
  writeCheckpoint(dir.string(), {{"state", {1, 2, 3}}});
  CHECK(readCheckpoint(dir.string())["state"] == nlohmann::json({1, 2, 3}));
}

TEST_CASE("run: a static run that reaches no load step under the weight points to dynamic relaxation") {
  // A 1 m cantilever 1e-5 m thick (E 1e9 Pa): at any load it swings from flat to hanging (STABILITY.md).
  auto sceneFor = [](double thickness) {
    const nlohmann::json j = {
        {"gravity", {0.0, 0.0, -9.81}},
        {"actors",
         {{{"type", "shell"},
           {"name", "sheet"},
           {"shape", {{"generator", "rectangle"}, {"width", 1.0}, {"height", 1.0}, {"nx", 6}, {"ny", 6}}},
           {"material", {{"youngsModulus", 1e9}, {"poissonRatio", 0.3}, {"thickness", thickness}, {"volumeDensity", 1000.0}}},
           {"fixed", {{{"select", {{"group", "left"}}}, {"clampRotation", true}}}}}}},
        {"analysis", {{"type", "static"}, {"loadSteps", 4}}},
        {"solver", {{"threads", 1}}},
        {"outputs", {{"png", false}, {"plots", false}}}};
    return sceneFromJson(j, ".");
  };
  RunOptions o;
  o.pictures = false;
  o.outputDirectory = freshDirectory("thin_static").string();
  const RunResult thin = runScene(sceneFor(1e-5), o);
  CHECK(!thin.summary.converged);
  CHECK(thin.summary.termination.find("dynamicRelaxation") != std::string::npos);
  o.outputDirectory = freshDirectory("thick_static").string();
  const RunResult thick = runScene(sceneFor(1e-2), o);
  CHECK(thick.summary.converged);
  CHECK(thick.summary.termination.find("dynamicRelaxation") == std::string::npos);
}

TEST_CASE("run: a column past its buckling load is reported unstable by load control, and relaxation leaves it") {
  // examples/euler_column.json (a straight strip at 1.6 times its Euler load), by load control without branch
  // switching and by a relaxation cut short: the static run ends on the straight saddle and says so; the
  // relaxation's step budget runs out after it stepped off the saddle, and its termination says that once. (With
  // branch switching, the default, load control buckles: tests/validation/scene_accuracy_test.cpp.)
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/euler_column.json");
  scene.outputs.vtu = false;
  RunOptions o;
  o.pictures = false;
  Scene statics = scene;
  statics.analysis.type = AnalysisType::Static;
  statics.analysis.loadSteps = 10;
  statics.analysis.branchSwitching = false;
  o.outputDirectory = freshDirectory("column_static").string();
  const RunResult s = runScene(statics, o);
  CHECK(s.summary.converged);
  CHECK(s.summary.extra.at("branch_switches").empty());
  CHECK(s.summary.extra.at("unstable_equilibria").get<int>() > 0);
  REQUIRE(!s.warnings.empty());
  CHECK(s.warnings.back().find("dynamicRelaxation") != std::string::npos);
  Scene relaxation = scene;
  relaxation.analysis.maxSteps = 20;
  o.outputDirectory = freshDirectory("column_relaxation").string();
  const RunResult r = runScene(relaxation, o);
  CHECK(!r.summary.converged);
  CHECK(r.summary.extra.at("saddle_escapes").get<int>() == 1);
  CHECK(r.summary.termination.rfind("maxSteps (20) reached", 0) == 0);
  CHECK(r.summary.termination.find("after") == std::string::npos);  // the run's report adds the counts
}

TEST_CASE("run: a snap-through that load control jumps over is reported") {
  // examples/hinged_roof_snap_through.json by load control in 10 steps: the step from λ = 0.7 to 0.8 passes the limit
  // point (λ 0.735) and lands on the inverted branch; arc length (the example's own control) traces it.
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/hinged_roof_snap_through.json");
  scene.outputs.vtu = false;
  scene.analysis.pathControl = PathControlSettings{};
  RunOptions o;
  o.pictures = false;
  o.outputDirectory = freshDirectory("roof_load_control").string();
  const RunResult r = runScene(scene, o);
  REQUIRE(r.summary.converged);
  const nlohmann::json& jumps = r.summary.extra.at("load_jumps");
  REQUIRE(jumps.size() == 1);
  CHECK(jumps[0].at("load_factor_before").get<double>() < 0.735);
  CHECK(jumps[0].at("load_factor_after").get<double>() > 0.735);
  CHECK(jumps[0].at("energy_released").get<double>() > 0.0);
  CHECK(std::any_of(r.warnings.begin(), r.warnings.end(),
                    [](const std::string& w) { return w.find("changed abruptly") != std::string::npos; }));
}

TEST_CASE("run: the membrane's staged evaluator gives the per-face run's answer", "[staged]") {
  // A static strip with a mirrored clamp and moment-free free edges (the scene defaults), to the elastica's tip.
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/cantilever_strip.json");
  auto tip = [&](const std::string& evaluator) {
    scene.solver.evaluator = evaluator;
    RunOptions o;
    o.pictures = false;
    o.outputDirectory = freshDirectory("evaluator_" + evaluator).string();
    const RunResult r = runScene(scene, o);
    REQUIRE(r.summary.converged);
    const nlohmann::json s = readJson(fs::path(o.outputDirectory) / "summary.json");
    return s.at("probes").begin()->get<std::vector<double>>();
  };
  const std::vector<double> hand = tip("perFace"), staged = tip("staged");
  REQUIRE(hand.size() == 3);
  for (int c = 0; c < 3; ++c) CHECK(staged[c] == Approx(hand[c]).epsilon(1e-8).margin(1e-12));
}

TEST_CASE("run: the fallback's bending Hessian reaches Newton, exact unless the scene asks", "[scene]") {
  SolverSettings s;
  CHECK(newtonOptionsFor(s, 4).fallbackBendingHessian == HessianModel::Exact);
  s.fallbackBendingHessian = "gaussNewton";
  CHECK(newtonOptionsFor(s, 4).fallbackBendingHessian == HessianModel::GaussNewton);
  CHECK_THROWS_AS(hessianModelFromString("gauss"), InputError);
}

TEST_CASE("run: a massless actor beside a massive one is judged by the residual, not passed unweighed") {
  // An actor of zero density takes a load; the time-discretization rule weighs residuals by mass, so its
  // vertices once went unjudged: every step "converged" after 0 Newton iterations, the load unbalanced
  // (residual 1e6 times its tolerance).
  const Scene scene = sceneFromJson(nlohmann::json::parse(R"({
    "gravity": [0, 0, 0],
    "actors": [
      {"type": "shell", "name": "light", "colliderType": "None",
       "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 2, "ny": 2},
       "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.01, "volumeDensity": 0},
       "fixed": [{"select": {"group": "left"}}],
       "loads": [{"select": {"group": "right"}, "force": [0, 0, 1]}]},
      {"type": "shell", "name": "heavy", "colliderType": "None",
       "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 2, "ny": 2},
       "worldFromLocalTransform": {"translation": [0, 3, 0]},
       "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.01, "volumeDensity": 100},
       "fixed": [{"select": {"group": "left"}}]}],
    "analysis": {"type": "dynamic", "timeStep": 0.01, "duration": 0.03},
    "solver": {"threads": 1}})"),
                                    ".");
  RunOptions o;
  o.pictures = false;
  o.outputDirectory = freshDirectory("massless_actor").string();
  const RunResult r = runScene(scene, o);
  const double worst = r.summary.extra.value("worst_residual_over_tolerance", 0.0);
  INFO("converged " << r.summary.converged << ", worst residual / tolerance " << worst);
  CHECK_FALSE((r.summary.converged && worst > 1e3));
}
