// A scene resolved onto one set of unknowns: every shell actor's reference mesh placed in world coordinates and
// stacked into one mesh (actor a owns vertices [firstVertex, firstVertex + numVertices)), selections turned
// into vertex ids, loads into a nodal force vector and end moments along ordered chains of boundary edges, fixed
// conditions into prescribed coordinates, probes into vertices. This is what the solvers consume; nothing here
// solves.
#pragma once

#include "tools/scene/scene.h"

#include "core/mesh.h"
#include "core/topology.h"
#include "energies/end_moment_load.h"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace jetshell {

struct ActorBlock {
  int firstVertex = 0, numVertices = 0;
  int firstFace = 0, numFaces = 0;
  /// The actor's own vertices (world reference positions, the rows firstVertex … of the stacked mesh) and its
  /// faces over them (ids 0 … numVertices − 1): what the actor's terms are built on (core/vertex_block_term.h), so
  /// that each actor costs its own size, not the scene's.
  TriMesh mesh;
  Topology topology;
  /// The actor's vertices (its own ids, size numVertices) whose boundary edges are clamped against rotation;
  /// empty when none.
  std::vector<char> clampedVertices;
};

/// A prescribed coordinate: x[3·vertex + component] = value(s), where s is the load factor λ in statics and
/// the time t in dynamics (the functions already include the λ(t) ramp). Constant when `value` is null.
struct PrescribedCoordinate {
  int vertex = 0;
  int component = 0;
  double constant = 0.0;
  std::function<double(double)> value;
};

struct ResolvedProbe {
  std::string name;
  int actor = 0;
  int vertex = 0;  // stacked id
  Eigen::Vector3d reference = Eigen::Vector3d::Zero();  // the vertex's reference position (world)
};

struct SceneModel {
  TriMesh world;                    // all shell actors, stacked, reference configuration in world coordinates
  std::vector<ActorBlock> actors;   // one per Scene::shells entry
  Eigen::VectorXd appliedForces;    // 3N, nodal forces at λ = 1
  std::vector<EndMomentLoad> endMoments;  // the moment loads, each along its chain of boundary edges (stacked ids)
  std::vector<PrescribedCoordinate> prescribed;  // sorted by (vertex, component); later conditions win
  std::vector<ResolvedProbe> probes;
  /// What resolved but may not be what was meant (`run --check` prints them, a run reports them with its
  /// warnings): a `nearest` point farther than one mean edge length from the vertex it picked; contact samples
  /// too sparse for the colliders they must catch (tools/scene/contact_coverage.h).
  std::vector<std::string> warnings;

  int numVertices() const { return world.numVertices(); }
  /// The load factor at time t in dynamics: min(1, t / loadRampTime), or 1 without a ramp.
  std::function<double(double)> loadFactorAtTime;
};

/// Resolves a validated scene. Throws InputError naming the field when a selection picks nothing or an index is
/// out of range, when an edgeLength load finds no boundary edge between its vertices, when a moment load's
/// vertices are not one open chain of boundary edges, or when a probe does not pick exactly one vertex.
SceneModel buildSceneModel(const Scene& scene);

/// The rest positions of each actor's vertices in world coordinates (N_a × 3).
Positions worldPositions(const ShellActorParams& actor);

}  // namespace jetshell
