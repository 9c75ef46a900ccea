#include "tools/checks/check_configurations.h"

#include "core/math_constants.h"
#include "core/mesh_generators.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>

namespace jetshell {
namespace {

Eigen::Vector3d vertex(const Eigen::VectorXd& x, int v) { return x.segment<3>(3 * v); }

Eigen::Matrix3d randomRotation(std::mt19937_64& rng, double minAngle, double maxAngle) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
  axis.normalize();
  const double angle = std::uniform_real_distribution<double>(minAngle, maxAngle)(rng);
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

Eigen::Vector3d randomTranslation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return {u(rng), u(rng), u(rng)};
}

void addNoise(Eigen::VectorXd& x, double amplitude, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += u(rng);
}

std::string degrees(double rad) {
  std::ostringstream s;
  s.precision(4);
  s << rad * 180.0 / kPi << " deg";
  return s.str();
}

/// Rotates the vertex opposite edge e in its second face about the edge so that the two faces' normals make
/// the angle π − δ: the faces lie almost on each other without passing through.
void foldAcrossEdge(const CheckMesh& m, int e, double delta, double side, Eigen::VectorXd& x) {
  const Topology& t = m.topology;
  const int a = t.edges(e, 0), b = t.edges(e, 1);
  auto opposite = [&](int f) {
    for (int k = 0; k < 3; ++k) {
      const int v = m.mesh.F(f, k);
      if (v != a && v != b) return v;
    }
    return -1;
  };
  const int c = opposite(t.edgeFaces(e, 0)), d = opposite(t.edgeFaces(e, 1));
  const Eigen::Vector3d pa = vertex(x, a);
  const Eigen::Vector3d u = (vertex(x, b) - pa).normalized();
  auto perpendicular = [&](int v) {
    const Eigen::Vector3d r = vertex(x, v) - pa;
    return Eigen::Vector3d(r - r.dot(u) * u);
  };
  const Eigen::Vector3d sA = perpendicular(c).normalized();
  const Eigen::Vector3d rd = perpendicular(d);
  const double along = (vertex(x, d) - pa).dot(u);
  // In the plane ⟂ u, flat faces have d's direction at −sA; folded back completely at +sA.
  const Eigen::Vector3d sB = std::cos(delta) * sA + side * std::sin(delta) * u.cross(sA);
  x.segment<3>(3 * d) = pa + along * u + rd.norm() * sB;
}

/// Moves one vertex of face f within the face's plane to altitude aspect·|opposite edge| over that edge.
void squashFace(const CheckMesh& m, int f, int k, double aspect, Eigen::VectorXd& x) {
  const int v = m.mesh.F(f, k), p = m.mesh.F(f, (k + 1) % 3), q = m.mesh.F(f, (k + 2) % 3);
  const Eigen::Vector3d pp = vertex(x, p), pq = vertex(x, q), pv = vertex(x, v);
  const Eigen::Vector3d u = (pq - pp).normalized();
  const double base = (pq - pp).norm();
  const Eigen::Vector3d r = pv - pp;
  // Keep the foot of the altitude, clamped inside the base so the longest edge stays the base.
  const double foot = std::clamp(r.dot(u), 0.2 * base, 0.8 * base);
  const Eigen::Vector3d up = (r - r.dot(u) * u).normalized();
  x.segment<3>(3 * v) = pp + foot * u + aspect * base * up;
}

}  // namespace

const char* toString(ConfigurationKind kind) {
  switch (kind) {
    case ConfigurationKind::Random: return "random";
    case ConfigurationKind::Rotation: return "rotation";
    case ConfigurationKind::Stretch: return "stretch";
    case ConfigurationKind::Fold: return "fold";
    case ConfigurationKind::Degenerate: return "degenerate";
  }
  return "?";
}

ConfigurationKind configurationKindFromString(const std::string& name) {
  for (ConfigurationKind k : kConfigurationKinds)
    if (name == toString(k)) return k;
  throw InputError("configuration kind '" + name + "' is not one of random, rotation, stretch, fold, degenerate");
}

TriMesh makeBendingStencilPatch() {
  TriMesh m;
  m.V.resize(6, 3);
  m.V << 0.0, 0.0, 0.0,  //
      1.0, 0.0, 0.0,     //
      0.4, 0.9, 0.0,     //
      1.3, 0.95, 0.12,   // across edge 0 (1, 2)
      -0.55, 0.8, -0.1,  // across edge 1 (2, 0)
      0.55, -0.85, 0.15;  // across edge 2 (0, 1)
  m.F.resize(4, 3);
  m.F << 0, 1, 2,  //
      2, 1, 3,     //
      0, 2, 4,     //
      1, 0, 5;
  return m;
}

CheckMesh makeCheckMesh(std::string name, TriMesh mesh) {
  CheckMesh c;
  c.name = std::move(name);
  c.topology = buildTopology(mesh);
  c.reference = computeReference(mesh, c.topology);
  c.meanEdgeLength = meanEdgeLength(mesh, c.topology);
  c.mesh = std::move(mesh);
  return c;
}

std::vector<CheckMesh> makeCheckMeshes() {
  TriMesh grid = makeRectangleGrid(1.0, 0.8, 3, 2);
  for (int v = 0; v < grid.numVertices(); ++v)
    grid.V(v, 2) = 0.15 * std::sin(2.0 * grid.V(v, 0)) * (grid.V(v, 1) + 0.3) + 0.05 * grid.V(v, 0) * grid.V(v, 0);
  std::vector<CheckMesh> out;
  out.push_back(makeCheckMesh("patch", makeBendingStencilPatch()));
  out.push_back(makeCheckMesh("grid", std::move(grid)));
  return out;
}

Eigen::VectorXd rigidlyMoved(const Eigen::VectorXd& x, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Eigen::VectorXd y(x.size());
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) y.segment<3>(3 * v) = R * x.segment<3>(3 * v) + t;
  return y;
}

ConfigurationGeometry measureGeometry(const CheckMesh& m, const Eigen::VectorXd& x) {
  ConfigurationGeometry g;
  g.minAspectRatio = std::numeric_limits<double>::infinity();
  const int nf = m.mesh.numFaces();
  std::vector<Eigen::Vector3d> normal(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3d p0 = vertex(x, m.mesh.F(f, 0)), p1 = vertex(x, m.mesh.F(f, 1)), p2 = vertex(x, m.mesh.F(f, 2));
    const Eigen::Vector3d e0 = p1 - p0, e1 = p2 - p0;
    const Eigen::Vector3d c = e0.cross(e1);
    normal[f] = c.normalized();
    const double longest = std::max({e0.squaredNorm(), e1.squaredNorm(), (p2 - p1).squaredNorm()});
    g.minAspectRatio = std::min(g.minAspectRatio, c.norm() / longest);
    // Principal stretches²: the generalized eigenvalues of a v = s A v (a, A symmetric, A definite), from Eigen's
    // symmetric solver, exact to rounding at rest (not from the roots of det(a − s A), whose discriminant is
    // rounding-sized there: its square root once gave 1 + 7e-9 under FMA).
    const Sym2& A = m.reference.metric[f];
    Eigen::Matrix2d reference, current;
    reference << A[0], A[1], A[1], A[2];
    current << e0.dot(e0), e0.dot(e1), e0.dot(e1), e1.dot(e1);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> stretches(current, reference, Eigen::EigenvaluesOnly);
    g.maxStretch = std::max(g.maxStretch, std::sqrt(stretches.eigenvalues().maxCoeff()));
  }
  for (int e = 0; e < m.topology.numEdges(); ++e) {
    const int fa = m.topology.edgeFaces(e, 0), fb = m.topology.edgeFaces(e, 1);
    if (fb < 0) continue;
    const double angle = std::atan2(normal[fa].cross(normal[fb]).norm(), normal[fa].dot(normal[fb]));
    g.maxFoldAngle = std::max(g.maxFoldAngle, angle);
  }
  return g;
}

CheckConfiguration makeCheckConfiguration(const CheckMesh& m, ConfigurationKind kind, std::uint64_t seed,
                                          const ConfigurationOptions& o) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  CheckConfiguration c;
  c.kind = kind;
  Eigen::VectorXd x = flatten(m.mesh.V);
  const double L = m.meanEdgeLength;
  std::ostringstream d;
  d << m.name << " " << toString(kind) << ": ";
  switch (kind) {
    case ConfigurationKind::Random:
      addNoise(x, 0.15 * L, rng);
      d << "noise 0.15 edge";
      break;
    case ConfigurationKind::Rotation: {
      addNoise(x, 0.1 * L, rng);
      const Eigen::Matrix3d R = randomRotation(rng, 0.5 * kPi, kPi);
      x = rigidlyMoved(x, R, randomTranslation(rng));
      d << "rotation by " << degrees(Eigen::AngleAxisd(R).angle()) << ", noise 0.1 edge";
      break;
    }
    case ConfigurationKind::Stretch: {
      const double theta = 2.0 * kPi * unit(rng);
      const Eigen::Vector3d dir(std::cos(theta), std::sin(theta), 0.0);
      const double along0 = x.size() > 0 ? vertex(x, 0).dot(dir) : 0.0;
      for (Eigen::Index v = 0; v < x.size() / 3; ++v) {
        const double along = vertex(x, static_cast<int>(v)).dot(dir) - along0;
        x.segment<3>(3 * v) += (o.stretch - 1.0) * along * dir;
      }
      addNoise(x, 0.05 * L, rng);
      x = rigidlyMoved(x, randomRotation(rng, 0.0, kPi), randomTranslation(rng));
      d << "x" << o.stretch << " along " << degrees(theta) << ", noise 0.05 edge";
      break;
    }
    case ConfigurationKind::Fold: {
      std::vector<int> interior;
      for (int e = 0; e < m.topology.numEdges(); ++e)
        if (!m.topology.isBoundaryEdge(e)) interior.push_back(e);
      if (interior.empty()) throw InputError("fold configuration: mesh '" + m.name + "' has no interior edge");
      addNoise(x, 0.02 * L, rng);
      const int e = interior[static_cast<std::size_t>(unit(rng) * static_cast<double>(interior.size())) %
                             interior.size()];
      const double delta = o.foldMinDelta * std::pow(o.foldMaxDelta / o.foldMinDelta, unit(rng));
      foldAcrossEdge(m, e, delta, unit(rng) < 0.5 ? -1.0 : 1.0, x);
      x = rigidlyMoved(x, randomRotation(rng, 0.0, kPi), randomTranslation(rng));
      d << "edge " << e << " folded to 180 - " << degrees(delta) << " (|m| = " << std::sin(0.5 * delta) << ")";
      break;
    }
    case ConfigurationKind::Degenerate: {
      addNoise(x, 0.05 * L, rng);
      const int f = static_cast<int>(unit(rng) * m.mesh.numFaces()) % m.mesh.numFaces();
      const int k = static_cast<int>(unit(rng) * 3.0) % 3;
      squashFace(m, f, k, o.degenerateAspect, x);
      x = rigidlyMoved(x, randomRotation(rng, 0.0, kPi), randomTranslation(rng));
      d << "face " << f << " squashed to aspect " << o.degenerateAspect;
      break;
    }
  }
  c.x = std::move(x);
  c.geometry = measureGeometry(m, c.x);
  c.description = d.str();
  return c;
}

}  // namespace jetshell
