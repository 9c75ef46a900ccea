// The friction terms' two Hessians (core/term.h, FrictionHessian): the majorizer keeps the energy and the
// forces, its tangent-plane Hessian is the secant curvature μλ f₁(y)/y, never below the exact one; and from a
// sliding start its full Newton step keeps a sample held below its Coulomb limit on its side, where the exact
// Hessian's step overshoots to the other side.
#include "energies/contact/volume_contact.h"
#include "energies/element_energy_term.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <memory>
#include <vector>

using namespace jetshell;
using namespace jetshell::test;

namespace {

constexpr double kStiffness = 1e5, kArea = 1e-3, kMu = 0.5, kStep = 0.01, kSlipVelocity = 0.01;
constexpr double kEpsV = kSlipVelocity * kStep;  // ε_v [m]

/// n single-vertex samples on the plane z = 0, 1 mm into its activation band (p = δ, so λ = A k δ/2).
struct Samples {
  int n = 0;
  ContactSampling sampling;
  ContactParams params;
  Eigen::VectorXd start;  // x_n
};

Samples samples(int n) {
  Samples s;
  s.n = n;
  s.sampling.table.width = 1;
  s.start.resize(3 * n);
  for (int i = 0; i < n; ++i) {
    s.sampling.table.ids.push_back(i);
    s.sampling.weights.push_back(1.0);
    s.sampling.area.push_back(kArea);
    s.start.segment<3>(3 * i) << 0.1 * i, 0.0, 0.004;
  }
  s.params.penaltyStiffness = kStiffness;
  s.params.activationDistance = 0.005;
  s.params.smoothingDistance = 0.001;
  s.params.frictionCoefficient = kMu;
  s.params.frictionSlipVelocity = kSlipVelocity;
  return s;
}

constexpr double kFrictionLimit = kMu * kArea * kStiffness * 0.5 * 0.001;  // μλ [N]

VolumeColliderPtr floorPlane() { return std::make_shared<VolumeCollider>("floor", makePlaneShape(), RigidPath{}); }

struct DenseEvaluation {
  double energy = 0.0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;
};

DenseEvaluation evaluateWith(EnergyTerm& term, const Eigen::VectorXd& x, FrictionHessian model) {
  EvalOptions o;
  o.frictionHessian = model;
  const DenseDerivatives r = evaluateDense(term, x, o);
  return {r.energy, r.gradient, r.hessian};
}

/// A spring per vertex to its own anchor: E = k/2 |x − a|², the rest of a shell holding the sample.
struct AnchorSpring {
  static constexpr int kVertices = 1;
  double stiffness = 1.0;
  std::vector<Eigen::Vector3d> anchor;
  template <typename T>
  T operator()(const T* x, int v) const {
    T e = constant<T>(0.0);
    for (int c = 0; c < 3; ++c) {
      const T d = x[c] - constant<T>(anchor[static_cast<std::size_t>(v)][c]);
      e += constant<T>(0.5 * stiffness) * d * d;
    }
    return e;
  }
};

}  // namespace

TEST_CASE("friction Hessian: the majorizer keeps energy and forces, its tangent Hessian is μλ f1(y)/y, above the "
          "exact one", "[contact]") {
  // Slips: zero, inside the regularization, at its edge, sliding, far sliding; in changing directions.
  const std::vector<double> slip = {0.0, 0.3 * kEpsV, 0.999 * kEpsV, 2.0 * kEpsV, 40.0 * kEpsV};
  const int n = static_cast<int>(slip.size());
  Samples s = samples(n);
  VolumeContactTerms t = makeVolumeContactTerms(s.sampling, n, floorPlane(), s.params);
  t.state->beginStep(s.start, 0.0, kStep);
  Eigen::VectorXd x = s.start;
  for (int i = 0; i < n; ++i) {
    const double angle = 0.7 * i;
    x.segment<3>(3 * i) += Eigen::Vector3d(slip[i] * std::cos(angle), slip[i] * std::sin(angle), -2e-5);
  }
  const DenseEvaluation exact = evaluateWith(*t.friction, x, FrictionHessian::Exact);
  const DenseEvaluation major = evaluateWith(*t.friction, x, FrictionHessian::Majorizer);
  CHECK(major.energy == Approx(exact.energy).epsilon(1e-14));
  CHECK((major.gradient - exact.gradient).norm() <= 1e-14 * exact.gradient.norm());
  const Eigen::Matrix3d tangent = Eigen::Vector3d(1, 1, 0).asDiagonal();  // I − n nᵀ, n = z
  for (int i = 0; i < n; ++i) {
    INFO("sample " << i << ", slip " << slip[i] / kEpsV << " eps_v");
    const Eigen::Matrix3d He = exact.hessian.block<3, 3>(3 * i, 3 * i);
    const Eigen::Matrix3d Hm = major.hessian.block<3, 3>(3 * i, 3 * i);
    // f₁(y)/y: 2/ε − y/ε² in the regularization (2/ε at zero slip), 1/y sliding.
    const double y = std::hypot(x[3 * i] - s.start[3 * i], x[3 * i + 1] - s.start[3 * i + 1]);
    const double secant = y < kEpsV ? 2.0 / kEpsV - y / (kEpsV * kEpsV) : 1.0 / y;
    CHECK((Hm - kFrictionLimit * secant * tangent).norm() <= 1e-9 * kFrictionLimit * secant);
    // The majorizer's Hessian minus the exact one is positive semi-definite (only along the slip it differs).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> difference(Hm - He);
    CHECK(difference.eigenvalues().minCoeff() >= -1e-9 * Hm.norm());
    if (y >= kEpsV) {
      // Sliding: the exact curvature along the slip is zero, the majorizer's μλ/y.
      const Eigen::Vector3d along(x[3 * i] - s.start[3 * i], x[3 * i + 1] - s.start[3 * i + 1], 0.0);
      CHECK(std::abs(along.dot(He * along)) <= 1e-9 * kFrictionLimit * y);
      CHECK(along.dot(Hm * along) == Approx(kFrictionLimit * y).epsilon(1e-9));
    }
  }
}

TEST_CASE("friction Hessian: from a sliding start, the majorizer's full Newton step lowers the energy and brings "
          "held samples towards sticking, the exact Hessian's overshoots past the stick region", "[contact]") {
  // Each sample is pulled sideways by a soft spring (the rest of a shell) whose force at the step's start is a
  // fraction of μλ, so the solution sticks (slip below ε_v); the iterate has every sample 5 ε_v away, sliding
  // with or against the pull.
  const std::vector<double> pull = {0.3, 0.6, 0.8, 0.95};
  const int n = static_cast<int>(pull.size());
  Samples s = samples(n);
  AnchorSpring spring;
  spring.stiffness = 1.0;  // N/m, against μλ/ε_v = 250 N/m: cloth on a floor
  for (int i = 0; i < n; ++i)
    spring.anchor.emplace_back(s.start.segment<3>(3 * i) +
                               Eigen::Vector3d(pull[i] * kFrictionLimit / spring.stiffness, 0.0, 0.0));
  VolumeContactTerms t = makeVolumeContactTerms(s.sampling, n, floorPlane(), s.params);
  t.state->beginStep(s.start, 0.0, kStep);
  ElementEnergyTerm<AnchorSpring> anchors("anchor", StencilTable{1, {0, 1, 2, 3}}, n, spring, false, false);
  const std::vector<EnergyTerm*> terms = {t.friction.get(), t.penalty.get(), &anchors};
  Eigen::VectorXd x = s.start;
  for (int i = 0; i < n; ++i) x[3 * i] += (i % 2 == 0 ? 5.0 : -5.0) * kEpsV;

  auto energy = [&](const Eigen::VectorXd& at) {
    double e = 0.0;
    for (EnergyTerm* term : terms) e += term->evaluate(at, {}, {});
    return e;
  };
  auto fullStep = [&](FrictionHessian model) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(x.size(), x.size());
    for (EnergyTerm* term : terms) {
      const DenseEvaluation e = evaluateWith(*term, x, model);
      g += e.gradient;
      H += e.hessian;
    }
    return Eigen::VectorXd(x + H.ldlt().solve(-g));
  };
  const Eigen::VectorXd exact = fullStep(FrictionHessian::Exact);
  const Eigen::VectorXd major = fullStep(FrictionHessian::Majorizer);
  const double e0 = energy(x), eExact = energy(exact), eMajor = energy(major);
  INFO("energy: start " << e0 << " J, after the exact step " << eExact << " J, after the majorizer's " << eMajor
                        << " J");
  // Majorization–minimization: the model bounds the energy from above and touches it at x, so its minimizer
  // cannot raise it.
  CHECK(eMajor < e0);
  CHECK(eExact > e0);
  for (int i = 0; i < n; ++i) {
    const double slipExact = exact[3 * i] - s.start[3 * i], slipMajor = major[3 * i] - s.start[3 * i];
    INFO("sample " << i << ": pull " << pull[i] << " mu lambda; slip after the step: exact " << slipExact / kEpsV
                   << " eps_v, majorizer " << slipMajor / kEpsV << " eps_v");
    CHECK(std::abs(slipMajor) < 5.0 * kEpsV);
    // The exact model sees only the spring along a sliding slip: its step lands (μλ ∓ F)/k away, on the other
    // side of the stick region.
    CHECK(std::abs(slipExact) > 25.0 * kEpsV);
    CHECK(slipExact * (x[3 * i] - s.start[3 * i]) < 0.0);
  }
}
