#include "tools/scene/scene_problem.h"

#include "tools/scene/volume_colliders.h"

namespace jetshell {
namespace {

ContactQuadrature quadratureOf(ActorBoundaryElementType t) {
  switch (t) {
    case ActorBoundaryElementType::FaceCentroids: return ContactQuadrature::FaceCentroids;
    case ActorBoundaryElementType::FaceThreePoint: return ContactQuadrature::FaceThreePoint;
    case ActorBoundaryElementType::Default:
    case ActorBoundaryElementType::Vertices: return ContactQuadrature::Vertices;
  }
  return ContactQuadrature::Vertices;
}

}  // namespace

ShellProblem shellProblemFromScene(const Scene& scene, const SceneModel& model) {
  ShellProblem p;
  p.mesh = model.world;
  p.material = scene.shells[0].material;
  p.hasGravity = scene.shells[0].hasGravity;
  p.gravity = scene.gravity;
  for (const PrescribedCoordinate& c : model.prescribed) {
    if (c.value) p.prescribed.fix(c.vertex, c.component, TimeFunction(c.value));
    else p.prescribed.fix(c.vertex, c.component, c.constant);
  }
  if (model.appliedForces.cwiseAbs().maxCoeff() > 0.0) p.nodalForces = model.appliedForces;
  p.endMoments = model.endMoments;
  // Every shell actor with its own material, gravity flag, clamps and contact settings.
  for (std::size_t a = 0; a < scene.shells.size(); ++a) {
    const ShellActorParams& s = scene.shells[a];
    const ActorBlock& b = model.actors[a];
    ShellActorPart part;
    part.name = s.name;
    part.mesh = b.mesh;
    part.firstVertex = b.firstVertex;
    part.material = s.material;
    part.hasGravity = s.hasGravity;
    part.clampedVertices = b.clampedVertices;
    part.contact = s.contact;
    part.contactQuadrature = quadratureOf(s.contactElementType);
    part.pointCloud = s.colliderType == ColliderType::PointCloud;
    part.pointCloudCollider = s.pointCloudCollider;
    p.actors.push_back(std::move(part));
  }
  SdfShapes grids;  // one shape per grid file, however many actors name it
  for (const VolumeActorParams& v : scene.volumes) p.volumes.push_back({makeVolumeCollider(v, &grids), v.contact});
  return p;
}

}  // namespace jetshell
