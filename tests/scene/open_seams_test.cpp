// Vertices of one shell that lie on one another with no edge between them (tools/scene/open_seams.h): a garment
// exported as unjoined panels reads as a valid mesh and falls apart at its seams, so the scene reader names it.
#include "tools/scene/open_seams.h"
#include "core/garment_generator.h"
#include "core/mesh_generators.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"
#include "tools/scene/shapes.h"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

using namespace jetshell;

namespace {

OpenSeams seamsOf(const TriMesh& mesh) { return findOpenSeams(mesh, buildTopology(mesh)); }

/// A unit square of two triangles, cut along its diagonal when `cut` (vertices 4 and 5 repeat 0 and 2).
TriMesh squareOfTwo(bool cut) {
  TriMesh m;
  m.V.resize(cut ? 6 : 4, 3);
  m.V.topRows(4) << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  if (cut) m.V.bottomRows(2) << 0, 0, 0, 1, 1, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, cut ? 4 : 0, cut ? 5 : 2, 3;
  return m;
}

}  // namespace

TEST_CASE("open seams: a mesh cut along an edge is found, a joined one and a short edge not", "[scene]") {
  const OpenSeams cut = seamsOf(squareOfTwo(true));
  CHECK(cut.vertices == 4);
  CHECK(cut.pairs == std::vector<std::array<int, 2>>{{0, 4}, {2, 5}});
  CHECK_FALSE(cut.partial);
  CHECK(seamsOf(squareOfTwo(false)).vertices == 0);
  // A sliver whose short edge (1e-5 m) is far below the tolerance (1e-3 of the mean edge): joined, not cut.
  TriMesh sliver;
  sliver.V.resize(3, 3);
  sliver.V << 0, 0, 0, 1e-5, 0, 0, 0, 1, 0;
  sliver.F.resize(1, 3);
  sliver.F << 0, 1, 2;
  const OpenSeams s = seamsOf(sliver);
  CHECK(s.tolerance > 1e-5);
  CHECK(s.vertices == 0);
}

TEST_CASE("open seams: the slit annulus's slit is found, the T-shirt generator's joined panels have none",
          "[scene]") {
  // Columns 0 and nodesPerRing − 1 coincide on every ring: the slit, 2 × rings vertices.
  const OpenSeams slit = seamsOf(makeSlitAnnulus(6.0, 10.0, 5, 21));
  CHECK(slit.vertices == 10);
  REQUIRE(slit.pairs.size() == 5);
  CHECK(slit.pairs.front() == std::array<int, 2>{0, 20});
  // The garment: front and back panels joined at the shoulder and side seams into one mesh.
  CHECK(seamsOf(makeTShirt(2).mesh).vertices == 0);
}

TEST_CASE("open seams: thousands of vertices crowded in one place end the search at its budget", "[scene]") {
  // 300 copies of one triangle, none sharing a vertex: each corner's 300 copies share a cell, 44,850 pairs and
  // 90,000 visits there, against budgets of 4 pairs (3,600 in all) and 64 visits (57,600) a vertex.
  const int copies = 300;
  TriMesh m;
  m.V.resize(3 * copies, 3);
  m.F.resize(copies, 3);
  for (int c = 0; c < copies; ++c) {
    m.V.middleRows(3 * c, 3) << 0, 0, 0, 1, 0, 0, 0, 1, 0;
    m.F.row(c) << 3 * c, 3 * c + 1, 3 * c + 2;
  }
  const OpenSeams s = findOpenSeams(m, buildTopology(m));
  CHECK(s.partial);
  CHECK(s.vertices > 0);
  CHECK(s.vertices <= 3 * copies);
  CHECK_THROWS_WITH(WeldOpenSeams(CreateTriMeshShape(m.V, m.F)),
                    "arrays: cannot weld: too many vertices lie within the tolerance of one another for a search "
                    "of 64 visits a vertex (or a coordinate is over 1e15 tolerances from the origin)");
}

TEST_CASE("open seams: welding joins a cut mesh, and refuses one whose sides face opposite ways", "[scene]") {
  const TriMesh cut = squareOfTwo(true);
  const ShapeHandle welded = WeldOpenSeams(CreateTriMeshShape(cut.V, cut.F));
  CHECK(welded->source == "arrays, 4 vertices welded into 2");
  CHECK(welded->mesh.V == squareOfTwo(false).V);
  CHECK(welded->mesh.F == squareOfTwo(false).F);
  CHECK(seamsOf(welded->mesh).vertices == 0);
  const ShapeHandle joined = CreateTriMeshShape(squareOfTwo(false).V, squareOfTwo(false).F);
  CHECK(WeldOpenSeams(joined) == joined);
  // The second triangle turned over: welded, its diagonal runs the same way in both faces.
  TriMesh flipped = cut;
  flipped.F.row(1) << 4, 3, 5;
  CHECK_THROWS_WITH(WeldOpenSeams(CreateTriMeshShape(flipped.V, flipped.F)), Catch::Contains("oriented against"));
}

TEST_CASE("open seams: a scene names a shape cut where it may be meant to be joined, not a generator's slit",
          "[scene]") {
  using SceneJson = nlohmann::json;
  const SceneJson material = {{"youngsModulus", 1e6}, {"poissonRatio", 0.3}, {"thickness", 0.001},
                              {"volumeDensity", 300}};
  const SceneJson square = {{"type", "shell"},
                            {"name", "square"},
                            {"shape",
                             {{"vertices", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {1, 1, 0}}},
                              {"faces", {{0, 1, 2}, {4, 5, 3}}}}},
                            {"worldFromLocalTransform", {{"translation", {0, 0, 2}}}},
                            {"material", material},
                            {"colliderType", "None"}};
  const SceneJson ring = {{"type", "shell"},
                          {"name", "ring"},
                          {"shape", {{"generator", "slitAnnulus"}, {"innerRadius", 6}, {"outerRadius", 10},
                                     {"rings", 3}, {"nodesPerRing", 11}}},
                          {"material", material},
                          {"colliderType", "None"}};
  const SceneJson analysis = {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}};
  const SceneJson j = {{"actors", {square, ring}}, {"analysis", analysis}};
  const SceneModel model = buildSceneModel(sceneFromJson(j, "."));
  REQUIRE(model.warnings.size() == 1);
  CHECK(model.warnings[0] ==
        "shell actor 'square': 4 vertices of its mesh (arrays) lie on others with no edge between them (within "
        "0.00113807 m, a thousandth of the mean edge), first vertices 0 and 4 (counted from 0) at (0, 0, 2): the "
        "mesh is cut there, and its sides move apart (\"weld\": true in the shape joins them; a slit is meant so)");
  // Welded, the square is one piece: no warning, four vertices, and the source says what was done.
  SceneJson weldedSquare = square;
  weldedSquare["shape"]["weld"] = true;
  const SceneJson w = {{"actors", {weldedSquare}}, {"analysis", analysis}};
  const Scene scene = sceneFromJson(w, ".");
  CHECK(scene.shells[0].shape->source == "arrays, 4 vertices welded into 2");
  const SceneModel welded = buildSceneModel(scene);
  CHECK(welded.warnings.empty());
  CHECK(welded.numVertices() == 4);
}

TEST_CASE("open seams: the garment example's panels, in centimetres, scaled and welded are the T-shirt generator's",
          "[scene]") {
  // examples/meshes/tshirt_panels_cm.obj: the generator's shirt at resolution 2 with its 88 seam vertices written
  // once for each panel, in centimetres.
  const Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/garment_from_obj.json");
  const TriangularMeshShape& shape = *scene.shells.at(0).shape;
  const std::string welded = "tshirt_panels_cm.obj, 176 vertices welded into 88";
  REQUIRE(shape.source.size() > welded.size());
  CHECK(shape.source.substr(shape.source.size() - welded.size()) == welded);
  const TriMesh generated = makeTShirt(2).mesh;
  REQUIRE(shape.mesh.numVertices() == generated.numVertices());
  CHECK((shape.mesh.V - generated.V).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(shape.mesh.F == generated.F);
  // Unwelded, the reader names the seams.
  const ShapeHandle panels =
      CreateTriMeshShape(std::string(JETSHELL_SOURCE_DIR) + "/examples/meshes/tshirt_panels_cm.obj", 0.01);
  const OpenSeams seams = seamsOf(panels->mesh);
  CHECK(seams.vertices == 176);
  CHECK(seams.pairs.size() == 88);
}
