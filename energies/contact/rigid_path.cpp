#include "energies/contact/rigid_path.h"

#include "core/math_constants.h"
#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetshell {
namespace {

/// Keyframed motion between two poses: from (d0, q0) at `start` to the next keyframe's at `end` (its time).
struct Segment {
  double start = 0.0, end = std::numeric_limits<double>::infinity();
  Eigen::Vector3d d0 = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero(), angularVelocity = Eigen::Vector3d::Zero();
};

/// The segment holding t: from the placement at 0 to the first keyframe, between two keyframes, or the last
/// keyframe's pose held (and, before 0, the placement held).
Segment segmentAt(const std::vector<RigidKeyframe>& keys, double t) {
  Segment s;
  if (t < 0.0) {  // the placement, until 0
    s.start = t;
    s.end = 0.0;
    return s;
  }
  const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double time, const RigidKeyframe& k) { return time < k.time; });
  if (next != keys.begin()) {
    const RigidKeyframe& k = *(next - 1);
    s.start = k.time;
    s.d0 = k.translation;
    s.q0 = k.turn.normalized();
  }
  if (next == keys.end()) return s;  // held at the last pose
  s.end = next->time;
  const double duration = s.end - s.start;
  s.velocity = (next->translation - s.d0) / duration;
  Eigen::Quaterniond q = next->turn.normalized() * s.q0.conjugate();
  if (q.w() < 0.0) q.coeffs() *= -1.0;  // the smaller angle
  const double sine = q.vec().norm();
  if (sine > 0.0) s.angularVelocity = (2.0 * std::atan2(sine, q.w()) / duration) * (q.vec() / sine);
  return s;
}

Eigen::Matrix3d turnBy(const Eigen::Vector3d& angularVelocity, double time) {
  const double w = angularVelocity.norm();
  if (w == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(w * time, angularVelocity / w).toRotationMatrix();
}

}  // namespace

bool RigidPath::isStatic() const {
  if (velocity.squaredNorm() != 0.0 || angularVelocity.squaredNorm() != 0.0) return false;
  for (const RigidKeyframe& k : keyframes)
    if (k.translation.squaredNorm() != 0.0 || k.turn.vec().squaredNorm() != 0.0) return false;
  return true;
}

RigidPath RigidPath::readBy(PathClock clock) const {
  RigidPath read = *this;
  if (clock == PathClock::Time) return read;
  read.velocity.setZero();
  read.angularVelocity.setZero();
  if (clock == PathClock::Held) read.keyframes.clear();  // they start from the placement
  return read;
}

RigidPath::State RigidPath::stateAt(double t) const {
  State state;
  const Eigen::Matrix3d r0 = rotation.normalized().toRotationMatrix();
  if (keyframes.empty()) {
    state.rotation = turnBy(angularVelocity, t) * r0;
    state.origin = origin + t * velocity;
    state.velocity = velocity;
    state.angularVelocity = angularVelocity;
    return state;
  }
  const Segment s = segmentAt(keyframes, t);
  state.rotation = turnBy(s.angularVelocity, t - s.start) * s.q0.toRotationMatrix() * r0;
  state.origin = origin + s.d0;
  if (s.velocity.squaredNorm() > 0.0) state.origin += (t - s.start) * s.velocity;
  state.velocity = s.velocity;
  state.angularVelocity = s.angularVelocity;
  return state;
}

Eigen::Matrix3d RigidPath::rotationAt(double t) const { return stateAt(t).rotation; }

Eigen::Vector3d RigidPath::originAt(double t) const { return stateAt(t).origin; }

RigidPath::Piece RigidPath::pieceAt(double t) const {
  const State state = stateAt(t);
  return {t, 0.0, state.velocity, state.angularVelocity};
}

RigidPath::Motion RigidPath::motion(double from, double to) const {
  if (from == to) return {};
  const State a = stateAt(from), b = stateAt(to);
  return {b.rotation * a.rotation.transpose(), a.origin, b.origin};
}

std::vector<RigidPath::Piece> RigidPath::piecesOver(double t, double h) const {
  if (keyframes.empty()) return {{t, h, velocity, angularVelocity}};
  std::vector<Piece> pieces;
  const double end = t + h;
  double start = t;
  while (true) {
    // The next keyframe's own time ends the piece (+∞ for the held pose), so the next piece starts exactly there.
    const Segment s = segmentAt(keyframes, start);
    if (!(s.end < end)) {
      pieces.push_back({start, end - start, s.velocity, s.angularVelocity});
      return pieces;
    }
    pieces.push_back({start, s.end - start, s.velocity, s.angularVelocity});
    start = s.end;
  }
}

void RigidPath::validate(const std::string& where) const {
  if (!origin.allFinite() || !velocity.allFinite() || !angularVelocity.allFinite() ||
      !rotation.coeffs().allFinite() || rotation.norm() == 0.0)
    throw InputError(where + ": path must be finite with a non-zero rotation");
  if (keyframes.empty()) return;
  if (velocity.squaredNorm() != 0.0 || angularVelocity.squaredNorm() != 0.0)
    throw InputError(where + ": keyframes cannot be combined with a constant velocity or angular velocity");
  double previous = 0.0;
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const RigidKeyframe& f = keyframes[k];
    const std::string at = where + ": keyframe " + std::to_string(k);
    if (!std::isfinite(f.time) || !(f.time > previous))
      throw InputError(at + ": time = " + std::to_string(f.time) + " must be finite and after " +
                       (k == 0 ? std::string("0 (the placement)") : "the previous keyframe's"));
    if (!f.translation.allFinite() || !f.turn.coeffs().allFinite() || f.turn.norm() == 0.0)
      throw InputError(at + ": translation and turn must be finite, the turn non-zero");
    // The speed to it (the turn's rate is at most π over the same time).
    const Eigen::Vector3d from = k == 0 ? Eigen::Vector3d::Zero() : keyframes[k - 1].translation;
    if (!((f.translation - from) / (f.time - previous)).allFinite() || !std::isfinite(kPi / (f.time - previous)))
      throw InputError(at + ": too close in time to the one before for its move (a speed past any finite number)");
    previous = f.time;
  }
}

}  // namespace jetshell
