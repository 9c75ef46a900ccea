// The prescribed motion of a rigid volume actor: where its frame is at time t, and how fast it moves.
//
// Input: the placement at t = 0 (origin c₀, rotation R₀) and either
//  - constant velocities: origin c(t) = c₀ + v t, rotation R(t) = Rot(ω t) · R₀ (ω [rad/s] in world axes, about
//    the actor's origin), or
//  - keyframes: poses reached at given times t_k > 0, each the placement moved by a translation d_k and turned by
//    Q_k (world axes, about the actor's origin): c(t) = c₀ + d(t), R(t) = Q(t) · R₀. From the placement at t = 0
//    (d = 0, Q = I) through each keyframe in turn, d moves linearly and Q turns at a constant angular velocity by
//    the smaller angle (at most 180°) between successive keyframes; after the last keyframe the pose is held.
// Either way the motion is a sequence of pieces of constant velocity and angular velocity (one piece for constant
// velocities), which contact's step division reads over a time step (piecesOver).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace jetshell {

/// What runs a volume actor's path in an analysis (RigidPath::readBy).
enum class PathClock {
  Time,        // dynamics: the whole path, in seconds
  LoadFactor,  // a static path: the keyframes, their times read as load factors λ
  Held         // dynamic relaxation: none (the placement)
};

/// A pose of a keyframed path: at `time` [s] the placement moved by `translation` [m] and turned by `turn`.
struct RigidKeyframe {
  double time = 0.0;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond turn = Eigen::Quaterniond::Identity();
};

struct RigidPath {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();                // c₀ [m]
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();    // R₀
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();              // v [m/s] (constant velocities)
  Eigen::Vector3d angularVelocity = Eigen::Vector3d::Zero();       // ω [rad/s] (constant velocities)
  /// Keyframed motion, times increasing and positive; empty: the constant velocities. With keyframes, velocity
  /// and angularVelocity are zero (validate).
  std::vector<RigidKeyframe> keyframes;

  /// A stretch of time over which the motion has constant velocity and angular velocity.
  struct Piece {
    double start = 0.0, duration = 0.0;  // [s]
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero(), angularVelocity = Eigen::Vector3d::Zero();
  };

  /// Where the frame is at t and how it moves then (at a keyframe's time, as the piece that starts there).
  struct State {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // R(t)
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();        // c(t)
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero(), angularVelocity = Eigen::Vector3d::Zero();
  };

  /// How the solid's material moves from one time to another: the point at p then is at
  /// c(to) + R(to) R(from)ᵀ (p − c(from)) later.
  struct Motion {
    Eigen::Matrix3d turn = Eigen::Matrix3d::Identity();  // R(to) R(from)ᵀ
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();  // c(from), c(to)
    Eigen::Vector3d operator()(const Eigen::Vector3d& p) const { return to + turn * (p - from); }
  };

  /// No velocity and no keyframe that moves or turns the actor.
  bool isStatic() const;
  /// The path as an analysis run by `clock` reads it, the one place that says which motions each analysis
  /// follows. Time: all of it. LoadFactor: the keyframes, with the load factor λ as their time, as prescribed
  /// positions are evaluated at λ; constant velocities are a motion in time and stay at the placement, as a
  /// fixed condition's velocity does in statics. Held: the placement (a relaxation's pseudo-time chasing a moving
  /// solid would have no equilibrium to reach).
  RigidPath readBy(PathClock clock) const;
  /// The whole state at t from one look-up of the keyframes (what a collider's query needs); the next three are
  /// its parts.
  State stateAt(double t) const;
  Eigen::Matrix3d rotationAt(double t) const;
  Eigen::Vector3d originAt(double t) const;
  Piece pieceAt(double t) const;
  /// The motion from the pose at `from` to the pose at `to` (exact whatever pieces lie between; none when equal).
  Motion motion(double from, double to) const;
  /// The pieces covering [t, t + h], in order, their durations adding up to h (one piece of duration exactly h
  /// for constant velocities).
  std::vector<Piece> piecesOver(double t, double h) const;
  /// Throws InputError, naming `where`, for a non-finite or zero rotation, non-finite velocities, keyframe times
  /// that are not positive, finite and increasing, non-finite keyframe translations or turns, or keyframes
  /// together with constant velocities.
  void validate(const std::string& where) const;
};

}  // namespace jetshell
