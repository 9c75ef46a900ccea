#include "core/math_constants.h"
#include "core/mesh_generators.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/support_check.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

/// A 4 × 4 plate under gravity (−z) with the given fixed conditions, loads and analysis.
Scene plate(const nlohmann::json& fixed, const nlohmann::json& loads, const nlohmann::json& analysis) {
  const nlohmann::json j = {
      {"gravity", {0, 0, -9.81}},
      {"actors",
       {{{"type", "shell"},
         {"shape", {{"generator", "rectangle"}, {"width", 1.0}, {"height", 1.0}, {"nx", 4}, {"ny", 4}}},
         {"material", {{"youngsModulus", 1e6}, {"poissonRatio", 0.3}, {"thickness", 0.01}, {"volumeDensity", 100}}},
         {"colliderType", "None"},
         {"fixed", fixed},
         {"loads", loads}}}},
      {"analysis", analysis},
      {"outputs", {{"png", false}, {"plots", false}}}};
  return sceneFromJson(j, ".");
}

const nlohmann::json kStatic = {{"type", "static"}, {"loadSteps", 2}};

}  // namespace

TEST_CASE("support check: a static problem with no supports under load names its rigid-body mode", "[support]") {
  const Scene scene = plate(nlohmann::json::array(), nlohmann::json::array(), kStatic);
  const SceneModel model = buildSceneModel(scene);
  const std::vector<std::string> modes = unbalancedRigidModes(scene, model);
  REQUIRE(modes.size() == 1);  // weight along z only
  CHECK_THAT(modes[0], Catch::Contains("without supports along z") && Catch::Contains("rigid-body mode") &&
                           Catch::Contains("-9.81 N"));
  CHECK_THROWS_WITH(checkRigidModes(scene, model), Catch::Contains("rigid-body mode"));
  // The run says so before solving instead of ending at the iteration cap.
  RunOptions o;
  o.outputDirectory = test::scratchDirectory("support_test").string();
  o.pictures = false;
  CHECK_THROWS_WITH(runScene(scene, o), Catch::Contains("no equilibrium exists"));
  // Dynamic relaxation seeks the same equilibrium.
  const Scene relaxation =
      plate(nlohmann::json::array(), nlohmann::json::array(), {{"type", "dynamicRelaxation"}, {"timeStep", 0.01}, {"massDamping", 1.0}});
  CHECK(unbalancedRigidModes(relaxation, buildSceneModel(relaxation)).size() == 1);
}

TEST_CASE("support check: supported, balanced or dynamic problems pass", "[support]") {
  // Fixed in z only, a load along x: x is free and pushed, y is free but not pushed.
  const nlohmann::json fixZ = {{{"select", {{"group", "left"}}}, {"components", "z"}}};
  const nlohmann::json pushX = {{{"select", {{"group", "right"}}}, {"force", {2.0, 0, 0}}}};
  Scene s = plate(fixZ, pushX, kStatic);
  std::vector<std::string> modes = unbalancedRigidModes(s, buildSceneModel(s));
  REQUIRE(modes.size() == 1);
  CHECK_THAT(modes[0], Catch::Contains("along x"));
  // Fully fixed edge: nothing to report.
  s = plate({{{"select", {{"group", "left"}}}}}, pushX, kStatic);
  CHECK(unbalancedRigidModes(s, buildSceneModel(s)).empty());
  // No supports, no gravity, balanced loads: equilibrium exists (up to rigid motion).
  s = plate(nlohmann::json::array(),
            {{{"select", {{"group", "right"}}}, {"force", {1.0, 0, 0}}}, {{"select", {{"group", "left"}}}, {"force", {-1.0, 0, 0}}}},
            kStatic);
  s.gravity.setZero();
  CHECK(unbalancedRigidModes(s, buildSceneModel(s)).empty());
  // A free fall is a legitimate dynamic problem.
  s = plate(nlohmann::json::array(), nlohmann::json::array(), {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.02}});
  CHECK(unbalancedRigidModes(s, buildSceneModel(s)).empty());
}

TEST_CASE("support check: faces pushed through their neighbours are inverted, rigid motions are not", "[support]") {
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, 3, 3);
  const Topology t = buildTopology(mesh);
  Eigen::VectorXd x = flatten(mesh.V);
  CHECK(invertedFaces(mesh, t, x).empty());
  // Turned over as a whole (rotation by 180° about x): no face is inverted relative to its neighbours.
  for (int v = 0; v < mesh.numVertices(); ++v) {
    x[3 * v + 1] = -mesh.V(v, 1);
    x[3 * v + 2] = -mesh.V(v, 2);
  }
  CHECK(invertedFaces(mesh, t, x).empty());
  // An interior vertex pushed in-plane beyond its neighbours' ring flips the faces around it.
  x = flatten(mesh.V);
  const int centre = 1 * 4 + 1;  // vertex (1, 1)
  x[3 * centre] += 0.8;
  x[3 * centre + 1] += 0.8;
  const std::vector<int> inverted = invertedFaces(mesh, t, x);
  int flipped = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d a = x.segment<3>(3 * mesh.F(f, 0)), b = x.segment<3>(3 * mesh.F(f, 1)), c = x.segment<3>(3 * mesh.F(f, 2));
    if ((b - a).cross(c - a).z() >= 0.0) continue;  // still facing +z
    ++flipped;
    CHECK(std::find(inverted.begin(), inverted.end(), f) != inverted.end());
  }
  CHECK(flipped > 0);
}

TEST_CASE("support check: a fold of the reference is measured from its own angle, so a seam folded flatter is not inverted", "[support]") {
  // A 2 x 1 strip folded about the grid line x = 1 by phi: the half x > 1 turns about the y axis.
  const TriMesh flat = makeRectangleGrid(2.0, 1.0, 4, 2);
  auto folded = [&](double degrees) {
    const double phi = degrees * kPi / 180.0;
    Eigen::MatrixXd V = flat.V;
    for (int v = 0; v < V.rows(); ++v) {
      const double s = flat.V(v, 0) - 1.0;
      if (s <= 0.0) continue;
      V(v, 0) = 1.0 + s * std::cos(phi);
      V(v, 2) = s * std::sin(phi);
    }
    return V;
  };
  TriMesh reference = flat;
  reference.V = folded(100.0);  // a seam: the two halves' normals 100° apart at rest
  const Topology t = buildTopology(reference);
  // Folded on to 125° on the same side: 25° from the reference, although the normals are now more than 120° apart.
  CHECK(invertedFaces(reference, t, flatten(folded(125.0))).empty());
  CHECK(invertedFaces(reference, t, flatten(folded(100.0))).empty());
  // Folded back through the flat strip to −30° on the other side: 130° from the reference.
  const std::vector<int> through = invertedFaces(reference, t, flatten(folded(-30.0)));
  CHECK(through.size() == 4);  // the two faces on each side of the fold line's two edges
  // The same strip with a flat reference: 125° is an inversion there.
  const Topology flatTopology = buildTopology(flat);
  CHECK(invertedFaces(flat, flatTopology, flatten(folded(125.0))).size() == 4);
  CHECK(invertedFaces(flat, flatTopology, flatten(folded(100.0))).empty());
}
