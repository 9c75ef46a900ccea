#include "core/input_limits.h"
#include "energies/contact/sdf_grid.h"
#include "energies/contact/volume_collider.h"
#include "tests/test_util.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

using namespace jetshell;

namespace {

/// Central differences of the distance and its gradient at p against the sample's gradient and Hessian.
void checkSample(const VolumeCollider& c, const Eigen::Vector3d& p, double t = 0.0) {
  const SdfSample s = c.query(p, t);
  const double h = 1e-6;
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[i] = h;
    const SdfSample a = c.query(p + e, t), b = c.query(p - e, t);
    CHECK((a.distance - b.distance) / (2 * h) == Approx(s.gradient[i]).margin(1e-7));
    const Eigen::Vector3d col = (a.gradient - b.gradient) / (2 * h);
    for (int j = 0; j < 3; ++j) CHECK(col[j] == Approx(s.hessian(j, i)).margin(1e-5));
  }
}

std::string tempFile(const std::string& name, const std::string& text) {
  const std::string path = (test::scratchDirectory("volume_shapes") / name).string();
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST_CASE("volume shapes: distances, normals and curvature of plane, sphere, box and capsule", "[contact]") {
  RigidPath tilted;
  tilted.origin = Eigen::Vector3d(0.1, -0.2, 0.3);
  tilted.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const VolumeCollider plane("p", makePlaneShape(), tilted), sphere("s", makeSphereShape(0.5), tilted),
      box("b", makeBoxShape({0.3, 0.2, 0.1}), tilted), capsule("c", makeCapsuleShape(0.2, 0.4), tilted);
  const Eigen::Vector3d q = tilted.origin + tilted.rotation * Eigen::Vector3d(0.05, 0.1, 0.9);
  CHECK(plane.query(q, 0).distance == Approx(0.9));
  CHECK(sphere.query(q, 0).distance == Approx(std::sqrt(0.05 * 0.05 + 0.01 + 0.81) - 0.5));
  CHECK(box.query(q, 0).distance == Approx(0.8));
  CHECK(capsule.query(q, 0).distance == Approx(std::sqrt(0.05 * 0.05 + 0.01 + 0.25) - 0.2));
  // Inside: negative.
  CHECK(box.query(tilted.origin, 0).distance == Approx(-0.1));
  CHECK(capsule.query(tilted.origin, 0).distance < 0.0);
  for (const VolumeCollider* c : {&plane, &sphere, &box, &capsule}) {
    INFO(c->shape().kind());
    checkSample(*c, q);
    checkSample(*c, tilted.origin + tilted.rotation * Eigen::Vector3d(0.5, 0.35, 0.2));  // near a box edge
  }
}

TEST_CASE("volume shapes: a box with rounded edges is the points within r of its core box", "[contact]") {
  const VolumeCollider rounded("r", makeBoxShape({0.3, 0.2, 0.1}, 0.05), RigidPath{}),
      sharp("s", makeBoxShape({0.3, 0.2, 0.1}), RigidPath{});
  // On a face's middle and inside, the same as the sharp box.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.1, 0.05, 0.4), Eigen::Vector3d(0.0, 0.0, 0.02),
                                  Eigen::Vector3d(0.29, 0.0, 0.0)})
    CHECK(rounded.query(p, 0).distance == Approx(sharp.query(p, 0).distance));
  // Beyond an edge (x, z) the distance is to the rounded edge of radius 0.05 about the core's edge (0.25, ·, 0.05).
  const Eigen::Vector3d edge(0.25, 0.0, 0.05), out(0.33, 0.1, 0.11);
  const double beyond = std::hypot(out.x() - edge.x(), out.z() - edge.z());
  CHECK(rounded.query(out, 0).distance == Approx(beyond - 0.05));
  CHECK(sharp.query(out, 0).distance == Approx(std::hypot(0.03, 0.01)));
  // The curvature a rounded edge has and a sharp one lacks near its surface: 1/r across the edge.
  const Eigen::Vector3d onEdge = edge + 0.051 * Eigen::Vector3d(1, 0, 1).normalized();
  const SdfSample s = rounded.query(onEdge, 0);
  CHECK(s.distance == Approx(0.001));
  const Eigen::Vector3d across = Eigen::Vector3d(1, 0, -1).normalized();
  CHECK(across.dot(s.hessian * across) == Approx(1.0 / 0.051));
  // A corner's rounding: the distance to the core's corner less r.
  const Eigen::Vector3d corner(0.25, 0.15, 0.05), far(0.4, 0.3, 0.3);
  CHECK(rounded.query(far, 0).distance == Approx((far - corner).norm() - 0.05));
  for (const Eigen::Vector3d& p : {out, onEdge, far, Eigen::Vector3d(0.0, 0.0, 0.02)}) checkSample(rounded, p);
  // As rounded as it can be: the thinnest half-extent.
  CHECK(makeBoxShape({0.3, 0.2, 0.1}, 0.1)->signedDistance(Eigen::Vector3d(0.0, 0.0, 0.3)).distance == Approx(0.2));
  CHECK_THROWS_WITH(makeBoxShape({0.3, 0.2, 0.1}, 0.11), "box edgeRadius: must lie in [0, the smallest half extent]");
  CHECK_THROWS_WITH(makeBoxShape({0.3, 0.2, 0.1}, -0.01), "box edgeRadius: must lie in [0, the smallest half extent]");
  CHECK_THROWS(makeBoxShape({0.3, 0.2, 0.1}, std::nan("")));
}

TEST_CASE("volume shapes: a collider moves on its path, with the material move friction needs", "[contact]") {
  RigidPath path;
  path.velocity = Eigen::Vector3d(0, 0, 1);
  path.angularVelocity = Eigen::Vector3d(0, 0, 2);
  const VolumeCollider sphere("s", makeSphereShape(0.5), path);
  CHECK(sphere.query(Eigen::Vector3d(0, 0, 2), 1.0).distance == Approx(0.5));
  // The material at (1, 0, 1) at t = 1 is 1 m off the axis through the centre (0, 0, 1): over 0.25 s it rises
  // 0.25 m and turns by 0.5 rad along the circle (the chord, not the tangent); over a short step the move is the
  // material's velocity (0, 2, 1) times the step.
  const Eigen::Vector3d m = sphere.materialMove(Eigen::Vector3d(1, 0, 1), 1.0, 0.25);
  CHECK(m.x() == Approx(std::cos(0.5) - 1.0));
  CHECK(m.y() == Approx(std::sin(0.5)));
  CHECK(m.z() == Approx(0.25));
  const Eigen::Vector3d v = sphere.materialMove(Eigen::Vector3d(1, 0, 1), 1.0, 1e-6) / 1e-6;
  CHECK(v.x() == Approx(0.0).margin(1e-5));
  CHECK(v.y() == Approx(2.0));
  CHECK(v.z() == Approx(1.0));
  checkSample(sphere, Eigen::Vector3d(0.3, 0.4, 1.9), 1.0);
}

TEST_CASE("sdf grid: a sampled plane reads back exactly, bad files name their line", "[contact]") {
  std::string text = "# z - 0.25 on a 3x3x3 grid\ndims 3 3 3\norigin 0 0 0\nspacing 0.5\n";
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) text += std::to_string(0.5 * k - 0.25) + (i == 2 ? "\n" : " ");
  const VolumeShapePtr grid = makeSdfGridShape(readSdfGrid(tempFile("grid_ok.sdf", text)));
  const SdfSample s = grid->signedDistance(Eigen::Vector3d(0.3, 0.7, 0.6));
  CHECK(s.distance == Approx(0.35));
  CHECK(s.gradient.z() == Approx(1.0));
  CHECK(grid->signedDistance(Eigen::Vector3d(0.5, 0.5, 2.0)).distance == Approx(1.75));  // outside: continued
  CHECK_THROWS_WITH(readSdfGrid(tempFile("grid_bad1.sdf", "dims 3 3\n")), Catch::Contains("grid_bad1.sdf:1"));
  CHECK_THROWS_WITH(readSdfGrid(tempFile("grid_bad2.sdf", "dims 2 2 2\norigin 0 0 0\nspacing 1\n1 2 x\n")),
                    Catch::Contains("grid_bad2.sdf:4") && Catch::Contains("'x'"));
  CHECK_THROWS_WITH(readSdfGrid(tempFile("grid_bad3.sdf", "dims 2 2 2\norigin 0 0 0\nspacing 1\n1 2 3\n")),
                    Catch::Contains("3 distance values, 8 expected"));
  CHECK_THROWS_WITH(readSdfGrid(tempFile("grid_bad4.sdf", "dims 100000 100000 100000\n")),
                    Catch::Contains("at most"));
  // Each dimension within its bound, their product 2^72: once wrapped to 0 samples, then read past the values.
  CHECK_THROWS_WITH(readSdfGrid(tempFile("grid_bad5.sdf", "dims 16777216 16777216 16777216\norigin 0 0 0\n"
                                                          "spacing 0.1\n")),
                    Catch::Contains("grid_bad5.sdf:1: at most 16777216 samples"));
  SdfGrid wrapped;
  wrapped.nx = wrapped.ny = wrapped.nz = 1 << 24;
  wrapped.spacing = 0.1;
  CHECK_THROWS_WITH(makeSdfGridShape(wrapped), "SDF grid: at most 16777216 samples");
  // Only regular files of bounded size and line length are read.
  CHECK_THROWS_WITH(readSdfGrid("/dev/zero"), Catch::Contains("not a regular file"));
  CHECK_THROWS_WITH(readSdfGrid(test::scratchDirectory("volume_shapes").string()),
                    Catch::Contains("not a regular file"));
  const std::int64_t lineBound = inputLimits().maxSdfLineBytes;
  inputLimits().maxSdfLineBytes = 1024;  // the default, 64 MiB, works alike
  CHECK_THROWS_WITH(readSdfGrid(tempFile("grid_bad6.sdf", "dims 2 2 2\norigin 0 0 0\nspacing 1\n" +
                                                              std::string(1025, ' ') + "\n")),
                    Catch::Contains("grid_bad6.sdf:4: line is too long (at most 1024 bytes)"));
  inputLimits().maxSdfLineBytes = lineBound;
}
