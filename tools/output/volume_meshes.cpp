#include "tools/output/volume_meshes.h"

#include "core/mesh_generators.h"
#include "energies/contact/sdf_grid.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

/// A box of half-extents h with edges and corners rounded by r: each face a grid whose lines crowd into the
/// rounded bands, each grid point moved from the sharp box onto the rounded one (towards the nearest point of the
/// core box, of half-extents h − r, to the distance r). Faces meet where their edge points land on the same arc.
TriMesh roundedBox(const Eigen::Vector3d& h, double r) {
  constexpr int kBand = 4;  // grid intervals across each rounded band of a face (half a quarter circle)
  const Eigen::Vector3d core = h - Eigen::Vector3d::Constant(r);
  auto coordinates = [&](int axis) {
    std::vector<double> c;
    for (int k = kBand; k >= 0; --k) c.push_back(-core[axis] - r * k / kBand);
    for (int k = 1; k <= 4; ++k) c.push_back(-core[axis] + 2.0 * core[axis] * k / 4);
    for (int k = 1; k <= kBand; ++k) c.push_back(core[axis] + r * k / kBand);
    c.erase(std::unique(c.begin(), c.end()), c.end());  // a band or the core of no width
    return c;
  };
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> triangles;
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // (u, v, axis) right-handed: the face's normal is +axis
      const std::vector<double> cu = coordinates(u), cv = coordinates(v);
      const int first = static_cast<int>(points.size()), nu = static_cast<int>(cu.size());
      for (double b : cv)
        for (double a : cu) {
          Eigen::Vector3d p;
          p[axis] = side * h[axis];
          p[u] = a;
          p[v] = b;
          const Eigen::Vector3d nearest = p.cwiseMax(-core).cwiseMin(core);
          points.push_back(nearest + r * (p - nearest).normalized());
        }
      for (int j = 0; j + 1 < static_cast<int>(cv.size()); ++j)
        for (int i = 0; i + 1 < nu; ++i) {
          const int a = first + j * nu + i, b = a + 1, c = a + nu, d = c + 1;
          if (side > 0) triangles.insert(triangles.end(), {{a, b, d}, {a, d, c}});
          else triangles.insert(triangles.end(), {{a, d, b}, {a, c, d}});
        }
    }
  TriMesh m;
  m.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t k = 0; k < points.size(); ++k) m.V.row(static_cast<Eigen::Index>(k)) = points[k].transpose();
  m.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t k = 0; k < triangles.size(); ++k) m.F.row(static_cast<Eigen::Index>(k)) = triangles[k].transpose();
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
      if (volume.edgeRadius > 0.0) {
        m = roundedBox(volume.halfExtents, volume.edgeRadius);
        break;
      }
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
