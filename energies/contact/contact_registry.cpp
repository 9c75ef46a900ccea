#include "energies/contact/contact_registry.h"

#include "energies/contact/point_cloud_contact.h"
#include "energies/contact/volume_contact.h"

namespace jetshell {
namespace {

/// The mesh's centre and size (bounding-box diagonal).
std::pair<Eigen::Vector3d, double> centreAndSize(const TriMesh& mesh) {
  const Eigen::Vector3d lo = mesh.V.colwise().minCoeff(), hi = mesh.V.colwise().maxCoeff();
  return {0.5 * (lo + hi), (hi - lo).norm()};
}

ContactParams scaledParams(double size) {
  ContactParams c;
  c.penaltyStiffness = 1e3;
  c.activationDistance = 0.15 * size;
  c.smoothingDistance = 0.1 * size;
  c.huntCrossleyDamping = 0.5;
  c.frictionCoefficient = 0.4;
  c.frictionSlipVelocity = 0.1 * size;  // ε_v = 0.1·size with Δt = 1
  return c;
}

VolumeContactTerms volumeTerms(const TermSetup& s, ContactQuadrature quadrature, VolumeColliderPtr collider) {
  const auto [centre, size] = centreAndSize(s.mesh);
  VolumeContactTerms t = makeVolumeContactTerms(sampleContactPoints(s.mesh, s.reference.area, quadrature),
                                                s.mesh.numVertices(), std::move(collider), scaledParams(size));
  t.state->beginStep(flatten(s.mesh.V), 0.0, 1.0);  // lagged at rest: friction and damping see a step
  return t;
}

VolumeColliderPtr tiltedPlane(const TriMesh& mesh) {
  const auto [centre, size] = centreAndSize(mesh);
  RigidPath path;
  path.origin = centre;
  path.rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0.3, -0.2, 1.0));
  return std::make_shared<VolumeCollider>("plane", makePlaneShape(), path);
}

VolumeColliderPtr offsetSphere(const TriMesh& mesh) {
  const auto [centre, size] = centreAndSize(mesh);
  RigidPath path;
  path.origin = centre - Eigen::Vector3d(0.1, 0.2, 0.5) * size;
  return std::make_shared<VolumeCollider>("sphere", makeSphereShape(0.5 * size), path);
}

VolumeColliderPtr movingCapsule(const TriMesh& mesh) {
  const auto [centre, size] = centreAndSize(mesh);
  RigidPath path;
  path.origin = centre - Eigen::Vector3d(0.0, 0.0, 0.3) * size;
  path.rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), Eigen::Vector3d(1.0, 0.2, 0.1));
  path.velocity = Eigen::Vector3d(0.02, 0.0, 0.05) * size;
  path.angularVelocity = Eigen::Vector3d(0.0, 0.1, 0.05);
  return std::make_shared<VolumeCollider>("capsule", makeCapsuleShape(0.3 * size, 0.4 * size), path);
}

/// Every vertex pair at least one fifth of the mesh size apart at rest, touching below 0.45·size.
std::pair<StencilTable, std::shared_ptr<PointPairData>> allPairs(const TriMesh& mesh, bool lagFriction) {
  const auto [centre, size] = centreAndSize(mesh);
  const ContactParams c = scaledParams(size);
  StencilTable table{2, {}};
  auto data = std::make_shared<PointPairData>();
  data->slipRegularization = 0.1 * size;
  for (int i = 0; i < mesh.numVertices(); ++i)
    for (int j = i + 1; j < mesh.numVertices(); ++j) {
      const Eigen::Vector3d diff = mesh.V.row(i) - mesh.V.row(j);
      if (diff.norm() < 0.2 * size) continue;
      const double D = 0.45 * size;
      const double p = D - diff.norm();
      if (lagFriction && p <= 0.0) continue;
      table.ids.insert(table.ids.end(), {i, j});
      data->contactDistance.push_back(D);
      data->weight.push_back(c.penaltyStiffness * 0.01 * size * size);
      data->smoothing.push_back(c.smoothingDistance);
      data->friction.push_back(c.frictionCoefficient);
      data->frictionForce.push_back(c.frictionCoefficient * 10.0 * (1.0 + i));
      data->normal.push_back(diff.normalized());
      data->startDifference.push_back(diff);
    }
  return {table, data};
}

}  // namespace

std::vector<RegisteredTerm> contactRegistryEntries() {
  using S = const TermSetup&;
  return {
      {"contact_penalty", "shell vs tilted plane: ramp penalty at vertices",
       [](S s) { return volumeTerms(s, ContactQuadrature::Vertices, tiltedPlane(s.mesh)).penalty; }},
      {"contact_penalty_sphere_faces", "shell vs sphere: ramp penalty at three face quadrature points",
       [](S s) { return volumeTerms(s, ContactQuadrature::FaceThreePoint, offsetSphere(s.mesh)).penalty; }},
      {"contact_penalty_moving_capsule", "shell vs translating, rotating capsule: penalty at face centroids",
       [](S s) { return volumeTerms(s, ContactQuadrature::FaceCentroids, movingCapsule(s.mesh)).penalty; }},
      {"contact_damping", "Hunt-Crossley normal damping potential vs tilted plane (lagged at rest)",
       [](S s) { return volumeTerms(s, ContactQuadrature::Vertices, tiltedPlane(s.mesh)).damping; }},
      {"contact_friction", "regularized Coulomb friction vs tilted plane (normal forces lagged at rest)",
       [](S s) { return volumeTerms(s, ContactQuadrature::Vertices, tiltedPlane(s.mesh)).friction; }},
      {"pointcloud_penalty", "point-cloud pair penalty over every pair of vertices",
       [](S s) {
         auto [table, data] = allPairs(s.mesh, false);
         return makePointPairPenaltyTerm("pointcloud_penalty", table, data, s.mesh.numVertices());
       }},
      {"pointcloud_friction", "point-cloud pair friction (lagged at rest)",
       [](S s) {
         auto [table, data] = allPairs(s.mesh, true);
         return makePointPairFrictionTerm("pointcloud_friction", table, data, s.mesh.numVertices());
       }},
  };
}

}  // namespace jetshell
