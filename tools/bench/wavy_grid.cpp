#include "tools/bench/wavy_grid.h"

#include "core/flatten.h"
#include "core/math_constants.h"

#include <cmath>

namespace jetshell {

Eigen::VectorXd wavyGridPositions(const TriMesh& mesh, bool shear) { return wavyPositions(mesh, shear); }

Eigen::VectorXd wavyPositions(const TriMesh& mesh, bool shear) {
  Eigen::VectorXd x = flatten(mesh.V);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const double px = x[3 * v], py = x[3 * v + 1];
    x[3 * v + 2] += 0.05 * std::sin(6.0 * kPi * px) * std::cos(4.0 * kPi * py);
    if (shear) x[3 * v] += 0.01 * std::sin(2.0 * kPi * py);
  }
  return x;
}

}  // namespace jetshell
