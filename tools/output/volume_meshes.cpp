#include "tools/output/volume_meshes.h"

#include "core/mesh_generators.h"
#include "energies/contact/sdf_grid.h"

#include <cmath>

namespace jetshell {
namespace {

TriMesh box() {
  TriMesh m;
  m.V.resize(8, 3);
  for (int k = 0; k < 8; ++k) m.V.row(k) << (k & 1 ? 1 : -1), (k & 2 ? 1 : -1), (k & 4 ? 1 : -1);
  m.F.resize(12, 3);
  m.F << 0, 2, 3, 0, 3, 1,  // -z
      4, 5, 7, 4, 7, 6,     // +z
      0, 1, 5, 0, 5, 4,     // -y
      2, 6, 7, 2, 7, 3,     // +y
      0, 4, 6, 0, 6, 2,     // -x
      1, 3, 7, 1, 7, 5;     // +x
  return m;
}

TriMesh sphere() {
  // Two hemispheres (the lower one mirrored and re-oriented) sharing the equator's positions.
  const TriMesh top = makeHemisphere(1.0, 8, 24);
  TriMesh m;
  m.V.resize(2 * top.V.rows(), 3);
  m.V.topRows(top.V.rows()) = top.V;
  m.V.bottomRows(top.V.rows()) = top.V;
  m.V.bottomRows(top.V.rows()).col(2) *= -1.0;
  m.F.resize(2 * top.F.rows(), 3);
  m.F.topRows(top.F.rows()) = top.F;
  for (Eigen::Index f = 0; f < top.F.rows(); ++f)
    m.F.row(top.F.rows() + f) << top.F(f, 0) + top.V.rows(), top.F(f, 2) + top.V.rows(), top.F(f, 1) + top.V.rows();
  return m;
}

}  // namespace

TriMesh volumeSurface(const VolumeActorParams& volume, double planeHalfSize, const Eigen::Vector3d& hint) {
  TriMesh m;
  const RigidTransform& T = volume.worldFromLocalTransform;
  switch (volume.kind) {
    case VolumeActorParams::Kind::Plane: {
      m = makeRectangleGrid(2 * planeHalfSize, 2 * planeHalfSize, 1, 1);
      const Eigen::Vector3d local = T.rotation.inverse() * (hint - T.translation);
      for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
        m.V(v, 0) += local.x() - planeHalfSize;
        m.V(v, 1) += local.y() - planeHalfSize;
      }
      break;
    }
    case VolumeActorParams::Kind::Box:
      m = box();
      for (Eigen::Index v = 0; v < m.V.rows(); ++v) m.V.row(v) = m.V.row(v).cwiseProduct(volume.halfExtents.transpose());
      break;
    case VolumeActorParams::Kind::Sphere:
      m = sphere();
      m.V *= volume.radius;
      break;
    case VolumeActorParams::Kind::Capsule: {  // two hemispherical caps and the cylinder between them
      const TriMesh caps = sphere();
      const TriMesh side = makeCylinder(1.0, 1.0, 2.0 * 3.14159265358979323846, 24, 2);
      m.V.resize(caps.V.rows() + side.V.rows(), 3);
      m.F.resize(caps.F.rows() + side.F.rows(), 3);
      for (Eigen::Index v = 0; v < caps.V.rows(); ++v) {
        m.V.row(v) = volume.radius * caps.V.row(v);
        m.V(v, 2) += (v < caps.V.rows() / 2 ? 1.0 : -1.0) * volume.halfLength;
      }
      for (Eigen::Index v = 0; v < side.V.rows(); ++v)  // cylinder axis y ∈ [0, 1] -> z ∈ [−L, L]
        m.V.row(caps.V.rows() + v) << volume.radius * side.V(v, 0), volume.radius * side.V(v, 2),
            volume.halfLength * (2.0 * side.V(v, 1) - 1.0);
      m.F.topRows(caps.F.rows()) = caps.F;
      m.F.bottomRows(side.F.rows()) = side.F.array() + static_cast<int>(caps.V.rows());
      break;
    }
    case VolumeActorParams::Kind::SdfGrid: {  // the grid's bounding box
      const Eigen::AlignedBox3d b = volume.sdfShape ? volume.sdfBox : sdfGridBox(readSdfGrid(volume.sdfFile));
      const Eigen::Vector3d half = 0.5 * b.sizes();
      m = box();
      for (Eigen::Index v = 0; v < m.V.rows(); ++v)
        m.V.row(v) = (b.center() + m.V.row(v).transpose().cwiseProduct(half)).transpose();
      break;
    }
  }
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) m.V.row(v) = T.apply(Eigen::Vector3d(m.V.row(v))).transpose();
  return m;
}

}  // namespace jetshell
