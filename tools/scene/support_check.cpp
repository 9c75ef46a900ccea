#include "tools/scene/support_check.h"

#include <array>
#include <cmath>
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
  auto normal = [&](int f, bool deformed) -> Eigen::Vector3d {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      p[k] = deformed ? Eigen::Vector3d(x.segment<3>(3 * v)) : Eigen::Vector3d(mesh.V.row(v).transpose());
    }
    return (p[1] - p[0]).cross(p[2] - p[0]);
  };
  // Turned against a neighbour: the unit normals across an edge make more than 120° (cos < −1/2).
  auto turned = [&](int f, int g, bool deformed) {
    const Eigen::Vector3d a = normal(f, deformed), b = normal(g, deformed);
    const double n = a.norm() * b.norm();
    return !(n > 0.0) || a.dot(b) < -0.5 * n;
  };
  std::vector<char> mark(static_cast<std::size_t>(nf), 0);
  for (int f = 0; f < nf; ++f)
    for (int i = 0; i < 3; ++i) {
      const int g = topology.faceNeighbors(f, i);
      if (g > f && turned(f, g, true) && !turned(f, g, false)) mark[static_cast<std::size_t>(f)] = mark[static_cast<std::size_t>(g)] = 1;
    }
  std::vector<int> out;
  for (int f = 0; f < nf; ++f)
    if (mark[static_cast<std::size_t>(f)]) out.push_back(f);
  return out;
}

}  // namespace jetshell
