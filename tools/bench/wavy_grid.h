// The element benchmarks' test shape (`jetshell bench elements`): the flat unit square of n × n squares (2 n²
// faces, makeRectangleGrid) as reference, deformed into waves z = 0.05 sin(6πx) cos(4πy), and with `shear` also
// moved in x by 0.01 sin(2πy), so that no edge keeps its reference length. One place for every bench that reads it.
// (wavyPositions: the same displacement on any mesh.)
#pragma once

#include "core/mesh.h"

#include <Eigen/Core>

namespace jetshell {

/// The deformed positions (3N) of `mesh`, a grid from makeRectangleGrid over the unit square.
Eigen::VectorXd wavyGridPositions(const TriMesh& mesh, bool shear);

/// Any mesh (`bench elements --garment`): its reference positions moved by the same waves (and shear), added to
/// z and x, so a curved or folded rest shape (a garment's two panels) keeps its form; on the flat grid (z = 0)
/// the same bits as wavyGridPositions, which calls it.
Eigen::VectorXd wavyPositions(const TriMesh& mesh, bool shear);

}  // namespace jetshell
