#include "core/mesh_generators.h"
#include "core/input_limits.h"
#include "core/mesh_io.h"
#include "solvers/shell_system.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"
#include "tools/scene/scene_problem.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <functional>
#include <fstream>

using namespace jetshell;
using Json = nlohmann::json;

namespace {

/// A small valid scene: a 4 × 2 strip, left edge fixed, a load on the right edge, one probe.
Json baseScene() {
  return Json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{
      "type": "shell", "name": "strip",
      "shape": {"generator": "rectangle", "width": 4, "height": 1, "nx": 8, "ny": 2},
      "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.01, "volumeDensity": 100},
      "fixed": [{"select": {"group": "left"}}],
      "loads": [{"select": {"group": "right"}, "force": [0, 0, 1], "distribution": "edgeLength"}],
      "probes": [{"name": "tip", "select": {"nearest": [4, 0.5, 0]}}]
    }],
    "analysis": {"type": "static", "loadSteps": 2}
  })");
}

std::string tempDir() {
  const auto dir = test::scratchDirectory("scene_tests");
  std::filesystem::create_directories(dir);
  return dir.string();
}

/// The error message of loading (and resolving) a scene, or "no error".
std::string errorOf(const Json& scene) {
  try {
    buildSceneModel(sceneFromJson(scene, tempDir()));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string errorOfText(const std::string& text) {
  try {
    buildSceneModel(sceneFromJson(jetshell::json::parse(text, "s.json"), tempDir()));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

template <typename Edit>
std::string errorAfter(Edit edit) {
  Json s = baseScene();
  edit(s);
  return errorOf(s);
}

void writeFile(const std::string& name, const std::string& text) {
  std::ofstream(std::filesystem::path(tempDir()) / name) << text;
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

TEST_CASE("scene: every example parses and resolves") {
  const std::filesystem::path dir = std::filesystem::path(JETSHELL_SOURCE_DIR) / "examples";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    if (entry.path().filename().string().rfind("fit_", 0) == 0) continue;  // fit files (FITTING.md): tests/tools/fit
    INFO(entry.path().string());
    const Scene scene = loadSceneFile(entry.path().string());
    const SceneModel model = buildSceneModel(scene);
    CHECK(model.numVertices() > 0);
    CHECK((!model.prescribed.empty() || !scene.volumes.empty()));  // held, or falling onto a volume actor
    CHECK(!model.probes.empty());
    ++count;
  }
  CHECK(count >= 3);
}

TEST_CASE("scene: the slit annular ring resolves to the page's setup") {
  const Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/slit_annular_ring.json");
  const SceneModel m = buildSceneModel(scene);
  REQUIRE(m.numVertices() == 325);
  CHECK(m.prescribed.size() == 2 * 5 * 3);  // two columns of 5 nodes, all components
  for (const PrescribedCoordinate& p : m.prescribed) CHECK(p.vertex % 65 <= 1);
  // 0.32 N in total, on the θ = 2π column only, with the end nodes carrying half a segment each.
  double total = 0;
  for (int v = 0; v < 325; ++v) {
    const double fz = m.appliedForces[3 * v + 2];
    total += fz;
    if (fz != 0.0) CHECK(v % 65 == 64);
  }
  CHECK(total == Approx(0.32));
  CHECK(m.appliedForces[3 * 64 + 2] == Approx(0.04));
  CHECK(m.appliedForces[3 * (65 + 64) + 2] == Approx(0.08));
  REQUIRE(m.probes.size() == 2);
  CHECK(m.probes[0].vertex == 64);
  CHECK(m.probes[1].vertex == 4 * 65 + 64);
  CHECK(scene.shells[0].material.membraneMu == Approx(0.003 * 210e6 / 2));
  CHECK(scene.shells[0].material.density == Approx(3.0));
  CHECK(scene.shells[0].material.massDampingCoefficient == 0.3);
  CHECK(!scene.shells[0].hasGravity);
  CHECK(scene.analysis.type == AnalysisType::DynamicRelaxation);
}

TEST_CASE("scene: prescribed motion follows the load factor, per component") {
  Json s = baseScene();
  s["actors"][0]["fixed"] = Json::parse(R"([
    {"select": {"group": "left"}},
    {"select": {"group": "right"}, "components": "xz", "displacement": [0.5, 0, -1]}
  ])");
  const SceneModel m = buildSceneModel(sceneFromJson(s, tempDir()));
  CHECK(m.prescribed.size() == 3 * 3 + 3 * 2);
  int moving = 0;
  for (const PrescribedCoordinate& p : m.prescribed) {
    if (!p.value) continue;
    ++moving;
    CHECK(p.component != 1);
    const double X = m.world.V(p.vertex, p.component);
    CHECK(p.value(0.5) == Approx(X + 0.5 * (p.component == 0 ? 0.5 : -1.0)));
  }
  CHECK(moving == 3 * 2);
}

TEST_CASE("scene: transforms place actors and loads are spread as asked") {
  Json s = baseScene();
  s["actors"][0]["worldFromLocalTransform"] = Json::parse(R"({"translation": [1, 2, 3], "rotation": {"axis": [0, 0, 1], "degrees": 90}})");
  s["actors"][0]["loads"] = Json::parse(R"([{"select": {"all": true}, "force": [0, 0, 2], "distribution": "area"},
                                             {"select": {"indices": [0, 1]}, "force": [1, 0, 0], "distribution": "perVertex"}])");
  s["actors"][0]["probes"][0]["select"]["nearest"] = {0.5, 6, 3};
  const SceneModel m = buildSceneModel(sceneFromJson(s, tempDir()));
  CHECK(m.world.V(0, 0) == Approx(1));
  CHECK(m.world.V(8, 1) == Approx(6));  // (4, 0, 0) rotated by 90° about z, then shifted
  CHECK(m.probes[0].vertex == 8 + 9);   // local (4, 0.5) after the transform: (−0.5, 4) + (1, 2)
  double fz = 0, fx = 0;
  for (int v = 0; v < m.numVertices(); ++v) fz += m.appliedForces[3 * v + 2], fx += m.appliedForces[3 * v];
  CHECK(fz == Approx(2.0));
  CHECK(fx == Approx(2.0));
  // A corner carries a sixth of one face's area (alternating diagonals), an interior vertex more.
  CHECK(m.appliedForces[3 * 10 + 2] > m.appliedForces[3 * 0 + 2]);
}

TEST_CASE("scene: the membrane's evaluator, and its former name handChained for perFace") {
  Json s = baseScene();
  CHECK(sceneFromJson(s, tempDir()).solver.evaluator == "perFace");
  for (const char* given : {"perFace", "handChained", "staged"}) {
    s["solver"] = {{"evaluator", given}};
    CHECK(sceneFromJson(s, tempDir()).solver.evaluator == (std::string(given) == "staged" ? "staged" : "perFace"));
  }
}

TEST_CASE("scene: several actors stack into one set of unknowns") {
  Json s = baseScene();
  Json second = s["actors"][0];
  second["name"] = "second";
  second["worldFromLocalTransform"] = {{"translation", {0, 0, 1}}};
  second.erase("probes");
  s["actors"].push_back(second);
  s["actors"].push_back(Json::parse(R"({"type": "plane", "name": "floor", "point": [0, 0, -1], "normal": [0, 0, 1]})"));
  const Scene scene = sceneFromJson(s, tempDir());
  CHECK(scene.volumes.size() == 1);
  CHECK(unsupportedFeatures(scene).empty());  // a static floor is simulated, nothing to note
  const SceneModel m = buildSceneModel(scene);
  REQUIRE(m.actors.size() == 2);
  CHECK(m.actors[1].firstVertex == 27);
  CHECK(m.numVertices() == 54);
  // Each actor's mesh holds its own vertices (ids from 0); the stacked faces are its faces shifted.
  CHECK(m.actors[1].mesh.numVertices() == 27);
  CHECK(m.actors[1].mesh.F.minCoeff() == 0);
  CHECK(m.actors[1].mesh.V == m.world.V.middleRows(27, 27));
  CHECK(m.world.F.middleRows(m.actors[1].firstFace, m.actors[1].numFaces).minCoeff() == 27);
  CHECK(m.world.V(27, 2) == 1.0);
}

TEST_CASE("scene: malformed scenes give one clear line naming the field") {
  CHECK(startsWith(errorOfText("{\n  \"actors\": [\n    {\"type\": \"shell\",,}\n  ]\n}"),
                   "s.json:3:22: invalid JSON: syntax error while parsing object key - unexpected ','"));
  CHECK(errorOfText(R"({"actors": [], "actors": []})") == "s.json: /actors: repeated key (each key may appear once per object)");
  CHECK(errorOfText(R"({"actors": [{"type": "shell"}, {"shape": {}, "type": "shell", "type": "plane"}]})") ==
        "s.json: /actors/1/type: repeated key (each key may appear once per object)");
  CHECK(errorAfter([](Json& s) { s.erase("actors"); }) == "/actors: missing (required)");
  CHECK(errorAfter([](Json& s) { s.erase("analysis"); }) == "/analysis: missing (required)");
  CHECK(errorAfter([](Json& s) { s["actors"][0].erase("shape"); }) == "/actors/0/shape: missing (required)");
  CHECK(errorAfter([](Json& s) { s["solvr"] = Json::object(); }) ==
        "/solvr: unknown key in a scene (did you mean \"solver\"?)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["material"]["poisonRatio"] = 0.3; }) ==
        "/actors/0/material/poisonRatio: unknown key in a shell material (did you mean \"poissonRatio\"?)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["material"]["poissonRatio"] = "0.3"; }) ==
        "/actors/0/material/poissonRatio: expected a number, got a string");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["material"]["poissonRatio"] = 0.5; }) ==
        "/actors/0/material/poissonRatio = 0.5: must lie in (-1, 0.5)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["material"]["thickness"] = 0; }) ==
        "/actors/0/material/thickness = 0: must be finite and > 0");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["material"].erase("thickness"); }) ==
        "/actors/0/material/thickness: missing (required)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["material"] = {{"density", -1}}; }) ==
        "/actors/0/material/density = -1: must be finite and >= 0");
  CHECK(startsWith(errorAfter([](Json& s) { s["actors"][0]["material"]["membraneMu"] = 10; }),
                   "/actors/0/material/membraneMu: cannot be combined with \"youngsModulus\""));
  CHECK(errorAfter([](Json& s) { s["gravity"] = {0, -9.81}; }) ==
        "/gravity: expected an array of 3 numbers [x, y, z], got an array");
  CHECK(errorAfter([](Json& s) { s["gravity"][2] = std::numeric_limits<double>::infinity(); }) ==
        "/gravity/2 = inf: must be finite");
  CHECK(errorOfText(R"({"gravity": [0, 0, 1e999]})") == "s.json:1:20: invalid JSON: number overflow parsing '1e999'");
  CHECK(startsWith(errorOfText(R"({"gravity": [0, 0, NaN]})"), "s.json:1:20: invalid JSON: syntax error while parsing value - invalid literal"));
  CHECK(errorAfter([](Json& s) { s["actors"][0]["shape"]["nx"] = 2.5; }) ==
        "/actors/0/shape/nx: expected an integer, got 2.5");
  CHECK(startsWith(errorAfter([](Json& s) { s["actors"][0]["shape"]["generator"] = "disk"; }),
                   "/actors/0/shape/generator: \"disk\" is not one of \"rectangle\""));
  CHECK(errorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"generator", "slitAnnulus"}, {"innerRadius", 1}, {"outerRadius", 2},
                                     {"rings", 1}, {"nodesPerRing", 8}};
        }) == "/actors/0/shape/rings = 1: must be >= 2");
  CHECK(startsWith(errorAfter([](Json& s) {
                     s["actors"][0]["shape"] = {{"generator", "slitAnnulus"}, {"innerRadius", 1}, {"outerRadius", 2},
                                                {"rings", 3}, {"nodesPerRing", 8}, {"ringSpacing", "log"}};
                   }),
                   "/actors/0/shape/ringSpacing: \"log\" is not one of \"uniform\", \"cosine\""));
  CHECK(errorAfter([](Json& s) { s["actors"][0]["material"]["thickness"] = 1e-200; }) ==
        "/actors/0/material: youngsModulus 1e+06 and thickness 1e-200 give a membrane stiffness mu = 3.84615e-195 N/m "
        "and a bending stiffness beta = 0 N m, which must be finite and > 0 (E h and E h^3 out of a double's range)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["shape"]["diagonals"] = "zigzag"; }) ==
        "/actors/0/shape/diagonals: \"zigzag\" is not one of \"alternating\", \"uniform\"");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["type"] = "cloth"; }) ==
        "/actors/0/type: \"cloth\" is not one of \"shell\", \"plane\", \"box\", \"sphere\", \"capsule\", \"sdfGrid\"");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["colliderType"] = "Sphere"; }) ==
        "/actors/0/colliderType: \"Sphere\" is not one of \"PointCloud\", \"None\"");
  CHECK(errorAfter([](Json& s) { s["analysis"] = {{"type", "static"}, {"timeStep", 0.1}}; }) ==
        "/analysis/timeStep: unknown key in a static analysis "
        "(allowed: type, loadSteps, pathControl, branchSwitching)");
  CHECK_THAT(errorAfter([](Json& s) { s["analysis"] = {{"type", "static"}, {"branchSwitching", "yes"}}; }),
             Catch::StartsWith("/analysis/branchSwitching"));
  CHECK(errorAfter([](Json& s) { s["analysis"] = {{"type", "dynamic"}, {"timeStep", -0.1}, {"duration", 1}}; }) ==
        "/analysis/timeStep = -0.1: must be finite and > 0");
  CHECK(errorAfter([](Json& s) { s["analysis"] = {{"type", "dynamic"}, {"duration", 1}}; }) ==
        "/analysis/timeStep: missing (required)");
  CHECK(errorAfter([](Json& s) { s["solver"] = {{"lineSearch", "wolf"}}; }) ==
        "/solver/lineSearch: \"wolf\" is not one of \"default\", \"none\", \"armijo\", \"residual\", \"wolfe\" "
        "(did you mean \"wolfe\"?)");
  CHECK(errorAfter([](Json& s) { s["solver"] = {{"evaluator", "stages"}}; }) ==
        "/solver/evaluator: \"stages\" is not one of \"perFace\", \"staged\", \"handChained\" (did you mean "
        "\"staged\"?)");
  CHECK(errorAfter([](Json& s) { s["solver"] = {{"fallbackBendingHessian", "gauss"}}; }) ==
        "/solver/fallbackBendingHessian: \"gauss\" is not one of \"exact\", \"gaussNewton\"");
  CHECK(errorAfter([](Json& s) { s["actors"].push_back({{"type", "sphere"}, {"radius", -1}}); }) ==
        "/actors/1/radius = -1: must be finite and > 0");
  // Magnitudes whose squares or reciprocals overflow, which run --check used to pass and the run then refused
  // without naming the field (or wrote inf into the summary).
  CHECK(errorAfter([](Json& s) { s["analysis"] = {{"type", "dynamic"}, {"timeStep", 1e-12}, {"duration", 2e-12}}; }) ==
        "/analysis/timeStep = 1e-12: must be at least 1e-09 s (its inverse square scales the inertia)");
  CHECK(errorAfter([](Json& s) { s["analysis"] = {{"type", "dynamicRelaxation"}, {"timeStep", 0.1}}; }) ==
        "/analysis/massDamping = 0: must be > 0 when no actor's material has a massDampingCoefficient (relaxation "
        "needs damping)");
  CHECK(errorAfter([](Json& s) {
          s["analysis"] = {{"type", "dynamicRelaxation"}, {"timeStep", 0.1}, {"massDamping", 1e300}};
        }) == "/analysis/massDamping = 1e+300: must be at most 1e+09 1/s");
  CHECK_THAT(errorAfter([](Json& s) { s["actors"][0]["material"]["massDampingCoefficient"] = 1e308; }),
             Catch::Contains("massDampingCoefficient") && Catch::Contains("must lie in [0, 1e+09] (1/s)"));
  CHECK(errorAfter([](Json& s) { s["actors"][0]["fixed"][0]["displacement"] = {1e200, 0, 0}; }) ==
        "/actors/0/fixed/0/displacement = [1e+200, 0, 0]: too large (norm at most 1e+06)");
  CHECK_THAT(errorAfter([](Json& s) { s["actors"][0]["worldFromLocalTransform"] = {{"translation", {1e308, 0, 0}}}; }),
             Catch::Contains("translation = [1e+308, 0, 0]: too large (norm at most 1e+06)"));
  // A tolerance of the force scale's size passes the unloaded start: "converged" with nothing balanced.
  CHECK(errorAfter([](Json& s) { s["solver"] = {{"residualTolerance", 1e308}}; }) ==
        "/solver/residualTolerance = 1e+308: too large (at most 0.1)");
  CHECK(errorAfter([](Json& s) { s["solver"] = {{"decrementTolerance", 2}}; }) ==
        "/solver/decrementTolerance = 2: too large (at most 0.1)");
  CHECK(errorAfter([](Json& s) {
          s["analysis"] = {{"type", "dynamicRelaxation"}, {"timeStep", 0.1}, {"tolerance", 0.5}};
        }) == "/analysis/tolerance = 0.5: too large (at most 0.1)");
}

TEST_CASE("scene: selections that cannot resolve name the selector") {
  CHECK(errorAfter([](Json& s) { s["actors"][0]["fixed"][0]["select"] = {{"indices", {0, 99}}}; }) ==
        "/actors/0/fixed/0/select/indices/1 = 99: out of range [0, 27)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["fixed"][0]["select"] = {{"group", "slitEnd"}}; }) ==
        "/actors/0/fixed/0/select/group = \"slitEnd\": unknown group of generator rectangle (known: bottom, left, "
        "right, top)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["fixed"][0]["select"] = Json::object(); }) ==
        "/actors/0/fixed/0/select: selects nothing (give at least one criterion, or \"all\": true)");
  CHECK(errorAfter([](Json& s) {
          s["actors"][0]["fixed"][0]["select"] = {{"box", {{"min", {10, 10, 10}}, {"max", {11, 11, 11}}}}};
        }) == "/actors/0/fixed/0/select: no vertex matches the selection");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["fixed"][0]["components"] = "xw"; }) ==
        "/actors/0/fixed/0/components: \"xw\" must be made of the letters x, y, z");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["probes"][0]["select"] = {{"group", "left"}}; }) ==
        "/actors/0/probes/0/select: picks 3 vertices; a probe needs exactly one (add \"nearest\": [x, y, z])");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["probes"].push_back(s["actors"][0]["probes"][0]); }) ==
        "/actors/0/probes/1/name = \"tip\": duplicate probe name");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["loads"][0]["select"] = {{"nearest", {2, 0.5, 0}}}; }) ==
        "/actors/0/loads/0/distribution = \"edgeLength\": no boundary edge joins two selected vertices (select a "
        "line of boundary vertices)");
  CHECK(errorAfter([](Json& s) {
          s["actors"][0]["fixed"][0]["select"] = {{"plane", {{"point", {0, 0, 0}}, {"normal", {0, 0, 0}}, {"distance", 0}}}};
        }) == "/actors/0/fixed/0/select/plane/normal = [0, 0, 0]: must be a non-zero vector");
}

TEST_CASE("scene: broken and missing meshes name the file and line") {
  writeFile("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  writeFile("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  const std::string dir = tempDir();
  CHECK(errorAfter([](Json& s) { s["actors"][0]["shape"] = {{"obj", "missing.obj"}}; }) ==
        "/actors/0/shape/obj: " + dir + "/missing.obj: cannot open mesh file");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["shape"] = {{"obj", "bad_index.obj"}}; }) ==
        "/actors/0/shape/obj: " + dir + "/bad_index.obj:4: face index 4 is out of range (the file has 3 vertices)");
  CHECK(startsWith(errorAfter([](Json& s) { s["actors"][0]["shape"] = {{"obj", "fin.obj"}}; }),
                   "/actors/0/shape/obj: " + dir + "/fin.obj:8: face uses the non-manifold edge between vertices 1 and 2"));
  CHECK(errorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}, {"faces", {{0, 1, 5}}}};
        }) == "/actors/0/shape: mesh: face 0 (0, 1, 5) has vertex index 5 out of range [0, 3)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["shape"] = {{"obj", 3}}; }) ==
        "/actors/0/shape/obj: expected a string, got a number");
}

TEST_CASE("scene: a missing scene file is named") {
  CHECK_THROWS_WITH(loadSceneFile("/nonexistent/scene.json"), "/nonexistent/scene.json: cannot open scene file");
}

TEST_CASE("scene: a vertex that no face uses is refused, in the scene and in the shell system") {
  CHECK(errorAfter([](Json& s) {
          s["actors"][0]["shape"] = {{"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}}},
                                     {"faces", {{0, 1, 2}}}};
          s["actors"][0]["fixed"][0]["select"] = {{"indices", {0, 1, 2}}};
        }) == "/actors/0/shape: arrays: vertex 3 (counted from 0) belongs to no face: a shell vertex without a face "
              "has no stiffness and no mass (remove it from the mesh)");
  ShellProblem p;
  p.mesh.V = (Positions(4, 3) << 0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5).finished();
  p.mesh.F = (Faces(1, 3) << 0, 1, 2).finished();
  p.material = ShellMaterialParamsFrom3dIsotropic(1e6, 0.3, 100, 0.01);
  CHECK_THROWS_WITH(ShellSystem(p, AnalysisKind::Dynamics),
                    "mesh: vertex 3 belongs to no face (a shell vertex without a face has no stiffness and no mass)");
}

TEST_CASE("scene: a moment load resolves to one chain of boundary edges, and a bad one names the field") {
  auto withMoment = [](const Json& select) {
    Json s = baseScene();
    s["actors"][0]["loads"][0] = {{"select", select}, {"moment", 2.0}, {"axis", {0, -1, 0}}};
    return s;
  };
  {
    const Scene scene = sceneFromJson(withMoment({{"group", "right"}}), tempDir());
    const SceneModel model = buildSceneModel(scene);
    REQUIRE(model.endMoments.size() == 1);
    const EndMomentLoad& m = model.endMoments[0];
    CHECK(m.chain == std::vector<int>{8, 17, 26});  // the right edge of the 9 × 3 grid, from the smaller id
    CHECK(m.moment == 2.0);
    CHECK(m.axis == Eigen::Vector3d(0, -1, 0));
    CHECK(m.where == "/actors/0/loads/0");
    CHECK(model.appliedForces.cwiseAbs().maxCoeff() == 0.0);  // a moment is not a nodal force
    const ShellProblem problem = shellProblemFromScene(scene, model);
    ShellSystem system(problem, AnalysisKind::Statics);
    REQUIRE(system.endMoments.size() == 1);
    CHECK(system.endMoments[0]->name() == "end_moment");
    CHECK(momentLoadedVertices(problem)[17] == 1);
    CHECK(momentLoadedVertices(problem)[16] == 0);
  }
  const std::string rule = ": a moment load's vertices must form one open chain of boundary edges (an edge of the "
                           "shell, from one end to the other); ";
  CHECK(errorOf(withMoment({{"indices", {0, 26}}})) ==
        "/actors/0/loads/0/select" + rule + "vertex 0 is on no boundary edge to another");
  CHECK(errorOf(withMoment({{"boundary", true}})) == "/actors/0/loads/0/select" + rule + "these close a loop");
  CHECK(errorOf(withMoment(Json::array({{{"group", "left"}}, {{"group", "right"}}}))) ==
        "/actors/0/loads/0/select" + rule + "they form separate pieces (3 of 6 vertices are joined to the first end)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["loads"][0]["moment"] = 1.0; }) ==
        "/actors/0/loads/0/force: a moment load takes \"select\", \"moment\" and \"axis\" only (a force is a separate "
        "load)");
  CHECK(errorAfter([](Json& s) { s["actors"][0]["loads"][0]["axis"] = {0, 1, 0}; }) ==
        "/actors/0/loads/0/axis: only a moment load has an axis");
  Json zeroAxis = withMoment({{"group", "right"}});
  zeroAxis["actors"][0]["loads"][0]["axis"] = {0, 0, 0};
  CHECK(errorOf(zeroAxis) == "/actors/0/loads/0/axis = [0, 0, 0]: must be a non-zero vector");
  Json noAxis = withMoment({{"group", "right"}});
  noAxis["actors"][0]["loads"][0].erase("axis");
  CHECK(errorOf(noAxis) == "/actors/0/loads/0/axis: missing (required)");
  Json dynamic = withMoment({{"group", "right"}});
  dynamic["analysis"] = {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}};
  CHECK(errorOf(dynamic) == "/actors/0/loads/0/moment: an end moment needs a static analysis (its rotation is "
                            "unwrapped from one load step to the next)");
  Json many = baseScene();
  for (int k = 0; k <= 64; ++k)
    many["actors"][0]["loads"][k] = {{"select", {{"group", "right"}}}, {"moment", 1.0}, {"axis", {0, 1, 0}}};
  CHECK(errorOf(many) == "/actors/0/loads/64: moment loads in the scene = 65: too large (at most 64)");
  // The axis along the loaded edge's normal in the plane: no segment has a sense about it.
  Json across = withMoment({{"group", "right"}});
  across["actors"][0]["loads"][0]["axis"] = {1, 0, 0};
  const Scene scene = sceneFromJson(across, tempDir());
  const ShellProblem problem = shellProblemFromScene(scene, buildSceneModel(scene));
  CHECK_THROWS_WITH(ShellSystem(problem, AnalysisKind::Statics),
                    "/actors/0/loads/0: end moment: chain segment 0 is perpendicular to the axis");
}

TEST_CASE("scene: constant velocities move a volume actor in dynamics only, keyframes in static paths too") {
  Json s = baseScene();
  s["actors"].push_back(Json::parse(R"({"type": "sphere", "name": "ball", "center": [0.5, 0.5, -0.3],
                                        "radius": 0.2, "velocity": [0, 0, 1], "angularVelocity": [0, 2, 0]})"));
  s["actors"].push_back(Json::parse(R"({"type": "sphere", "name": "punch", "center": [0.5, 0.5, 0.4],
                                        "radius": 0.2, "keyframes": [{"time": 2, "translation": [0, 0, -0.2]}]})"));
  const Json relaxation = {{"type", "dynamicRelaxation"}, {"timeStep", 0.01}, {"massDamping", 5.0}};
  const Json dynamic = {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}};
  for (const Json& analysis : {s["analysis"], relaxation, dynamic}) {
    s["analysis"] = analysis;
    const Scene scene = sceneFromJson(s, tempDir());
    const ShellProblem problem = shellProblemFromScene(scene, buildSceneModel(scene));
    const AnalysisKind kind = scene.analysis.type == AnalysisType::Static    ? AnalysisKind::Statics
                              : scene.analysis.type == AnalysisType::Dynamic ? AnalysisKind::Dynamics
                                                                             : AnalysisKind::DynamicRelaxation;
    CHECK(pathClock(kind) == pathClock(scene.analysis.type));
    const ShellSystem system(problem, kind);
    REQUIRE(system.contact.volume.size() == 2);
    const RigidPath& ball = system.contact.volume[0].state->collider->path();
    const RigidPath& punch = system.contact.volume[1].state->collider->path();
    CHECK(ball.origin == Eigen::Vector3d(0.5, 0.5, -0.3));
    const std::vector<std::string> notes = unsupportedFeatures(scene);
    if (scene.analysis.type == AnalysisType::Dynamic) {
      CHECK(ball.velocity == Eigen::Vector3d(0, 0, 1));
      CHECK(ball.angularVelocity == Eigen::Vector3d(0, 2, 0));
      CHECK_FALSE(punch.isStatic());
      CHECK(notes.empty());
    } else if (scene.analysis.type == AnalysisType::Static) {
      // The keyframes run on the load factor, which ends at 1: the punch goes half its way down.
      CHECK(ball.isStatic());
      REQUIRE_FALSE(punch.isStatic());
      CHECK((punch.originAt(1.0) - Eigen::Vector3d(0.5, 0.5, 0.3)).norm() < 1e-15);
      REQUIRE(notes.size() == 2);
      CHECK(notes[0] == "volume actor 'ball' moves by constant velocities in dynamic analyses only: this static "
                        "analysis holds it where it is at t = 0 (a static path moves a solid along its keyframes, "
                        "their times read as load factors)");
      CHECK(notes[1] == "volume actor 'punch': a static path reads its keyframes' times as load factors, which end "
                        "at 1, so it goes only as far as its path takes it by t = 1");
    } else {
      CHECK(ball.isStatic());
      CHECK(punch.isStatic());
      REQUIRE(notes.size() == 2);
      CHECK(notes[0] == "volume actor 'ball' does not move in a dynamicRelaxation analysis: it is held where it "
                        "is at t = 0");
      CHECK(notes[1] == "volume actor 'punch' does not move in a dynamicRelaxation analysis: it is held where it "
                        "is at t = 0");
    }
  }
  // Arc length and displacement control solve for λ, the moving solid's time: refused, naming the solid.
  Json statics = s;
  statics["analysis"] = {{"type", "static"}, {"pathControl", {{"type", "arcLength"}}}};
  CHECK_THROWS_WITH(sceneFromJson(statics, tempDir()),
                    Catch::Contains("/analysis/pathControl/type = \"arcLength\": the volume actor 'punch' moves"));
  statics["actors"].erase(2);  // without the punch, the ball's velocities are held: nothing moves
  CHECK_NOTHROW(sceneFromJson(statics, tempDir()));
}

TEST_CASE("scene: a volume actor moves through its keyframes, and bad keyframes are named") {
  Json s = baseScene();
  s["analysis"] = {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}};
  s["actors"].push_back(Json::parse(R"({"type": "box", "name": "lift", "center": [0.5, 0.5, -0.3],
      "halfExtents": [0.2, 0.2, 0.1], "keyframes": [
        {"time": 0.5, "translation": [0, 0, 0.2]},
        {"time": 1.5, "translation": [0, 0, 0.2], "rotation": {"axis": [0, 0, 1], "degrees": 90}}]})"));
  const Scene scene = sceneFromJson(s, tempDir());
  REQUIRE(scene.volumes.size() == 1);
  REQUIRE(scene.volumes[0].keyframes.size() == 2);
  CHECK(scene.volumes[0].keyframes[1].time == 1.5);
  const ShellProblem problem = shellProblemFromScene(scene, buildSceneModel(scene));
  const ShellSystem system(problem, AnalysisKind::Dynamics);
  const RigidPath& path = system.contact.volume[0].state->collider->path();
  CHECK((path.originAt(0.25) - Eigen::Vector3d(0.5, 0.5, -0.2)).norm() < 1e-15);
  CHECK((path.originAt(9.0) - Eigen::Vector3d(0.5, 0.5, -0.1)).norm() < 1e-15);
  CHECK(unsupportedFeatures(scene).empty());
  auto errorWith = [&](const std::function<void(Json&)>& change) {
    Json bad = s;
    change(bad["actors"][1]);
    return errorOf(bad);
  };
  // A box with rounded edges: its radius at most its smallest half-extent, and in the shape contact reads.
  CHECK(errorWith([](Json& a) { a["edgeRadius"] = 0.2; }) ==
        "/actors/1/edgeRadius = 0.2: must be at most the smallest half extent (0.1)");
  CHECK(errorWith([](Json& a) { a["edgeRadius"] = -1; }) == "/actors/1/edgeRadius = -1: must be finite and >= 0");
  {
    Json rounded = s;
    rounded["actors"][1]["edgeRadius"] = 0.05;
    const Scene r = sceneFromJson(rounded, tempDir());
    CHECK(r.volumes[0].edgeRadius == 0.05);
    const ShellSystem rs(shellProblemFromScene(r, buildSceneModel(r)), AnalysisKind::Dynamics);
    // 0.1 m beyond the top face's edge at x = 0.7, z = -0.2, diagonally: 0.1 from the core's edge, less 0.05.
    const Eigen::Vector3d p(0.65 + 0.1 / std::sqrt(2.0), 0.5, -0.25 + 0.1 / std::sqrt(2.0));
    CHECK(rs.contact.volume[0].state->collider->query(p, 0.0).distance == Approx(0.05));
  }
  CHECK(errorWith([](Json& a) { a["keyframes"][0]["time"] = 0.0; }) ==
        "/actors/1/keyframes/0/time = 0: must be finite and at least 1e-9 s (the actor is at its placement at t = 0)");
  CHECK(errorWith([](Json& a) { a["keyframes"][1]["time"] = 0.5; }) ==
        "/actors/1/keyframes/1/time = 0.5: must be finite and at least 1e-9 s after the previous keyframe's time");
  // Closer than that, a move of up to 1e6 m could take the actor past any finite speed.
  CHECK(errorWith([](Json& a) { a["keyframes"][1]["time"] = 0.5 + 1e-12; }).find(
            "at least 1e-9 s after the previous keyframe's time") != std::string::npos);
  CHECK(errorWith([](Json& a) { a["keyframes"][1]["speed"] = 1.0; }).find("/actors/1/keyframes/1") == 0);
  CHECK(errorWith([](Json& a) { a["keyframes"] = Json::array(); }) ==
        "/actors/1/keyframes: no keyframe (leave \"keyframes\" out for a static actor)");
  CHECK(errorWith([](Json& a) { a["keyframes"][0]["translation"] = {0, 0, 2e6}; }).find(
            "/actors/1/keyframes/0/translation") == 0);
  CHECK(errorWith([](Json& a) { a["velocity"] = {0, 0, 1}; }) ==
        "/actors/1/keyframes: cannot be combined with \"velocity\" or \"angularVelocity\" (a keyframed actor moves "
        "through its keyframes alone)");
  // Bounded: all volume actors' keyframes together.
  const std::int64_t saved = inputLimits().maxKeyframes;
  inputLimits().maxKeyframes = 3;
  Json two = s;
  two["actors"].push_back(s["actors"][1]);
  two["actors"][2]["name"] = "other";
  const std::string tooMany = errorOf(two);
  inputLimits().maxKeyframes = saved;
  CHECK(tooMany == "/actors/2/keyframes: 2 keyframes: too many (at most 1 for all volume actors of a scene "
                   "together)");
}
