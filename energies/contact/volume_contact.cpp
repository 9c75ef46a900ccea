#include "energies/contact/volume_contact.h"

#include "core/vertex_block_term.h"
#include "energies/contact/contact_ramp.h"
#include "energies/contact/sdf_model.h"
#include "energies/contact/stiffness_parameter.h"
#include "energies/element_energy_term.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetshell {
namespace {

/// Sample point q of element e: Σ_k w_qk x_k.
template <int K, typename T>
V3<T> samplePoint(const VolumeContactState& s, const T* x, int e, int q) {
  const double* w = s.sampling.weights.data() + (static_cast<std::size_t>(e) * s.sampling.pointsPerElement + q) * K;
  if (K == 1) return load3(x);
  V3<T> p = w[0] * load3(x);
  for (int k = 1; k < K; ++k) p = p + w[k] * load3(x + 3 * k);
  return p;
}

/// The penetration p = ε − d(x_q, t) of sample point q of element e, when it lies inside the activation band.
template <int K, typename T>
bool penetration(const VolumeContactState& s, const T* x, int e, int q, T& p) {
  const V3<T> xq = samplePoint<K>(s, x, e, q);
  const Eigen::Vector3d x0 = valueOf3(xq);
  const SdfSample d = s.collider->query(x0, s.time);
  if (d.distance >= s.params.activationDistance) return false;
  p = s.params.activationDistance - signedDistanceModel(d, xq, x0);
  return true;
}

template <int K>
struct VolumePenaltyEnergy {
  static constexpr int kVertices = K;
  std::shared_ptr<const VolumeContactState> s;
  template <typename T>
  T operator()(const T* x, int e) const {
    const ContactParams& c = s->params;
    T energy = constant<T>(0.0);
    for (int q = 0; q < s->sampling.pointsPerElement; ++q) {
      T p;
      if (!penetration<K>(*s, x, e, q, p)) continue;
      const double area = s->sampling.area[static_cast<std::size_t>(e) * s->sampling.pointsPerElement + q];
      energy += (area * c.penaltyStiffness) * contactRamp(p, c.smoothingDistance);
    }
    return energy;
  }
};

template <int K>
struct VolumeDampingEnergy {
  static constexpr int kVertices = K;
  std::shared_ptr<const VolumeContactState> s;
  template <typename T>
  T operator()(const T* x, int e) const {
    const ContactParams& c = s->params;
    T energy = constant<T>(0.0);
    if (s->timeStep <= 0.0) return energy;
    for (int q = 0; q < s->sampling.pointsPerElement; ++q) {
      T p;
      if (!penetration<K>(*s, x, e, q, p)) continue;
      const std::size_t i = static_cast<std::size_t>(e) * s->sampling.pointsPerElement + q;
      const double a = s->previousPenetration[i];
      const double scale = s->sampling.area[i] * c.huntCrossleyDamping * c.penaltyStiffness / s->timeStep;
      energy += scale * (contactRampMoment(p, c.smoothingDistance) - a * contactRamp(p, c.smoothingDistance));
    }
    return energy;
  }
};

template <int K>
struct VolumeFrictionEnergy {
  static constexpr int kVertices = K;
  explicit VolumeFrictionEnergy(std::shared_ptr<const VolumeContactState> state) : s(std::move(state)) {}
  std::shared_ptr<const VolumeContactState> s;
  EvalOptions options;  // options.frictionHessian (energies/element_energy_term.h)
  template <typename T>
  T operator()(const T* x, int e) const {
    const ContactParams& c = s->params;
    T energy = constant<T>(0.0);
    if (s->timeStep <= 0.0) return energy;
    const double epsV = c.frictionSlipVelocity * s->timeStep;
    for (int q = 0; q < s->sampling.pointsPerElement; ++q) {
      const std::size_t i = static_cast<std::size_t>(e) * s->sampling.pointsPerElement + q;
      const double lambda = s->normalForce[i];
      if (lambda <= 0.0) continue;
      const V3<T> xq = samplePoint<K>(*s, x, e, q);
      V3<T> u;
      for (int k = 0; k < 3; ++k) u[k] = xq[k] - (s->start[i][k] + s->colliderShift[i][k]);
      energy += (c.frictionCoefficient * lambda) *
                frictionPrimitive(tangentialSlipSquared(u, s->normal[i]), epsV, options.frictionHessian);
    }
    return energy;
  }
};

template <template <int> class Energy>
EnergyTermPtr makeTerm(const std::string& name, const std::shared_ptr<VolumeContactState>& state, int numVertices,
                       bool stiffnessIsParameter) {
  const StencilTable& table = state->sampling.table;
  if (state->sampling.verticesPerElement == 1) {
    if (stiffnessIsParameter)
      return std::make_shared<StiffnessParameterTerm<Energy<1>>>(name, table, numVertices, Energy<1>{state},
                                                                  &state->params.penaltyStiffness);
    return std::make_shared<ElementEnergyTerm<Energy<1>>>(name, table, numVertices, Energy<1>{state}, false, false);
  }
  if (stiffnessIsParameter)
    return std::make_shared<StiffnessParameterTerm<Energy<3>>>(name, table, numVertices, Energy<3>{state},
                                                                &state->params.penaltyStiffness);
  return std::make_shared<ElementEnergyTerm<Energy<3>>>(name, table, numVertices, Energy<3>{state}, false, false);
}

}  // namespace

VolumeContactState::VolumeContactState(ContactSampling s, VolumeColliderPtr c, const ContactParams& p)
    : sampling(std::move(s)), collider(std::move(c)), params(p) {
  if (!collider) throw InputError("volume contact: no collider");
  if (!(params.smoothingDistance > 0.0)) throw InputError("volume contact: smoothingDistance must be > 0");
  const std::size_t n = static_cast<std::size_t>(sampling.numPoints());
  previousPenetration.assign(n, 0.0);
  normalForce.assign(n, 0.0);
  normal.assign(n, Eigen::Vector3d::UnitZ());
  start.assign(n, Eigen::Vector3d::Zero());
  colliderShift.assign(n, Eigen::Vector3d::Zero());
}

Eigen::Vector3d VolumeContactState::point(const Eigen::VectorXd& x, int e, int q) const {
  const int K = sampling.verticesPerElement;
  const int* ids = sampling.table.element(e);
  const double* w = sampling.weights.data() + (static_cast<std::size_t>(e) * sampling.pointsPerElement + q) * K;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int k = 0; k < K; ++k) p += w[k] * x.segment<3>(3 * (firstVertex + ids[k]));
  return p;
}

void VolumeContactState::beginStep(const Eigen::VectorXd& xStart, double tStart, double h) {
  const int Q = sampling.pointsPerElement;
  const int ne = sampling.numElements();
#pragma omp parallel for schedule(static) if (ne >= 512)
  for (int e = 0; e < ne; ++e) {
    for (int q = 0; q < Q; ++q) {
      const std::size_t i = static_cast<std::size_t>(e) * Q + q;
      const Eigen::Vector3d p = point(xStart, e, q);
      const SdfSample d = collider->query(p, tStart);
      const double pen = params.activationDistance - d.distance;
      previousPenetration[i] = pen;
      normalForce[i] = sampling.area[i] * params.penaltyStiffness * contactRampForce(pen, params.smoothingDistance);
      const double gn = d.gradient.norm();
      normal[i] = gn > 0.0 ? Eigen::Vector3d(d.gradient / gn) : Eigen::Vector3d::UnitZ();
      start[i] = p;
      colliderShift[i] = collider->materialMove(p, tStart, h);
    }
  }
  time = tStart + h;
  timeStep = h;
}

double VolumeContactState::stepBound(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double fraction) const {
  const int Q = sampling.pointsPerElement;
  double alpha = 1.0;
  const double thinnest = collider->shape().thinnestHalfWidth();
  for (int e = 0; e < sampling.numElements(); ++e)
    for (int q = 0; q < Q; ++q) {
      const Eigen::Vector3d p = point(x, e, q);
      const SdfSample s = collider->query(p, time);
      const double approach = -s.gradient.dot(point(d, e, q));
      if (approach <= 0.0) continue;
      const double room = fraction * std::max({s.distance, params.activationDistance, thinnest});
      alpha = std::min(alpha, room / approach);
    }
  return alpha;
}

Eigen::Vector3d VolumeContactState::forceOnSolid(const Eigen::VectorXd& x, double t) const {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  const int Q = sampling.pointsPerElement;
  for (int e = 0; e < sampling.numElements(); ++e)
    for (int q = 0; q < Q; ++q) {
      const SdfSample d = collider->query(point(x, e, q), t);
      if (d.distance >= params.activationDistance) continue;
      const double area = sampling.area[static_cast<std::size_t>(e) * static_cast<std::size_t>(Q) +
                                        static_cast<std::size_t>(q)];
      force -= area * params.penaltyStiffness *
               contactRampForce(params.activationDistance - d.distance, params.smoothingDistance) * d.gradient;
    }
  return force;
}

double VolumeContactState::minDistance(const Eigen::VectorXd& x) const {
  double m = std::numeric_limits<double>::infinity();
  for (int e = 0; e < sampling.numElements(); ++e)
    for (int q = 0; q < sampling.pointsPerElement; ++q) m = std::min(m, collider->query(point(x, e, q), time).distance);
  return m;
}

double VolumeContactState::solidTravel(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double tStart,
                                       double h) const {
  const RigidPath& path = collider->path();
  if (path.isStatic() || !(h > 0.0)) return 0.0;
  // Over a piece of constant velocities from t to t + Δ a material point at p moves to c(t) + Δ v + Rot(ω Δ)
  // (p − c(t)) (rigid_path.h); a turn about an axis of the shape's symmetry leaves its surface in place and is left
  // out. Over several pieces (keyframes) the point is followed through them and its moves added up. A move is the
  // length of the point's path, |Δ v| + |ω| Δ ρ (ρ its distance from the axis), not the chord to where it ends: a
  // solid that turns by a whole turn within the step ends where it began, and sweeps everything within its reach.
  struct Move {
    Eigen::Vector3d centre, shift, axis;  // axis: ω' / |ω'| (zero without a turn)
    double angle;                         // |ω'| Δ [rad]
    Eigen::Matrix3d turn;                 // Rot(ω' Δ) − I
  };
  std::vector<Move> moves;
  for (const RigidPath::Piece& piece : path.piecesOver(tStart, h)) {
    const Eigen::Vector3d omega = collider->surfaceTurning(piece);
    const double angle = omega.norm() * piece.duration;
    const Eigen::Vector3d axis = angle > 0.0 ? Eigen::Vector3d(omega.normalized()) : Eigen::Vector3d::Zero();
    const Eigen::Matrix3d turn =
        angle > 0.0 ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, axis).toRotationMatrix() - Eigen::Matrix3d::Identity())
                    : Eigen::Matrix3d::Zero();
    moves.push_back({path.originAt(piece.start), piece.duration * piece.velocity, axis, angle, turn});
  }
  double largest = 0.0;
  for (int e = 0; e < sampling.numElements(); ++e)
    for (int q = 0; q < sampling.pointsPerElement; ++q) {
      const Eigen::Vector3d p = point(x, e, q);
      double move = 0.0;
      Eigen::Vector3d m = p;
      for (const Move& piece : moves) {
        const Eigen::Vector3d arm = m - piece.centre;
        const double fromAxis = (arm - piece.axis * piece.axis.dot(arm)).norm();
        move += piece.shift.norm() + piece.angle * fromAxis;
        m += piece.shift + piece.turn * arm;
      }
      if (!(move > largest)) continue;
      const double reach = move + h * point(v, e, q).norm() + params.activationDistance;
      if (collider->query(p, tStart).distance <= reach) largest = move;
    }
  return largest;
}

VolumeContactTerms makeVolumeContactTerms(ContactSampling sampling, int numVertices, VolumeColliderPtr collider,
                                          const ContactParams& params, const std::string& suffix, int firstVertex) {
  if (firstVertex < 0) throw InputError("volume contact: firstVertex must not be negative");
  VolumeContactTerms t;
  t.state = std::make_shared<VolumeContactState>(std::move(sampling), std::move(collider), params);
  t.state->firstVertex = firstVertex;
  auto place = [&](const EnergyTermPtr& term) -> EnergyTermPtr {
    return firstVertex == 0 ? term : std::make_shared<VertexBlockTerm>(term, firstVertex, numVertices);
  };
  t.penalty = place(makeTerm<VolumePenaltyEnergy>("contact_penalty" + suffix, t.state, numVertices, true));
  if (params.huntCrossleyDamping > 0.0)
    t.damping = place(makeTerm<VolumeDampingEnergy>("contact_damping" + suffix, t.state, numVertices, false));
  if (params.frictionCoefficient > 0.0)
    t.friction = place(makeTerm<VolumeFrictionEnergy>("contact_friction" + suffix, t.state, numVertices, false));
  return t;
}

}  // namespace jetshell
