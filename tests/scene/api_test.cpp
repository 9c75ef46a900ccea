// The C++ API example of SCENES.md, kept compiling and running here.
#include "core/mesh_generators.h"
#include "tools/scene/generated_shapes.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <catch2/catch.hpp>

using namespace jetshell;

TEST_CASE("api: the SCENES.md example builds a valid scene") {
  // --- SCENES.md: C++ API ---
  Scene scene;
  scene.gravity = {0, 0, -9.81};

  ShellActorParams cloth;
  cloth.name = "cloth";
  cloth.shape = makeRectangleShape(1.0, 1.0, 20, 20);  // or CreateTriMeshShape("cloth.obj") / (V, F)
  cloth.material = ShellMaterialParamsFrom3dIsotropic(1e6, 0.3, 300.0, 0.0005);
  cloth.material.massDampingCoefficient = 0.2;
  cloth.colliderType = ColliderType::None;
  const int actor = scene.addShellActor(cloth);

  FixedCondition pins;
  pins.actor = actor;
  pins.select = {VertexSelector{}, VertexSelector{}};
  pins.select[0].nearest = Eigen::Vector3d(0, 1, 0);
  pins.select[1].nearest = Eigen::Vector3d(1, 1, 0);
  scene.fixed.push_back(pins);

  Probe corner;
  corner.name = "freeCorner";
  corner.actor = actor;
  corner.select = {VertexSelector{}};
  corner.select[0].nearest = Eigen::Vector3d(1, 0, 0);
  scene.probes.push_back(corner);

  scene.analysis.type = AnalysisType::Dynamic;
  scene.analysis.timeStep = 1.0 / 60.0;
  scene.analysis.duration = 2.0;
  validate(scene);
  // --- end ---
  const SceneModel model = buildSceneModel(scene);
  CHECK(model.numVertices() == 21 * 21);
  CHECK(model.prescribed.size() == 6);
  REQUIRE(model.probes.size() == 1);
  CHECK(model.probes[0].vertex == 20);
}

TEST_CASE("api: parameters are validated with the field named") {
  Scene scene;
  ShellActorParams p;
  CHECK_THROWS_WITH(scene.addShellActor(p),
                    "shell actor 'shell0'.shape: missing (required; create it with CreateTriMeshShape)");
  p.shape = makeRectangleShape(1, 1, 1, 1);
  p.material.density = -1;
  CHECK_THROWS_WITH(scene.addShellActor(p), "shell actor 'shell0'.material.density = -1: must be finite and >= 0");
  p.material.density = 1;
  p.pointCloudCollider.radius = 0;
  CHECK_THROWS_WITH(scene.addShellActor(p),
                    "shell actor 'shell0'.pointCloudCollider.radius = 0: must be finite and > 0");
  p.pointCloudCollider.radius = 0.01;
  CHECK(scene.addShellActor(p) == 0);
  CHECK(scene.shells[0].name == "shell0");
  p.name = "shell0";
  CHECK_THROWS_WITH(scene.addShellActor(p), "shell actor 'shell0': the name is already used by another shell actor");
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(1e6, 0.5, 1, 1),
                    "ShellMaterialParamsFrom3dIsotropic.poissonRatio = 0.5: must lie in (-1, 0.5)");
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(1e6, 0.3, 1, 0),
                    "ShellMaterialParamsFrom3dIsotropic.thickness = 0: must be finite and > 0");
  CHECK_THROWS_WITH(ShellMaterialParamsFrom3dIsotropic(1e6, 0.3, 1, 1e-200),
                    Catch::StartsWith("ShellMaterialParamsFrom3dIsotropic: youngsModulus 1e+06 and thickness 1e-200 "
                                      "give a membrane stiffness mu = 3.84615e-195 N/m and a bending stiffness "
                                      "beta = 0 N m"));
  Positions V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  Faces F(1, 3);
  F << 0, 1, 2;
  CHECK_THROWS_WITH(CreateTriMeshShape(V, F), Catch::StartsWith("mesh: face 0 (0, 1, 2) is degenerate"));
  VolumeActorParams sphere;
  sphere.kind = VolumeActorParams::Kind::Sphere;
  sphere.radius = -1;
  CHECK_THROWS_WITH(scene.addVolumeActor(sphere), "volume actor 'sphere0'.radius = -1: must be finite and > 0");
  // Shell actor defaults are the spec's.
  const ShellActorParams d;
  CHECK(d.colliderType == ColliderType::PointCloud);
  CHECK(d.hasGravity);
  CHECK(d.material.membraneLambda == 300.0);
  CHECK(d.material.bendingBeta == 7e-5);
  CHECK(d.contact.penaltyStiffness == 1e9);
  CHECK(d.pointCloudCollider.radius == 0.01);
  CHECK(d.worldFromLocalTransform.rotation.w() == 1.0);
}
