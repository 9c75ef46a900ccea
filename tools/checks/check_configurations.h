// Small meshes and adversarial configurations on which energy terms' derivatives are checked
// (tools/checks/derivative_check.h, `jetshell check-derivatives`, tests/energies/conformance_test.cpp).
//
// Kinds of configuration (every kind except `random` also applies a random rigid motion):
//   random      rest positions + uniform noise of ±0.15 mean edge lengths per coordinate;
//   rotation    a rotation by 90°–180° about a random axis, a translation, and ±0.1 edge lengths of noise;
//   stretch     ×3 along a random in-plane direction, ±0.05 edge lengths of noise;
//   fold        two faces folded back on each other across an interior edge: the angle between their normals
//               is 180° − δ, δ log-uniform in [foldMinDelta, foldMaxDelta] (never 180°: the Kelvin inversion
//               n̄ = m/‖m‖² diverges there, with ‖m‖ = sin(δ/2));
//   degenerate  one face squashed to aspect ratio 1e-3 (altitude / longest edge) in its own plane.
#pragma once

#include "core/mesh.h"
#include "energies/shell/reference_state.h"
#include "core/topology.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace jetshell {

enum class ConfigurationKind { Random, Rotation, Stretch, Fold, Degenerate };
inline constexpr ConfigurationKind kConfigurationKinds[] = {ConfigurationKind::Random, ConfigurationKind::Rotation,
                                                            ConfigurationKind::Stretch, ConfigurationKind::Fold,
                                                            ConfigurationKind::Degenerate};

const char* toString(ConfigurationKind kind);
/// "random" | "rotation" | "stretch" | "fold" | "degenerate"; throws InputError otherwise.
ConfigurationKind configurationKindFromString(const std::string& name);

/// A small reference mesh with its topology and reference state.
struct CheckMesh {
  std::string name;
  TriMesh mesh;
  Topology topology;
  ShellReference reference;
  double meanEdgeLength = 0.0;
};

/// One face and its three edge neighbours (6 vertices, 4 faces: the full bending stencil of face 0), with a
/// curved rest shape (the opposite vertices leave the plane, so B ≠ 0 on face 0).
TriMesh makeBendingStencilPatch();

/// The meshes every check runs on: "patch" (makeBendingStencilPatch) and "grid" (3×2 squares, 12 vertices,
/// 12 faces, bent into a curved rest shape, with boundary and interior stencils).
std::vector<CheckMesh> makeCheckMeshes();

/// Builds the CheckMesh (topology, reference state, mean edge length) of a valid mesh.
CheckMesh makeCheckMesh(std::string name, TriMesh mesh);

struct ConfigurationOptions {
  double foldMinDelta = 1e-3;  // rad: 180° − 0.057°
  double foldMaxDelta = 0.2;   // rad: 180° − 11.5°
  double degenerateAspect = 1e-3;
  double stretch = 3.0;
};

/// What a configuration looks like, to report conditioning next to the errors measured on it.
struct ConfigurationGeometry {
  double minAspectRatio = 0.0;  // min over faces of altitude / longest edge = 2·area / longest edge²
  double maxFoldAngle = 0.0;    // max over interior edges of the angle between the two face normals [rad]
  double maxStretch = 0.0;      // max over faces of the largest principal stretch relative to the reference
};

struct CheckConfiguration {
  ConfigurationKind kind = ConfigurationKind::Random;
  Eigen::VectorXd x;  // 3N positions
  std::string description;
  ConfigurationGeometry geometry;
};

/// A configuration of the given kind on the mesh; the same (mesh, kind, seed) gives the same positions.
CheckConfiguration makeCheckConfiguration(const CheckMesh& mesh, ConfigurationKind kind, std::uint64_t seed,
                                          const ConfigurationOptions& options = {});

ConfigurationGeometry measureGeometry(const CheckMesh& mesh, const Eigen::VectorXd& x);

/// Every vertex p of x (3N) moved to R p + t.
Eigen::VectorXd rigidlyMoved(const Eigen::VectorXd& x, const Eigen::Matrix3d& R, const Eigen::Vector3d& t);

}  // namespace jetshell
