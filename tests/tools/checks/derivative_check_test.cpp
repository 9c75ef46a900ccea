// The derivative checker must catch wrong derivatives: each test plants one kind of error in an otherwise
// correct term and requires the matching check to fail, beside the unmodified term passing.
#include "tests/test_util.h"
#include "energies/shell/shell_terms.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <limits>

using namespace jetshell;
using namespace jetshell::test;

namespace {

/// Delegates to a real term, then lets a test edit what it returns on one path.
class MutantTerm : public EnergyTerm {
 public:
  using Edit = std::function<void(const Eigen::VectorXd& x, Eigen::VectorXd* g, HessianAssembler* H, int slot)>;
  MutantTerm(EnergyTermPtr inner, DerivativePath mutated, Edit edit)
      : inner_(std::move(inner)), mutated_(mutated), edit_(std::move(edit)) {}
  std::string name() const override { return "mutant_" + inner_->name(); }
  StencilTable stencils() const override { return inner_->stencils(); }
  bool hasAnalytic() const override { return inner_->hasAnalytic(); }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& r, const EvalOptions& o) override {
    const double e = inner_->evaluate(x, r, o);
    if (o.path == mutated_) edit_(x, r.gradient, r.hessian, r.hessianSlot);
    return e;
  }

 private:
  EnergyTermPtr inner_;
  DerivativePath mutated_;
  Edit edit_;
};

/// E = ½ xᵀ S x with S symmetric, but the "gradient" returned is A x with A = S + K, K skew: the gradient of
/// no energy. The Hessian reports S.
class NonConservativeTerm : public EnergyTerm {
 public:
  explicit NonConservativeTerm(int ndof) : S_(Eigen::MatrixXd::Identity(ndof, ndof)), K_(Eigen::MatrixXd::Zero(ndof, ndof)) {
    for (int i = 0; i + 1 < ndof; ++i) {
      S_(i, i + 1) = S_(i + 1, i) = 0.3;
      K_(i, i + 1) = 0.2;
      K_(i + 1, i) = -0.2;
    }
  }
  std::string name() const override { return "non_conservative"; }
  StencilTable stencils() const override { return {}; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& r, const EvalOptions&) override {
    if (r.gradient) *r.gradient += (S_ + K_) * x;
    return 0.5 * x.dot(S_ * x);
  }

 private:
  Eigen::MatrixXd S_, K_;
};

struct Setup {
  CheckMesh mesh = makeCheckMeshes()[0];  // the 4-face patch
  ShellMaterialParams material;
  Eigen::VectorXd x = makeCheckConfiguration(mesh, ConfigurationKind::Random, 5).x;
  EnergyTermPtr membrane() const { return makeMembraneTerm(mesh.mesh, mesh.reference, 3.0, 4.0); }
  EnergyTermPtr bending() const { return makeBendingTerm(mesh.mesh, mesh.topology, mesh.reference, 0.3, 0.5); }
};

const DerivativeTolerances kTol;  // the defaults

}  // namespace

TEST_CASE("derivative check: correct terms pass with errors near round-off") {
  ScopedThreads serial(1);
  Setup s;
  for (const EnergyTermPtr& term : {s.membrane(), s.bending()}) {
    INFO(term->name());
    const DerivativeCheckResult r = checkDerivatives(*term, s.x);
    CHECK(checkFailures(r, kTol).empty());
    CHECK(r.finite);
    CHECK(r.paths.size() == 2);
    // Measured on this configuration: vs FD 5e-14 (membrane), 9e-14 (bending); AD vs analytic <= 3e-16.
    CHECK(r.maxVsFd() <= 1e-11);
    CHECK(*r.maxAdVsAnalytic() <= 1e-13);
    CHECK(r.lengthScale == Approx(configurationLengthScale(s.x)));
  }
}

TEST_CASE("derivative check: a gradient off by 1e-6 relative fails against finite differences") {
  ScopedThreads serial(1);
  Setup s;
  MutantTerm term(s.membrane(), DerivativePath::AutoDiff,
                  [](const Eigen::VectorXd&, Eigen::VectorXd* g, HessianAssembler*, int) {
                    if (g) *g *= 1.0 + 1e-6;
                  });
  const DerivativeCheckResult r = checkDerivatives(term, s.x);
  CHECK(r.paths[0].gradientVsFd == Approx(1e-6).epsilon(1e-3));
  CHECK(r.paths[1].gradientVsFd < 1e-11);  // the analytic path is untouched
  CHECK(*r.gradientAdVsAnalytic == Approx(1e-6).epsilon(1e-3));
  // Flagged three ways: against the analytic path, against FD of the energy, and (the AD Hessian being
  // right) against FD of the wrong gradient.
  const auto failures = checkFailures(r, kTol);
  REQUIRE(failures.size() == 3);
  CHECK_THAT(failures[0], Catch::Contains("AD vs analytic"));
  CHECK_THAT(failures[1], Catch::Contains("AD gradient vs FD"));
  CHECK_THAT(failures[2], Catch::Contains("AD Hessian vs FD"));
}

TEST_CASE("derivative check: a Hessian missing its curvature part fails against finite differences") {
  ScopedThreads serial(1);
  Setup s;
  // The Gauss–Newton bending Hessian presented as exact: what a forgotten Σ w_k ∇²b_k looks like.
  const EnergyTermPtr bending = s.bending();
  DerivativeCheckOptions o;
  o.evalOptions.hessianModel = HessianModel::GaussNewton;
  const DerivativeCheckResult wrong = checkDerivatives(*bending, s.x, o);
  CHECK(wrong.maxVsFd() > 1e-3);
  CHECK_FALSE(checkFailures(wrong, kTol).empty());
  // Declared as a model, the same Hessian passes (it is PSD) and its FD gap is reported, not judged.
  o.hessianIsExact = false;
  const DerivativeCheckResult model = checkDerivatives(*bending, s.x, o);
  CHECK(checkFailures(model, kTol).empty());
  CHECK(model.paths[0].hessianVsFd > 1e-3);
  CHECK(model.minHessianEigenvalue() >= -1e-12);
}

TEST_CASE("derivative check: a single wrong Hessian entry is caught") {
  ScopedThreads serial(1);
  Setup s;
  // Perturbs one stored (upper-triangle) entry by 1e-6 of the matrix norm.
  MutantTerm term(s.membrane(), DerivativePath::Analytic,
                  [](const Eigen::VectorXd&, Eigen::VectorXd*, HessianAssembler* H, int) {
                    if (!H) return;
                    auto& m = H->matrix();
                    m.valuePtr()[m.nonZeros() / 2] += 1e-6 * m.norm();
                  });
  const DerivativeCheckResult r = checkDerivatives(term, s.x);
  CHECK(r.paths[1].hessianVsFd > 1e-7);
  CHECK(r.paths[0].hessianVsFd < 1e-11);
  CHECK(*r.hessianAdVsAnalytic > 1e-7);
  CHECK_FALSE(checkFailures(r, kTol).empty());
}

TEST_CASE("derivative check: a gradient that is not the derivative of any energy has an asymmetric Jacobian") {
  ScopedThreads serial(1);
  NonConservativeTerm term(12);
  Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(12, -1.0, 1.0);
  DerivativeCheckOptions o;
  o.checkHessian = true;
  const DerivativeCheckResult r = checkDerivatives(term, x, o);
  // ‖K − Kᵀ‖ / ‖S + K‖: well above round-off.
  CHECK(r.paths[0].hessianAsymmetry > 0.1);
  CHECK(r.paths[0].gradientVsFd > 0.01);
  const auto failures = checkFailures(r, kTol);
  bool asymmetry = false;
  for (const std::string& f : failures) asymmetry |= f.find("asymmetry") != std::string::npos;
  CHECK(asymmetry);
}

TEST_CASE("derivative check: non-finite values fail") {
  ScopedThreads serial(1);
  Setup s;
  MutantTerm term(s.membrane(), DerivativePath::AutoDiff,
                  [](const Eigen::VectorXd&, Eigen::VectorXd* g, HessianAssembler*, int) {
                    if (g) (*g)[0] = std::numeric_limits<double>::quiet_NaN();
                  });
  const DerivativeCheckResult r = checkDerivatives(term, s.x);
  CHECK_FALSE(r.finite);
  const auto failures = checkFailures(r, kTol);
  REQUIRE_FALSE(failures.empty());
  CHECK_THAT(failures[0], Catch::Contains("non-finite"));
}

TEST_CASE("derivative check: relative errors use the floor only for vanishing references") {
  Eigen::VectorXd a(2), b(2);
  a << 1.0, 2.0;
  b << 1.0, 2.0 + 1e-6;
  CHECK(relativeError(a, b, 1e-3) == Approx(1e-6 / b.norm()));
  CHECK(relativeError(a, b, 1e3) == Approx(1e-6 / 1e3));
  CHECK(relativeError(Eigen::VectorXd::Constant(2, 1e-9), Eigen::VectorXd::Zero(2), 1e-3) ==
        Approx(std::sqrt(2.0) * 1e-6));
  CHECK(relativeError(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(2), 0.0) == 0.0);
  CHECK(std::isinf(relativeError(Eigen::VectorXd::Ones(2), Eigen::VectorXd::Zero(2), 0.0)));
  CHECK(relativeError(3.0, 2.0, 0.5) == Approx(0.5));
}

TEST_CASE("derivative check: at rest the floor keeps round-off in a vanishing gradient from counting") {
  ScopedThreads serial(1);
  Setup s;
  const EnergyTermPtr term = s.bending();
  const DerivativeCheckResult r = checkDerivatives(*term, flatten(s.mesh.mesh.V));
  CHECK(r.energyScale > 0.0);
  CHECK(checkFailures(r, kTol).empty());
}
