// Hostile scene input: sizes and counts beyond the bounds of core/input_limits.h, integers too large, deep
// nesting, huge strings, wrong types, non-positive-definite materials, special files. Each is rejected where it
// enters, before anything is allocated for it, with one line naming the field and the bound.
#include "core/input_limits.h"
#include "core/mesh.h"
#include "solvers/statics.h"
#include "tools/output/volume_meshes.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"
#include "tools/scene/scene_problem.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

using namespace jetshell;
using Json = nlohmann::json;

namespace {

Json boundsScene() {
  return Json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{
      "type": "shell", "name": "strip",
      "shape": {"generator": "rectangle", "width": 4, "height": 1, "nx": 4, "ny": 2},
      "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.01, "volumeDensity": 100},
      "fixed": [{"select": {"group": "left"}}],
      "probes": [{"name": "tip", "select": {"nearest": [4, 0.5, 0]}}]
    }],
    "analysis": {"type": "static", "loadSteps": 2}
  })");
}

/// Adds `count` small spheres (volume actors) to a scene.
void addSpheres(Json& scene, int count) {
  for (int k = 0; k < count; ++k)
    scene["actors"].push_back(
        {{"type", "sphere"}, {"name", "ball" + std::to_string(k)}, {"center", {k, 5, 5}}, {"radius", 0.1}});
}

std::string boundsErrorOf(const Json& scene) {
  try {
    buildSceneModel(sceneFromJson(scene, "."));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

template <typename Edit>
std::string boundsErrorAfter(Edit edit) {
  Json s = boundsScene();
  edit(s);
  return boundsErrorOf(s);
}

std::string boundsErrorOfText(const std::string& text) {
  try {
    buildSceneModel(sceneFromJson(json::parse(text, "s.json"), "."));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string boundsFileErrorOf(const std::string& path) {
  try {
    loadSceneFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

struct BoundsLimitOverride {
  InputLimits saved = inputLimits();
  ~BoundsLimitOverride() { inputLimits() = saved; }
};

Json rectangle(Json nx, Json ny) {
  return {{"generator", "rectangle"}, {"width", 1}, {"height", 1}, {"nx", nx}, {"ny", ny}};
}

std::string boundsTempPath(const std::string& name) {
  const auto dir = test::scratchDirectory("scene_bounds");
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

}  // namespace

TEST_CASE("scene bounds: generator resolutions are bounded before anything is allocated", "[scene][hostile]") {
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["shape"] = rectangle(65535, 65535); }) ==
        "/actors/0/shape: rectangle grid: the resolution gives 4294967296 vertices and 8589672450 faces, too many "
        "(at most 4000000 vertices and 8000000 faces)");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["shape"] = rectangle(2147483647, 1); }) ==
        "/actors/0/shape/nx = 2147483647: too large (at most 4000000)");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["shape"] = rectangle(1e12, 1); }) ==
        "/actors/0/shape/nx = 1000000000000.0: too large (at most 4000000)");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["shape"] = rectangle(-3, 1); }) == "/actors/0/shape/nx = -3: must be >= 1");
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"generator", "slitAnnulus"}, {"innerRadius", 1}, {"outerRadius", 2},
                                     {"rings", 3000}, {"nodesPerRing", 3000}};
        }) == "/actors/0/shape: slit annulus: the resolution gives 9000000 vertices and 17988002 faces, too many (at "
              "most 4000000 vertices and 8000000 faces)");
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"generator", "cylinder"}, {"radius", 1}, {"length", 2}, {"nAround", 4000000},
                                     {"nAlong", 4000000}};
        }).rfind("/actors/0/shape: cylinder: the resolution gives 16000008000001 vertices", 0) == 0);
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"generator", "hemisphere"}, {"radius", 1}, {"rings", 4000000}, {"segments", 3}};
        }).rfind("/actors/0/shape: hemisphere: the resolution gives 16000005 vertices", 0) == 0);
}

TEST_CASE("scene bounds: selections, steps, iterations and threads", "[scene][hostile]") {
  auto select = [](Json selector) {
    return boundsErrorAfter([&](Json& s) { s["actors"][0]["fixed"][0]["select"] = selector; });
  };
  CHECK(select({{"range", {0, 2000000000}}}) == "/actors/0/fixed/0/select/range/1 = 2000000000: too large (at most 4000000)");
  CHECK(select({{"range", {0, 5, 1e10}}}) == "/actors/0/fixed/0/select/range/2 = 10000000000.0: too large (at most 2147483647)");
  CHECK(select({{"range", {1, 5, 2147483647}}}) == "no error");  // start + step would overflow an int
  CHECK(select({{"range", {-1, 5}}}) == "/actors/0/fixed/0/select/range/0 = -1: must be >= 0");
  CHECK(select({{"range", {0, 5, 0}}}) == "/actors/0/fixed/0/select/range/2 = 0: must be >= 1");
  CHECK(select({{"range", {0, 100}}}) == "/actors/0/fixed/0/select/indices/15 = 15: out of range [0, 15)");
  CHECK(select({{"indices", {0, 3000000000.0}}}) ==
        "/actors/0/fixed/0/select/indices/1 = 3000000000.0: too large (at most 2147483647)");
  CHECK(boundsErrorAfter([](Json& s) { s["analysis"] = {{"type", "dynamic"}, {"timeStep", 1e-300}, {"duration", 1}}; }) ==
        "/analysis/timeStep = 1e-300: 1e+300 steps over the duration 1 s, too many (at most 10000000)");
  CHECK(boundsErrorAfter([](Json& s) { s["analysis"] = {{"type", "dynamic"}, {"timeStep", 1e-7}, {"duration", 10}}; }) ==
        "/analysis/timeStep = 1e-07: 1e+08 steps over the duration 10 s, too many (at most 10000000)");
  CHECK(boundsErrorAfter([](Json& s) { s["analysis"]["loadSteps"] = 1e12; }) ==
        "/analysis/loadSteps = 1000000000000.0: too large (at most 10000)");
  // Levels finer than the statics path's smallest increment are refused here, naming the scene's field.
  CHECK(boundsErrorAfter([](Json& s) { s["analysis"]["loadSteps"] = 10001; }) ==
        "/analysis/loadSteps = 10001: too large (at most 10000)");
  CHECK(boundsErrorAfter([](Json& s) { s["analysis"]["loadSteps"] = 10000; }) == "no error");
  CHECK(1.0 / LoadSteppingOptions{}.minIncrement == static_cast<double>(inputLimits().maxLoadLevels));
  CHECK(boundsErrorAfter([](Json& s) { s["analysis"] = {{"type", "dynamicRelaxation"}, {"timeStep", 0.1}, {"maxSteps", 1e8}}; }) ==
        "/analysis/maxSteps = 100000000.0: too large (at most 10000000)");
  CHECK(boundsErrorAfter([](Json& s) { s["solver"] = {{"threads", 1000000}}; }) ==
        "/solver/threads = 1000000: too large (at most 256)");
  CHECK(boundsErrorAfter([](Json& s) { s["solver"] = {{"threads", -1}}; }) == "/solver/threads = -1: must be >= 0");
  CHECK(boundsErrorAfter([](Json& s) { s["solver"] = {{"maxIterations", 1e9}}; }) ==
        "/solver/maxIterations = 1000000000.0: too large (at most 1000000)");
  CHECK(boundsErrorAfter([](Json& s) { s["outputs"] = {{"frameStride", 1e8}}; }) ==
        "/outputs/frameStride = 100000000.0: too large (at most 10000000)");
}

TEST_CASE("scene bounds: the C++ scene API checks the same bounds", "[scene][hostile]") {
  Scene scene = sceneFromJson(boundsScene(), ".");
  scene.solver.threads = 1000000;
  CHECK_THROWS_WITH(validate(scene), "/solver/threads = 1000000: too large (at most 256)");
  scene.solver.threads = 0;
  scene.analysis.type = AnalysisType::Dynamic;
  scene.analysis.timeStep = 1e-300;
  CHECK_THROWS_WITH(validate(scene), "/analysis/timeStep = 1e-300: 1e+300 steps over the duration 1 s, too many (at "
                                     "most 10000000)");
  scene.analysis.type = AnalysisType::Static;
  scene.analysis.loadSteps = 2000000000;
  CHECK_THROWS_WITH(validate(scene), "/analysis/loadSteps = 2000000000: too large (at most 10000)");
  scene.analysis.loadSteps = 1;
  BoundsLimitOverride restore;
  inputLimits().maxVertices = 20;  // the strip has 15 vertices: one actor fits, two do not
  Json two = boundsScene();
  two["actors"].push_back(two["actors"][0]);
  two["actors"][1]["name"] = "second";
  two["actors"][1]["probes"][0]["name"] = "tip2";
  // Refused at the second actor, before a third could be generated.
  CHECK(boundsErrorOf(two) == "/actors/1: vertices of all shell actors = 30: too large (at most 20)");
  Scene api = sceneFromJson(boundsScene(), ".");
  api.shells.push_back(api.shells[0]);
  api.shells[1].name = "second";
  CHECK_THROWS_WITH(validate(api), "scene: vertices of all shell actors = 30: too large (at most 20)");
}

TEST_CASE("scene bounds: conditions, probes, selected vertices, actors and contact pairs are bounded",
          "[scene][hostile]") {
  BoundsLimitOverride restore;
  // 20,000 conditions selecting all of a 40,401-vertex mesh took 181 s of `run --check`; 100,000 probes 17 s
  // (each name compared with every earlier one); 20,000 spheres over a 121-vertex cloth 1.2 GB.
  inputLimits().maxConditions = 2;
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["probes"].push_back({{"name", "b"}, {"select", {{"all", true}}}});
                                       s["actors"][0]["probes"].push_back({{"name", "c"}, {"select", {{"all", true}}}});
        }) == "/actors/0/probes/2: probes in the scene = 3: too large (at most 2)");
  CHECK(boundsErrorAfter([](Json& s) {
          for (int k = 0; k < 2; ++k) s["actors"][0]["fixed"].push_back({{"select", {{"all", true}}}});
        }) == "/actors/0/fixed/2: fixed conditions in the scene = 3: too large (at most 2)");
  CHECK(boundsErrorAfter([](Json& s) {
          for (int k = 0; k < 3; ++k)
            s["actors"][0]["loads"].push_back({{"select", {{"all", true}}}, {"force", {0, 0, 1}}});
        }) == "/actors/0/loads/2: loads in the scene = 3: too large (at most 2)");
  Scene api = sceneFromJson(boundsScene(), ".");
  api.probes.resize(3, api.probes[0]);
  CHECK_THROWS_WITH(validate(api), "scene: probes = 3: too large (at most 2)");
  inputLimits() = restore.saved;
  // The strip has 15 vertices: its "left" group (3) and one load on all of them (15) select 18.
  inputLimits().maxSelectedVertices = 17;
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["loads"].push_back({{"select", {{"all", true}}}, {"force", {0, 0, 1}}});
        }) == "/actors/0/fixed/0/select: the scene's fixed conditions and loads select more than 17 vertices in all");
  inputLimits() = restore.saved;
  // Actors: 12 large generated shells in a 1 KB scene took 7.7 s and 948 MB before the total was checked (300
  // would have needed 24 GB); the totals are now checked after each actor.
  inputLimits().maxActors = 2;
  Json three = boundsScene();
  addSpheres(three, 2);
  CHECK(boundsErrorOf(three) == "/actors/2: actors = 3: too large (at most 2)");
  inputLimits() = restore.saved;
  // Each shell-volume pair has contact terms of its own (1,000 x 1,000 pairs of four-vertex shells and spheres
  // took 4.1 GB and 36 s for two steps).
  inputLimits().maxContactPairs = 3;
  Json pairs = boundsScene();
  pairs["actors"].push_back(pairs["actors"][0]);
  pairs["actors"][1]["name"] = "second";
  pairs["actors"][1]["probes"][0]["name"] = "tip2";
  addSpheres(pairs, 2);
  CHECK(boundsErrorOf(pairs) == "/actors/3: 2 shell actors x 2 volume actors = 4 contact pairs, each with terms of "
                                "its own: at most 3 (merge shells into one mesh, or use fewer volume actors)");
  inputLimits() = restore.saved;
  // Each volume actor samples every shell vertex: one shell of 15 vertices and four spheres, 4 x 15 = 60.
  inputLimits().maxVolumeActorVertices = 59;
  Json balls = boundsScene();
  addSpheres(balls, 4);
  CHECK(boundsErrorOf(balls) == "/actors/4: 4 volume actors over 15 shell vertices: each volume actor samples every "
                                "shell vertex, so volume actors x vertices must be at most 59 (use fewer volume "
                                "actors)");
  inputLimits() = restore.saved;
  // Shell actors no longer multiply: each holds its own vertices (3,000 four-vertex actors took 866 MB for
  // `run --check` when each held every position of the scene). 40 actors of 15 vertices build, and each actor's
  // mesh holds only its own.
  Json many = boundsScene();
  for (int k = 1; k < 40; ++k) {
    Json a = many["actors"][0];
    a["name"] = "strip" + std::to_string(k);
    a.erase("probes");
    a["worldFromLocalTransform"] = {{"translation", {0, 2 * k, 0}}};
    many["actors"].push_back(a);
  }
  const SceneModel model = buildSceneModel(sceneFromJson(many, "."));
  REQUIRE(model.actors.size() == 40);
  CHECK(model.numVertices() == 600);
  for (const ActorBlock& b : model.actors) CHECK(b.mesh.numVertices() == 15);
}

TEST_CASE("scene bounds: the SDF grids of a scene are bounded together, and a file named twice is held once",
          "[scene][hostile]") {
  BoundsLimitOverride restore;
  // The grid files of a scene are bounded together, each counted once however many actors name it.
  const std::filesystem::path dir = test::scratchDirectory("sdf_total");
  for (const char* name : {"g.sdf", "h.sdf", "i.sdf"})
    std::ofstream(dir / name) << "dims 2 2 2\norigin 0 0 0\nspacing 1\n-1 -1 -1 -1 1 1 1 1\n";
  inputLimits().maxSdfSamples = 16;  // two grids of 8 samples fit, three do not
  Json s = boundsScene();
  for (const char* name : {"g.sdf", "h.sdf", "i.sdf"})
    s["actors"].push_back({{"type", "sdfGrid"}, {"name", name}, {"file", name}, {"center", {0, 0, -5}}});
  std::string error = "no error";
  try {
    sceneFromJson(s, dir.string());
  } catch (const InputError& e) {
    error = e.what();
  }
  CHECK(error == "/actors/3: samples of all SDF grids = 24: too large (at most 16)");
  // One file named by three actors (by a second name for it too) counts once, and its shape is read and held once.
  s["actors"][2]["file"] = "g.sdf";
  s["actors"][3]["file"] = "./g.sdf";
  const Scene scene = sceneFromJson(s, dir.string());
  CHECK(sceneTotals(scene).sdfSamples == 8);
  // Two files, one of them named twice: 16 samples, within the bound.
  Json two = s;
  two["actors"][3]["file"] = "h.sdf";
  CHECK(sceneTotals(sceneFromJson(two, dir.string())).sdfSamples == 16);
  // The run counts the grids it reads as well: a scene whose actors name other files than the reader counted (one
  // built through the API, or files replaced since the scene was read) is bounded all the same.
  Scene renamed = sceneFromJson(s, dir.string());
  for (VolumeActorParams& v : renamed.volumes) {  // as the API builds them: no counts, no shapes
    v.sdfSamples = 0;
    v.sdfShape = nullptr;
  }
  renamed.volumes[1].sdfFile = (dir / "h.sdf").string();
  renamed.volumes[2].sdfFile = (dir / "i.sdf").string();
  CHECK_THROWS_WITH(shellProblemFromScene(renamed, buildSceneModel(renamed)),
                    Catch::Contains("i.sdf: samples of all SDF grids of the scene = 24: too large (at most 16)"));
  inputLimits() = restore.saved;
  const ShellProblem problem = shellProblemFromScene(scene, buildSceneModel(scene));
  REQUIRE(problem.volumes.size() == 3);
  CHECK(&problem.volumes[0].collider->shape() == &problem.volumes[1].collider->shape());
  CHECK(&problem.volumes[0].collider->shape() == &problem.volumes[2].collider->shape());
  CHECK(problem.volumes[2].collider->name() == "i.sdf");
  // The run holds the reader's shape and draws the reader's box: nothing reads the file again (a run with a grid of
  // 4 million samples read it three times, 1.46 s against 0.49 s now), nor sees another if it was replaced since.
  CHECK(&problem.volumes[0].collider->shape() == scene.volumes[0].sdfShape.get());
  std::filesystem::remove(dir / "g.sdf");
  CHECK(shellProblemFromScene(scene, buildSceneModel(scene)).volumes.size() == 3);
  const TriMesh drawn = volumeSurface(scene.volumes[0], 1.0, Eigen::Vector3d::Zero());
  CHECK((drawn.V.colwise().minCoeff() - Eigen::RowVector3d(0, 0, -5)).norm() < 1e-15);
  CHECK((drawn.V.colwise().maxCoeff() - Eigen::RowVector3d(1, 1, -4)).norm() < 1e-15);
}

TEST_CASE("scene bounds: inline meshes and index lists are bounded", "[scene][hostile]") {
  BoundsLimitOverride restore;
  inputLimits().maxVertices = 2;
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"faces", {{0, 1, 2}}}};
        }) == "/actors/0/shape/vertices (count) = 3: too large (at most 2)");
  inputLimits().maxVertices = 100;
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["fixed"][0]["select"] = {{"indices", Json(std::vector<int>(101, 0))}}; }) ==
        "/actors/0/fixed/0/select/indices (count) = 101: too large (at most 100)");
}

TEST_CASE("scene bounds: deep nesting, huge strings and keys, huge numbers, wrong types", "[scene][hostile]") {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  CHECK(boundsErrorOfText(deep) == "s.json: nested too deeply (at most 64 levels of arrays and objects)");
  CHECK(boundsErrorOfText("{\"description\": " + std::string(70, '[') + std::string(70, ']') + "}") ==
        "s.json: nested too deeply (at most 64 levels of arrays and objects)");
  CHECK(boundsErrorAfter([](Json& s) { s["description"] = std::string(5000, 'x'); }) ==
        "/description: a string of 5000 bytes is too long (at most 4096)");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["probes"][0]["name"] = std::string(100000, 'p'); }) ==
        "/actors/0/probes/0/name: a string of 100000 bytes is too long (at most 4096)");
  CHECK(boundsErrorOfText("{\"" + std::string(10000, 'k') + "\": 1}") == "s.json: a key of 10000 bytes is too long (at most 4096)");
  CHECK(boundsErrorOfText(R"({"gravity": [0, 0, -1e400]})") == "s.json:1:20: invalid JSON: number overflow parsing '-1e400'");
  // 1e308 is finite, but the first steps' energies overflowed and the run failed in the solver, naming no field.
  CHECK(boundsErrorAfter([](Json& s) { s["gravity"] = {0, 0, 1e308}; }) ==
        "/gravity = [0, 0, 1e+308]: too large (norm at most 1e+06)");
  CHECK(boundsErrorAfter([](Json& s) { s["gravity"] = {0, 0, -1e6}; }) == "no error");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"] = "shell"; }) == "/actors: expected an array, got a string");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0] = 7; }) == "/actors/0: expected an object (an actor), got a number");
  CHECK(boundsErrorAfter([](Json& s) { s["analysis"] = Json::array(); }) == "/analysis: expected an object (the analysis), got an array");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["hasGravity"] = 1; }) == "/actors/0/hasGravity: expected true or false, got a number");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["name"] = nullptr; }) == "/actors/0/name: expected a string, got null");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["shape"]["nx"] = "8"; }) == "/actors/0/shape/nx: expected an integer, got a string");
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["shape"]["nx"] = true; }) == "/actors/0/shape/nx: expected an integer, got a boolean");
  CHECK(boundsErrorOfText("[1, 2]") == "(root): expected an object (a scene), got an array");
  CHECK(boundsErrorOfText("\"just a string\"") == "(root): expected an object (a scene), got a string");
}

TEST_CASE("scene bounds: materials must have positive-definite energies", "[scene][hostile]") {
  auto material = [](Json m) { return boundsErrorAfter([&](Json& s) { s["actors"][0]["material"] = m; }); };
  CHECK(material({{"membraneLambda", -100}, {"membraneMu", 0}}) == "/actors/0/material/membraneMu = 0: must be finite and > 0");
  CHECK(material({{"membraneLambda", -500}, {"membraneMu", 400}}) ==
        "/actors/0/material: material.membraneLambda = -500: must satisfy membraneLambda + membraneMu > 0");
  CHECK(material({{"bendingAlpha", -6e-5}, {"bendingBeta", 1e-4}}) ==
        "/actors/0/material: material.bendingAlpha = -6e-05: must satisfy 2 bendingAlpha + bendingBeta > 0");
  CHECK(material({{"bendingBeta", 0}}) == "/actors/0/material/bendingBeta = 0: must be finite and > 0");
  CHECK(material({{"membraneLambda", -399}, {"bendingAlpha", -4.9e-5}, {"bendingBeta", 1e-4}}) == "no error");
}

TEST_CASE("scene bounds: only regular scene files of bounded size are read", "[scene][hostile]") {
  CHECK(boundsFileErrorOf("/dev/zero") ==
        "/dev/zero: not a regular file (a directory, FIFO or device): cannot read it as a scene file");
  const std::string fifo = boundsTempPath("scene.fifo");
  std::filesystem::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(boundsFileErrorOf(fifo) == fifo + ": not a regular file (a directory, FIFO or device): cannot read it as a scene file");
  std::filesystem::remove(fifo);
  const std::string big = boundsTempPath("big.json");
  std::ofstream(big) << boundsScene().dump();
  BoundsLimitOverride restore;
  inputLimits().maxJsonBytes = 100;
  CHECK(boundsFileErrorOf(big).rfind(big + ": scene file of ", 0) == 0);
  CHECK(boundsFileErrorOf(big).find("bytes is too large (at most 100)") != std::string::npos);
  std::filesystem::remove(big);
}

TEST_CASE("scene bounds: a rest mesh folded flat or with a reversed duplicate face names the faces", "[scene][hostile]") {
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"faces", {{0, 1, 2}, {0, 2, 1}}}};
        }) == "/actors/0/shape: mesh: face 1 (0, 2, 1) is face 0 (0, 1, 2) reversed (two faces on the same three vertices)");
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.2, 0}}},
                                     {"faces", {{0, 1, 2}, {0, 2, 3}}}};
        }) == "/actors/0/shape: mesh: face 1 (0, 2, 3) is folded flat onto face 0 (0, 1, 2) across the edge between "
              "vertices 0 and 2 (normals 180.000 degrees apart, at most 179.9: the rest curvature is undefined there)");
}

TEST_CASE("scene bounds: directions with huge or tiny components keep their direction, a tiny radius is refused",
          "[scene][hostile]") {
  // A plane's normal and a rotation's axis are directions: [0, 1e308, 1e308] overflowed the norm and the floor
  // came out with a broken rotation, reported against worldFromLocalTransform instead of the normal.
  auto withFloor = [](const Json& normal) {
    return [normal](Json& s) {
      s["actors"].push_back({{"type", "plane"}, {"name", "floor"}, {"point", {0, 0, -1}}, {"normal", normal}});
    };
  };
  CHECK(boundsErrorAfter(withFloor({0, 1e308, 1e308})) == "no error");
  CHECK(boundsErrorAfter(withFloor({0, 1e-200, 1e-200})) == "no error");
  CHECK(boundsErrorAfter(withFloor({0, 0, 0})) == "/actors/1/normal = [0, 0, 0]: must be a non-zero vector");
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["worldFromLocalTransform"] = {{"rotation", {{"axis", {1e-200, 1e-200, 0}}, {"degrees", 30}}}};
        }) == "no error");
  // The broad phase's cells are 2r wide: a radius of 1e-300 m made every coordinate "huge" there, with no field.
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["pointCloudCollider"] = {{"radius", 1e-300}}; }) ==
        "/actors/0/pointCloudCollider/radius = 1e-300: too small (at least 1e-6 m: the broad phase's cells are this "
        "wide)");
}

TEST_CASE("scene bounds: shape lengths are metres, at most 1e6, and \"scale\" converts a mesh in other units",
          "[scene][hostile]") {
  // Generators' lengths: a 1e308 m rectangle once met the reader as a non-finite vertex coordinate.
  CHECK(boundsErrorAfter([](Json& s) { s["actors"][0]["shape"]["width"] = 1e308; }) ==
        "/actors/0/shape/width = 1e+308: too large (at most 1e+06)");
  CHECK(boundsErrorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"generator", "hemisphere"}, {"radius", 2e6}, {"rings", 2}, {"segments", 3}};
        }) == "/actors/0/shape/radius = 2e+06: too large (at most 1e+06)");
  // A triangle 2 km across, written in millimetres, is 2e6 units from the origin.
  const Json inMillimetres = {{"vertices", {{0, 0, 0}, {2e6, 0, 0}, {0, 2e6, 0}}}, {"faces", {{0, 1, 2}}}};
  CHECK(boundsErrorAfter([&](Json& s) { s["actors"][0]["shape"] = inMillimetres; }) ==
        "/actors/0/shape: arrays: vertex 1 (counted from 0) lies at (2e+06, 0, 0), over 1e+06 m from the origin in a "
        "coordinate (lengths are in metres: a scene's \"scale\" converts a mesh in other units)");
  Json scaled = inMillimetres;
  scaled["scale"] = 0.001;
  Json s = boundsScene();
  s["actors"][0]["shape"] = scaled;
  s["actors"][0]["fixed"] = {{{"select", {{"indices", {0}}}}}};
  s["actors"][0]["probes"][0]["select"] = {{"nearest", {2000, 0, 0}}};
  const SceneModel model = buildSceneModel(sceneFromJson(s, "."));
  CHECK(model.world.V.row(1) == Eigen::RowVector3d(2000, 0, 0));
  CHECK(model.probes.at(0).vertex == 1);
  // An OBJ file alike, and the factor bounded.
  const std::string obj = boundsTempPath("millimetres.obj");
  std::ofstream(obj) << "v 0 0 0\nv 2e6 0 0\nv 0 2e6 0\nf 1 2 3\n";
  s["actors"][0]["shape"] = {{"obj", obj}, {"scale", 0.001}};
  CHECK(buildSceneModel(sceneFromJson(s, ".")).world.V.row(2) == Eigen::RowVector3d(0, 2000, 0));
  s["actors"][0]["shape"]["scale"] = 0;
  CHECK(boundsErrorOf(s) == "/actors/0/shape/scale = 0: must lie in [1e-06, 1e+06] (the factor to metres)");
  s["actors"][0]["shape"]["scale"] = 1e7;
  CHECK(boundsErrorOf(s) == "/actors/0/shape/scale = 1e+07: must lie in [1e-06, 1e+06] (the factor to metres)");
}

TEST_CASE("scene bounds: volume actors' sizes, places and speeds are bounded, and named in the scene's words",
          "[scene][hostile]") {
  // A ball of radius 1e300 once ran, and every load step failed with a non-finite energy at iteration 0.
  const auto withSolid = [](Json solid) {
    return boundsErrorAfter([&](Json& s) { s["actors"].push_back(solid); });
  };
  CHECK(withSolid({{"type", "sphere"}, {"name", "ball"}, {"center", {0, 0, 2}}, {"radius", 1e300}}) ==
        "/actors/1/radius = 1e+300: too large (at most 1e+06)");
  CHECK(withSolid({{"type", "capsule"}, {"center", {0, 0, 2}}, {"radius", 0.1}, {"halfLength", 2e6}}) ==
        "/actors/1/halfLength = 2e+06: too large (at most 1e+06)");
  CHECK(withSolid({{"type", "box"}, {"center", {0, 0, 2}}, {"halfExtents", {1, 1e7, 1}}}) ==
        "/actors/1/halfExtents/1 = 1e+07: too large (at most 1e+06)");
  // Once named by the library's field ("volume actor 'ball'.worldFromLocalTransform.translation").
  CHECK(withSolid({{"type", "sphere"}, {"center", {0, 0, 1e300}}, {"radius", 0.1}}) ==
        "/actors/1/center = [0, 0, 1e+300]: too large (norm at most 1e+06)");
  CHECK(withSolid({{"type", "plane"}, {"point", {0, 2e6, 0}}}) ==
        "/actors/1/point = [0, 2e+06, 0]: too large (norm at most 1e+06)");
  CHECK(withSolid({{"type", "box"}, {"halfExtents", {1, 1, 1}}, {"center", {0, 0, 2}}, {"velocity", {0, 0, 1e300}}}) ==
        "/actors/1/velocity = [0, 0, 1e+300]: too large (norm at most 1e+06)");
  CHECK(withSolid({{"type", "box"}, {"halfExtents", {1, 1, 1}}, {"center", {0, 0, 2}},
                   {"angularVelocity", {0, 0, 1e12}}}) ==
        "/actors/1/angularVelocity = [0, 0, 1e+12]: too large (norm at most 1e+06)");
  // The C++ API holds the same bounds.
  VolumeActorParams ball;
  ball.kind = VolumeActorParams::Kind::Sphere;
  ball.name = "ball";
  ball.radius = 1e300;
  CHECK_THROWS_WITH(validate(ball, "ball"), "ball.radius = 1e+300: too large (at most 1e+06)");
  ball.radius = 0.1;
  ball.angularVelocity = {0, 0, 1e12};
  CHECK_THROWS_WITH(validate(ball, "ball"), "ball.angularVelocity = [0, 0, 1e+12]: too large (norm at most 1e+06)");
}
