#include "tools/scene/support_check.h"

#include "core/math_constants.h"

#include <array>
#include <cmath>
#include <limits>
#include <sstream>

namespace jetshell {

std::vector<std::string> unbalancedRigidModes(const Scene& scene, const SceneModel& model) {
  std::vector<std::string> out;
  if (scene.analysis.type == AnalysisType::Dynamic) return out;
  std::array<bool, 3> supported{false, false, false};
  for (const PrescribedCoordinate& c : model.prescribed) supported[static_cast<std::size_t>(c.component)] = true;
  Eigen::Vector3d net = Eigen::Vector3d::Zero();
  double scale = 0.0;  // Σ |nodal force| components: the round-off yardstick of the net force
  for (Eigen::Index v = 0; v < model.appliedForces.size() / 3; ++v) {
    net += model.appliedForces.segment<3>(3 * v);
    scale += model.appliedForces.segment<3>(3 * v).cwiseAbs().sum();
  }
  for (std::size_t a = 0; a < scene.shells.size() && a < model.actors.size(); ++a) {
    const ShellActorParams& actor = scene.shells[a];
    if (!actor.hasGravity || !(actor.material.density > 0.0)) continue;
    const ActorBlock& block = model.actors[a];
    double area = 0.0;
    for (int f = block.firstFace; f < block.firstFace + block.numFaces; ++f) {
      const Eigen::Vector3d p0 = model.world.V.row(model.world.F(f, 0)).transpose();
      const Eigen::Vector3d p1 = model.world.V.row(model.world.F(f, 1)).transpose();
      const Eigen::Vector3d p2 = model.world.V.row(model.world.F(f, 2)).transpose();
      area += 0.5 * (p1 - p0).cross(p2 - p0).norm();
    }
    const Eigen::Vector3d weight = actor.material.density * area * scene.gravity;
    net += weight;
    scale += weight.cwiseAbs().sum();
  }
  static const char* axes[3] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c) {
    if (supported[static_cast<std::size_t>(c)] || !(std::abs(net[c]) > 1e-9 * scale)) continue;
    std::ostringstream s;
    s << "/actors: " << toString(scene.analysis.type) << " analysis without supports along " << axes[c]
      << " (no fixed coordinate in " << axes[c] << ") under a net external " << axes[c] << " force of " << net[c]
      << " N (loads and weight): the shell is free to move as a rigid body (rigid-body mode) and no equilibrium"
      << " exists; fix some vertices in " << axes[c] << " (\"fixed\") or use a dynamic analysis";
    out.push_back(s.str());
  }
  return out;
}

void checkRigidModes(const Scene& scene, const SceneModel& model) {
  const std::vector<std::string> modes = unbalancedRigidModes(scene, model);
  if (!modes.empty()) throw InputError(modes.front());
}

std::vector<int> invertedFaces(const TriMesh& mesh, const Topology& topology, const Eigen::VectorXd& x) {
  const int nf = mesh.numFaces();
  auto point = [&](int v, bool deformed) -> Eigen::Vector3d {
    return deformed ? Eigen::Vector3d(x.segment<3>(3 * v)) : Eigen::Vector3d(mesh.V.row(v).transpose());
  };
  auto normal = [&](int f, bool deformed) -> Eigen::Vector3d {
    const Eigen::Vector3d p0 = point(mesh.F(f, 0), deformed);
    return (point(mesh.F(f, 1), deformed) - p0).cross(point(mesh.F(f, 2), deformed) - p0);
  };
  // The signed angle from f's normal to g's, turning about their shared edge (a → b as f lists it), in [−π, π];
  // NaN when a face or the edge has no direction.
  auto dihedral = [&](int f, int g, int a, int b, bool deformed) {
    const Eigen::Vector3d u = normal(f, deformed), w = normal(g, deformed);
    const Eigen::Vector3d e = point(b, deformed) - point(a, deformed);
    const double length = e.norm();
    const double scale = u.norm() * w.norm() * length;
    if (!(scale > 0.0) || !std::isfinite(scale)) return std::numeric_limits<double>::quiet_NaN();
    return std::atan2(e.dot(u.cross(w)) / length, u.dot(w));
  };
  // Turned against a neighbour: the angle between the two faces' normals changed by more than 120° from the
  // reference's across their edge. On a flat reference that is the angle between the normals itself; on a curved
  // one (a garment's seams, a cylinder) the reference's own angle is not counted, so a seam folded flat as the
  // garment lies down is not an inversion, while a face pushed through its neighbour is.
  constexpr double kTurnLimit = 2.0 * kPi / 3.0;
  std::vector<char> mark(static_cast<std::size_t>(nf), 0);
  for (int f = 0; f < nf; ++f)
    for (int i = 0; i < 3; ++i) {
      const int g = topology.faceNeighbors(f, i);
      if (g <= f) continue;
      const int a = mesh.F(f, (i + 1) % 3), b = mesh.F(f, (i + 2) % 3);
      const double reference = dihedral(f, g, a, b, false);
      if (std::isnan(reference)) continue;  // degenerate in the reference: nothing to compare with
      const double turned = dihedral(f, g, a, b, true);
      // The change, wrapped into [−π, π]; a face without a normal now counts as turned.
      const double change = std::remainder(turned - reference, 2.0 * kPi);
      if (!(std::abs(change) <= kTurnLimit)) mark[static_cast<std::size_t>(f)] = mark[static_cast<std::size_t>(g)] = 1;
    }
  std::vector<int> out;
  for (int f = 0; f < nf; ++f)
    if (mark[static_cast<std::size_t>(f)]) out.push_back(f);
  return out;
}

}  // namespace jetshell
