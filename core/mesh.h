// Triangle meshes: vertex positions and faces, plus the errors raised for invalid input.
#pragma once

#include <Eigen/Core>

#include <stdexcept>
#include <string>

namespace jetshell {

/// N×3 vertex positions, row-major so that a mesh's positions are one flat 3N vector (x0,y0,z0,x1,...).
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// F×3 vertex indices per triangle, counter-clockwise around the normal.
using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// A triangle mesh in its reference configuration.
struct TriMesh {
  Positions V;
  Faces F;
  int numVertices() const { return static_cast<int>(V.rows()); }
  int numFaces() const { return static_cast<int>(F.rows()); }
};

/// Invalid input (meshes, scenes, parameters). The message names the problem and the element, field or line.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Flat view of positions as a 3N vector.
inline Eigen::Map<const Eigen::VectorXd> flatten(const Positions& V) {
  return Eigen::Map<const Eigen::VectorXd>(V.data(), V.size());
}
inline Positions unflatten(const Eigen::VectorXd& x) {
  return Eigen::Map<const Positions>(x.data(), x.size() / 3, 3);
}

}  // namespace jetshell
