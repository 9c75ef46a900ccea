// What can be known about a scene's solvability before solving it.
//
// Rigid-body modes: a static problem (static or dynamic-relaxation analysis) whose unknowns include a rigid
// translation along an axis (no coordinate along that axis is prescribed) has no equilibrium when the external
// load (applied loads at λ = 1 plus the weight of the actors with gravity) has a net component along it: the
// shell would accelerate away, and Newton only meets a singular system. Rotations are not checked (a load can
// be balanced by a rotated shape, as a pendulum hangs from one point).
//
// Inverted faces: after a solve, faces turned by more than 120° against an edge neighbour, measured from the
// reference's own angle across their edge (the signed angle between the two normals about the edge): an element
// pushed through itself, or folded flat onto its neighbour. A fold of the reference (a garment's seam) that
// closes further as the garment lies flat is not one. Rigid motions of the whole shell turn no face against
// another.
#pragma once

#include "core/mesh.h"
#include "core/topology.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace jetshell {

/// One line per free rigid translation the external load pushes along (empty when there is none, or when the
/// analysis is dynamic: a free shell may move).
std::vector<std::string> unbalancedRigidModes(const Scene& scene, const SceneModel& model);

/// Throws InputError with unbalancedRigidModes' first line when it is not empty.
void checkRigidModes(const Scene& scene, const SceneModel& model);

/// Faces of `mesh` (reference) inverted in the deformed positions x (3N): see the file comment.
std::vector<int> invertedFaces(const TriMesh& mesh, const Topology& topology, const Eigen::VectorXd& x);

}  // namespace jetshell
