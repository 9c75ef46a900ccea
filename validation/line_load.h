// Consistent nodal forces of a line load (force per unit reference length along a chain of boundary vertices).
#pragma once

#include "core/mesh.h"

#include <Eigen/Core>

#include <vector>

namespace jetshell::validation {

/// Nodal forces (size 3N) of the uniform line load forcePerLength along the polyline chain (vertex ids in
/// order along the edge, reference positions): each vertex gets the load times half the reference length of
/// each chain segment it ends, so the total is forcePerLength × chain length whatever the mesh. Throws
/// InputError for fewer than two vertices or an id out of range.
Eigen::VectorXd consistentLineLoad(const TriMesh& mesh, const std::vector<int>& chain,
                                   const Eigen::Vector3d& forcePerLength);

/// Reference length of the polyline chain.
double chainLength(const TriMesh& mesh, const std::vector<int>& chain);

}  // namespace jetshell::validation
