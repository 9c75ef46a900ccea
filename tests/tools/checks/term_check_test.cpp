#include "tools/checks/term_check.h"

#include "energies/examples/seam_spring.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

using namespace jetshell;
using namespace jetshell::test;

namespace {

/// The seam spring with one derivative deliberately wrong, to see that the helper notices.
class BrokenSpring : public EnergyTerm {
 public:
  enum Fault { Gradient, Parameter };
  BrokenSpring(EnergyTermPtr inner, Fault fault) : inner_(std::move(inner)), fault_(fault) {}
  std::string name() const override { return "broken"; }
  StencilTable stencils() const override { return inner_->stencils(); }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& r, const EvalOptions& o) override {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
    const double e = inner_->evaluate(x, EvalRequest{&g, r.hessian, r.hessianSlot}, o);
    if (r.gradient) *r.gradient += fault_ == Gradient ? 1.001 * g : g;
    return e;
  }
  std::vector<std::string> parameterNames() const override { return inner_->parameterNames(); }
  std::vector<double> parameterValues() const override { return inner_->parameterValues(); }
  void setParameterValues(const std::vector<double>& v) override { inner_->setParameterValues(v); }
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override {
    inner_->evaluateParameterDerivatives(x, out);
    if (fault_ == Parameter) out.mixed *= 1.001;
  }

 private:
  EnergyTermPtr inner_;
  Fault fault_;
};

std::vector<std::array<int, 2>> allEdges(const Topology& t) {
  std::vector<std::array<int, 2>> pairs;
  for (int e = 0; e < t.numEdges(); ++e) pairs.push_back({t.edges(e, 0), t.edges(e, 1)});
  return pairs;
}

}  // namespace

TEST_CASE("term check: a correct term outside the registry passes every check in one call") {
  ScopedThreads serial(1);
  const auto failures = termCheckFailures(
      [](const TermSetup& s) { return makeSeamSpringTerm(s.mesh, allEdges(s.topology), 3.0); });
  for (const std::string& f : failures) FAIL_CHECK(f);
  CHECK(failures.empty());
}

TEST_CASE("term check: a wrong gradient or a wrong parameter derivative is reported") {
  ScopedThreads serial(1);
  const CheckMesh m = makeCheckMeshes().front();
  const Eigen::VectorXd x = makeCheckConfiguration(m, ConfigurationKind::Random, 3).x;
  BrokenSpring gradient(makeSeamSpringTerm(m.mesh, allEdges(m.topology), 3.0), BrokenSpring::Gradient);
  const auto g = termCheckFailures(gradient, x);
  REQUIRE_FALSE(g.empty());
  CHECK_THAT(g.front(), Catch::Contains("gradient vs FD"));
  BrokenSpring parameter(makeSeamSpringTerm(m.mesh, allEdges(m.topology), 3.0), BrokenSpring::Parameter);
  const auto p = termCheckFailures(parameter, x);
  REQUIRE(p.size() == 1);
  CHECK_THAT(p.front(), Catch::Contains("parameter 'stiffness' d2E/dxdp"));
}
