// Contact parameters of an actor (the spec's ContactParams and PointCloudColliderParams) and how two actors'
// coefficients combine: by geometric mean.
#pragma once

#include <cmath>

namespace jetshell {

/// Penalty on the signed distance with a C²-smoothed ramp (energies/contact/contact_ramp.h), Hunt–Crossley
/// normal damping and regularized Coulomb friction (which also applies to shell–shell contact).
struct ContactParams {
  double penaltyStiffness = 1e9;       // k [Pa/m]: pressure per metre of penetration
  double activationDistance = 0.005;   // ε [m]: the penalty acts where the signed distance is below ε
  double smoothingDistance = 0.001;    // δ [m]: width of the ramp's rounded corner
  double huntCrossleyDamping = 0.0;    // c [s/m]: normal force k·r(p)·(1 + c ṗ)
  double frictionCoefficient = 0.5;    // μ
  double frictionSlipVelocity = 0.01;  // V_f [m/s]: slip speed below which friction is regularized (sticking)
};

/// The smallest point-cloud radius a scene takes: the broad phase's cells are 2·radius wide, and cells of a
/// micrometre already cover any garment-sized scene with ample room in its 64-bit cell indices.
constexpr double kMinPointCloudRadius = 1e-6;  // m

/// Point-cloud collider of a shell: spheres of `radius` at the contact samples (vertices). Two samples touch
/// when closer than 2·radius. Samples of one actor whose rest positions are closer than
/// selfContactExclusionRatio · 2·radius never collide (neighbours on the surface; see the note in
/// energies/contact/point_cloud_contact.h on why the ratio applies to the diameter).
struct PointCloudColliderParams {
  double radius = 0.01;                    // m, at least kMinPointCloudRadius
  bool selfContact = false;
  double selfContactExclusionRatio = 1.5;
};

/// Geometric mean of two coefficients (0 when either is 0).
inline double combineCoefficients(double a, double b) { return std::sqrt(a * b); }

/// The pair's parameters: every coefficient is the geometric mean of the two actors'.
inline ContactParams combine(const ContactParams& a, const ContactParams& b) {
  ContactParams c;
  c.penaltyStiffness = combineCoefficients(a.penaltyStiffness, b.penaltyStiffness);
  c.activationDistance = combineCoefficients(a.activationDistance, b.activationDistance);
  c.smoothingDistance = combineCoefficients(a.smoothingDistance, b.smoothingDistance);
  c.huntCrossleyDamping = combineCoefficients(a.huntCrossleyDamping, b.huntCrossleyDamping);
  c.frictionCoefficient = combineCoefficients(a.frictionCoefficient, b.frictionCoefficient);
  c.frictionSlipVelocity = combineCoefficients(a.frictionSlipVelocity, b.frictionSlipVelocity);
  return c;
}

}  // namespace jetshell
