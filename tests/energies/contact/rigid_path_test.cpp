#include "energies/contact/rigid_path.h"

#include "core/mesh.h"
#include "energies/contact/volume_collider.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace jetshell;

namespace {

const double kPi = std::acos(-1.0);

Eigen::Quaterniond about(const Eigen::Vector3d& axis, double radians) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(radians, axis.normalized()));
}

/// Placed at (1, 0, 0) turned 90° about x; rises 0.2 m by t = 1, then turns 90° about z (and moves 0.1 m along x)
/// by t = 3, then stays.
RigidPath liftThenTurn() {
  RigidPath path;
  path.origin = {1.0, 0.0, 0.0};
  path.rotation = about(Eigen::Vector3d::UnitX(), 0.5 * kPi);
  path.keyframes = {{1.0, {0.0, 0.0, 0.2}, Eigen::Quaterniond::Identity()},
                    {3.0, {0.1, 0.0, 0.2}, about(Eigen::Vector3d::UnitZ(), 0.5 * kPi)}};
  return path;
}

}  // namespace

TEST_CASE("rigid path: keyframes are reached exactly, and the motion between them is steady", "[contact]") {
  const RigidPath path = liftThenTurn();
  path.validate("test");
  CHECK_FALSE(path.isStatic());
  const Eigen::Matrix3d r0 = path.rotation.toRotationMatrix();
  // At the placement until 0 and at t = 0; each keyframe's pose at its time; the last held after it.
  CHECK((path.originAt(-1.0) - path.origin).norm() == 0.0);
  CHECK((path.originAt(0.0) - path.origin).norm() == 0.0);
  CHECK((path.rotationAt(0.0) - r0).norm() < 1e-15);
  CHECK((path.originAt(1.0) - Eigen::Vector3d(1.0, 0.0, 0.2)).norm() < 1e-15);
  CHECK((path.rotationAt(1.0) - r0).norm() < 1e-15);
  const Eigen::Matrix3d turned = about(Eigen::Vector3d::UnitZ(), 0.5 * kPi).toRotationMatrix() * r0;
  for (double t : {3.0, 4.0, 100.0}) {
    CHECK((path.originAt(t) - Eigen::Vector3d(1.1, 0.0, 0.2)).norm() < 1e-15);
    CHECK((path.rotationAt(t) - turned).norm() < 1e-14);
  }
  // Halfway: half the rise, half the turn.
  CHECK((path.originAt(0.5) - Eigen::Vector3d(1.0, 0.0, 0.1)).norm() < 1e-15);
  CHECK((path.originAt(2.0) - Eigen::Vector3d(1.05, 0.0, 0.2)).norm() < 1e-15);
  CHECK((path.rotationAt(2.0) - about(Eigen::Vector3d::UnitZ(), 0.25 * kPi).toRotationMatrix() * r0).norm() < 1e-14);
  // Velocities: 0.2 m/s up, then 0.05 m/s along x turning at π/4 rad/s about z, then none.
  CHECK((path.pieceAt(0.3).velocity - Eigen::Vector3d(0.0, 0.0, 0.2)).norm() < 1e-15);
  CHECK(path.pieceAt(0.3).angularVelocity.norm() == 0.0);
  CHECK((path.pieceAt(1.0).velocity - Eigen::Vector3d(0.05, 0.0, 0.0)).norm() < 1e-15);
  CHECK((path.pieceAt(1.0).angularVelocity - Eigen::Vector3d(0.0, 0.0, 0.25 * kPi)).norm() < 1e-14);
  CHECK(path.pieceAt(3.0).velocity.norm() == 0.0);
  CHECK(path.pieceAt(3.0).angularVelocity.norm() == 0.0);
  // The pieces over a step that spans both keyframes.
  const std::vector<RigidPath::Piece> pieces = path.piecesOver(0.5, 3.0);
  REQUIRE(pieces.size() == 3);
  CHECK(pieces[0].start == 0.5);
  CHECK(pieces[0].duration == Approx(0.5));
  CHECK(pieces[1].start == 1.0);
  CHECK(pieces[1].duration == Approx(2.0));
  CHECK(pieces[2].start == 3.0);
  CHECK(pieces[2].duration == Approx(0.5));
  CHECK(pieces[2].velocity.norm() == 0.0);
  CHECK(path.piecesOver(1.2, 0.1).size() == 1);
  // Pieces start exactly at the keyframes' times, whatever the rounding of the times between them.
  RigidPath many;
  for (double t : {0.1, 0.3, 0.7, 0.7000000000000001, 1.1})
    many.keyframes.push_back({t, {t, 0.0, 0.0}, Eigen::Quaterniond::Identity()});
  const std::vector<RigidPath::Piece> split = many.piecesOver(0.05, 1.0);
  REQUIRE(split.size() == 5);
  double total = 0.0;
  for (std::size_t k = 1; k < split.size(); ++k) CHECK(split[k].start == many.keyframes[k - 1].time);
  for (const RigidPath::Piece& piece : split) {
    CHECK(piece.duration > 0.0);
    CHECK((piece.velocity - Eigen::Vector3d::UnitX()).norm() < 1e-6);
    total += piece.duration;
  }
  CHECK(total == Approx(1.0));
}

TEST_CASE("rigid path: a turn between keyframes takes the smaller angle", "[contact]") {
  RigidPath path;
  path.keyframes = {{1.0, Eigen::Vector3d::Zero(), about(Eigen::Vector3d::UnitZ(), 1.5 * kPi)}};  // 270° = −90°
  CHECK((path.pieceAt(0.5).angularVelocity - Eigen::Vector3d(0.0, 0.0, -0.5 * kPi)).norm() < 1e-14);
  CHECK((path.rotationAt(1.0) - about(Eigen::Vector3d::UnitZ(), 1.5 * kPi).toRotationMatrix()).norm() < 1e-14);
}

TEST_CASE("rigid path: constant velocities are one piece, and bad keyframes are refused", "[contact]") {
  RigidPath steady;
  steady.velocity = {0.0, 0.0, 2.0};
  steady.angularVelocity = {0.0, 0.0, 3.0};
  const std::vector<RigidPath::Piece> one = steady.piecesOver(0.25, 1.0 / 60.0);
  REQUIRE(one.size() == 1);
  CHECK(one[0].duration == 1.0 / 60.0);
  CHECK((steady.originAt(0.5) - Eigen::Vector3d(0.0, 0.0, 1.0)).norm() == 0.0);
  RigidPath still;
  still.keyframes = {{1.0, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()}};
  CHECK(still.isStatic());
  auto refused = [](RigidPath p, const std::string& text) {
    CHECK_THROWS_WITH(p.validate("volume actor 'lift'"), Catch::Contains("volume actor 'lift'") &&
                                                           Catch::Contains(text));
  };
  RigidPath p = liftThenTurn();
  p.keyframes[0].time = 0.0;
  refused(p, "keyframe 0: time = 0");
  p = liftThenTurn();
  p.keyframes[1].time = 1.0;
  refused(p, "keyframe 1: time = 1");
  p = liftThenTurn();
  p.keyframes[1].time = std::numeric_limits<double>::infinity();
  refused(p, "keyframe 1");
  p = liftThenTurn();
  p.keyframes[0].translation.x() = std::nan("");
  refused(p, "keyframe 0: translation and turn must be finite");
  p = liftThenTurn();
  p.keyframes[0].turn = Eigen::Quaterniond(0.0, 0.0, 0.0, 0.0);
  refused(p, "the turn non-zero");
  p = liftThenTurn();
  p.keyframes[1].time = 1.0 + 1e-300;  // as good as 1: the time between them rounds to 0
  refused(p, "keyframe 1");
  p = liftThenTurn();
  p.keyframes[0] = {1e-310, {1e6, 0.0, 0.0}, Eigen::Quaterniond::Identity()};  // 1e316 m/s
  refused(p, "keyframe 0: too close in time to the one before for its move");
  p = liftThenTurn();
  p.velocity.z() = 1.0;
  refused(p, "keyframes cannot be combined with a constant velocity");
}

TEST_CASE("volume collider: a keyframed solid is where its path puts it, and held at its placement", "[contact]") {
  const VolumeCollider lift("lift", makeSphereShape(0.1), liftThenTurn());
  // The ball's centre rises with the path: 0.1 m above at t = 0.5, its surface 5 cm from (1, 0, 0.15).
  CHECK(lift.query({1.0, 0.0, 0.15}, 0.0).distance == Approx(0.05));
  CHECK(lift.query({1.0, 0.0, 0.15}, 0.5).distance == Approx(-0.05));
  // The material moves with the path over a step: rising 0.2 m/s, over 0.1 s by 2 cm; over a step that passes
  // the last keyframe (t = 3) only up to it, as the pose is held after; not at all once held.
  CHECK((lift.materialMove({1.0, 0.0, 0.0}, 0.5, 0.1) - Eigen::Vector3d(0.0, 0.0, 0.02)).norm() < 1e-15);
  const Eigen::Vector3d p(1.2, 0.3, 0.2), toEnd = lift.materialMove(p, 2.9, 0.1);
  CHECK(toEnd.norm() > 0.01);
  CHECK((lift.materialMove(p, 2.9, 0.5) - toEnd).norm() < 1e-15);
  CHECK(lift.materialMove(p, 5.0, 0.1).norm() == 0.0);
  const auto held = lift.readBy(PathClock::Held);
  CHECK(held->path().isStatic());
  CHECK(held->query({1.0, 0.0, 0.15}, 0.5).distance == Approx(0.05));
  // A static path reads the keyframes at time λ, as they are; dynamics all of it.
  const auto byLoad = lift.readBy(PathClock::LoadFactor);
  CHECK(byLoad->query({1.0, 0.0, 0.15}, 0.5).distance == Approx(-0.05));
  CHECK(lift.readBy(PathClock::Time)->query({1.0, 0.0, 0.15}, 0.5).distance == Approx(-0.05));
}

TEST_CASE("rigid path: each analysis reads the motions it follows", "[contact]") {
  RigidPath steady;
  steady.velocity = {0.0, 0.0, 2.0};
  steady.angularVelocity = {0.0, 0.0, 3.0};
  CHECK(steady.readBy(PathClock::Time).velocity == steady.velocity);
  CHECK(steady.readBy(PathClock::Time).angularVelocity == steady.angularVelocity);
  // Constant velocities are a motion in time: a static path holds them at the placement, as a relaxation does.
  CHECK(steady.readBy(PathClock::LoadFactor).isStatic());
  CHECK(steady.readBy(PathClock::Held).isStatic());
  const RigidPath keyed = liftThenTurn();
  REQUIRE_FALSE(keyed.keyframes.empty());
  CHECK(keyed.readBy(PathClock::LoadFactor).keyframes.size() == keyed.keyframes.size());
  CHECK((keyed.readBy(PathClock::LoadFactor).originAt(0.7) - keyed.originAt(0.7)).norm() == 0.0);
  CHECK(keyed.readBy(PathClock::Held).isStatic());
}
