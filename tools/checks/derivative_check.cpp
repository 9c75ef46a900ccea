#include "tools/checks/derivative_check.h"

#include "core/assembly.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace jetshell {
namespace {

/// Derivative of f at x0 by Ridders' method: central differences on h0, h0/2, ... and Richardson's tableau.
/// Each difference divides by the step actually taken, (x0 + h) − (x0 − h), not by 2h: for a coordinate far
/// from 0 the two differ by ~eps·|x0|/h, a bias that no tableau estimate sees.
struct Extrapolated {
  Eigen::VectorXd derivative;
  double errorEstimate = std::numeric_limits<double>::infinity();
};

template <typename F>
Extrapolated riddersSequence(const F& f, double x0, double h0, int steps) {
  constexpr double kShrink = 2.0;
  constexpr double kFactor = kShrink * kShrink;  // central differences: the error is a series in h²
  constexpr double kSafe = 2.0;                  // stop once the extrapolation gets this much worse (NR's SAFE)
  const double eps = std::numeric_limits<double>::epsilon();
  std::vector<std::vector<Eigen::VectorXd>> a(static_cast<std::size_t>(steps));
  Extrapolated best;
  double h = h0;
  double noise = 0.0;
  for (int i = 0; i < steps; ++i, h /= kShrink) {
    a[i].resize(static_cast<std::size_t>(i) + 1);
    const double xp = x0 + h, xm = x0 - h;
    const Eigen::VectorXd fp = f(xp), fm = f(xm);
    a[i][0] = (fp - fm) / (xp - xm);
    // Round-off of this difference; every entry of row i inherits it: without it, the smallest of many noisy
    // estimates would be picked by chance at tiny steps.
    noise = std::max(noise, eps * (fp.norm() + fm.norm()) / (xp - xm));
    if (i == 0) {
      best.derivative = a[0][0];
      continue;
    }
    double fac = kFactor;
    for (int j = 1; j <= i; ++j, fac *= kFactor) {
      a[i][j] = (fac * a[i][j - 1] - a[i - 1][j - 1]) / (fac - 1.0);
      // Ridders' estimate: the distance to the two lower-order neighbours in the tableau.
      const double err =
          std::max({(a[i][j] - a[i][j - 1]).norm(), (a[i][j] - a[i - 1][j - 1]).norm(), noise});
      if (err <= best.errorEstimate) {
        best.errorEstimate = err;
        best.derivative = a[i][j];
      }
    }
    if ((a[i][i] - a[i - 1][i - 1]).norm() >= kSafe * best.errorEstimate) break;
  }
  return best;
}

/// Step selection: Ridders' estimate can be fooled by a function that looks smooth on scales larger than its
/// own feature size (a fold a few 1e-4 rad from 180° seen with steps of 1e-3), converging confidently to a wrong
/// value. So sequences starting at h0, h0/2^s, h0/2^2s, ... are run until two consecutive ones agree within
/// their estimates and to within 100× the target accuracy; the disagreement is part of the reported
/// uncertainty. Without agreement the most consistent pair is returned with its (large) uncertainty.
template <typename F>
Extrapolated extrapolatedDerivative(const F& f, double x0, double h0, int steps, int maxSequences,
                                    double agreement, double floor) {
  constexpr double kAgreement = 10.0;
  constexpr double kAccept = 100.0;
  const int offset = std::max(1, (2 * steps) / 3);  // consecutive sequences overlap by a third of their steps
  std::vector<Extrapolated> seq{riddersSequence(f, x0, h0, steps)};
  Extrapolated fallback = seq[0];
  fallback.errorEstimate = std::numeric_limits<double>::infinity();
  for (int k = 1; k < maxSequences; ++k) {
    seq.push_back(riddersSequence(f, x0, std::ldexp(h0, -offset * k), steps));
    const Extrapolated& p = seq[k - 1];
    const Extrapolated& q = seq[k];
    const double diff = (p.derivative - q.derivative).norm();
    Extrapolated better = p.errorEstimate <= q.errorEstimate ? p : q;
    better.errorEstimate = std::max(better.errorEstimate, diff);
    // Agreement within the estimates, or within the accuracy asked for (round-off can make the estimates of a
    // nearly linear function meaninglessly small).
    const double target = agreement * std::max({p.derivative.norm(), q.derivative.norm(), floor});
    // The less precise sequence must confirm the more precise one at the latter's precision: a wide estimate
    // (large steps straddling a sharp feature) confirms nothing. Two sequences that agree only roughly (both
    // straddling it) do not end the search either.
    const bool agree = diff <= kAgreement * std::min(p.errorEstimate, q.errorEstimate) + target &&
                       better.errorEstimate <= kAccept * target;
    // Smaller steps carry more round-off, so an earlier pair that disagreed only by round-off may still be
    // the better answer.
    if (better.errorEstimate < fallback.errorEstimate) fallback = better;
    if (agree) return fallback;
  }
  return maxSequences > 1 ? fallback : seq[0];
}

bool allFinite(const DenseDerivatives& d) {
  return std::isfinite(d.energy) && d.gradient.allFinite() && d.hessian.allFinite();
}

EvalOptions withPath(EvalOptions o, DerivativePath p) {
  o.path = p;
  return o;
}

}  // namespace

DenseDerivatives evaluateDense(EnergyTerm& term, const Eigen::VectorXd& x, const EvalOptions& options,
                               bool wantHessian) {
  DenseDerivatives d;
  d.gradient = Eigen::VectorXd::Zero(x.size());
  if (!wantHessian) {
    d.energy = term.evaluate(x, EvalRequest{&d.gradient, nullptr, -1}, options);
    return d;
  }
  HessianAssembler assembler;
  const int slot = assembler.addStencils(term.stencils());
  assembler.finalize(static_cast<int>(x.size() / 3));
  d.energy = term.evaluate(x, EvalRequest{&d.gradient, &assembler, slot}, options);
  const Eigen::MatrixXd upper(assembler.matrix());
  d.hessian = upper + upper.transpose();
  d.hessian.diagonal() -= upper.diagonal();
  return d;
}

double relativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double floor) {
  const double denominator = std::max(b.norm(), floor);
  const double diff = (a - b).norm();
  if (diff == 0.0) return 0.0;
  return denominator > 0.0 ? diff / denominator : std::numeric_limits<double>::infinity();
}

double relativeError(double a, double b, double floor) {
  const double denominator = std::max(std::abs(b), floor);
  const double diff = std::abs(a - b);
  if (diff == 0.0) return 0.0;
  return denominator > 0.0 ? diff / denominator : std::numeric_limits<double>::infinity();
}

double configurationLengthScale(const Eigen::VectorXd& x) {
  const Eigen::Index n = x.size() / 3;
  if (n == 0) return 1.0;
  const auto P = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>>(x.data(), 3, n);
  const Eigen::Vector3d centroid = P.rowwise().mean();
  const double rms = std::sqrt((P.colwise() - centroid).squaredNorm() / static_cast<double>(n));
  return rms > 0.0 ? rms : 1.0;
}

std::optional<double> DerivativeCheckResult::maxAdVsAnalytic() const {
  if (!gradientAdVsAnalytic) return std::nullopt;
  double m = std::max(*energyAdVsAnalytic, *gradientAdVsAnalytic);
  if (hessianAdVsAnalytic) m = std::max(m, *hessianAdVsAnalytic);
  return m;
}

double DerivativeCheckResult::maxVsFd() const {
  double m = 0.0;
  for (const PathCheck& p : paths) {
    m = std::max(m, p.gradientVsFd);
    if (hessianChecked && hessianIsExact) m = std::max(m, p.hessianVsFd);
  }
  return m;
}

double DerivativeCheckResult::maxHessianAsymmetry() const {
  double m = 0.0;
  for (const PathCheck& p : paths) m = std::max(m, p.hessianAsymmetry);
  return m;
}

double DerivativeCheckResult::minHessianEigenvalue() const {
  double m = std::numeric_limits<double>::infinity();
  for (const PathCheck& p : paths) m = std::min(m, p.hessianMinEigenvalue);
  return m;
}

double DerivativeCheckResult::maxFdUncertainty() const {
  double m = gradientFdUncertainty;
  for (const PathCheck& p : paths) m = std::max(m, p.hessianFdUncertainty);
  return m;
}

DerivativeCheckResult checkDerivatives(EnergyTerm& term, const Eigen::VectorXd& x,
                                       const DerivativeCheckOptions& options) {
  DerivativeCheckResult r;
  r.hessianIsExact = options.hessianIsExact;
  r.hessianChecked = options.checkHessian;
  const double ell = options.lengthScale > 0.0 ? options.lengthScale : configurationLengthScale(x);
  r.lengthScale = ell;
  const Eigen::Index ndof = x.size();

  std::vector<DerivativePath> paths{DerivativePath::AutoDiff};
  if (term.hasAnalytic()) paths.push_back(DerivativePath::Analytic);
  std::vector<DenseDerivatives> dense;
  for (DerivativePath p : paths) {
    dense.push_back(evaluateDense(term, x, withPath(options.evalOptions, p), options.checkHessian));
    if (!allFinite(dense.back())) r.finite = false;
  }
  const DenseDerivatives& ref = dense.back();
  const double hNorm = options.checkHessian ? ref.hessian.norm() : 0.0;
  r.energyScale = std::max({std::abs(ref.energy), ref.gradient.norm() * ell, hNorm * ell * ell});
  if (!(r.energyScale > 0.0)) r.energyScale = std::numeric_limits<double>::min();
  const double tau = options.floorFraction;
  const double floorE = tau * r.energyScale, floorG = floorE / ell, floorH = floorG / ell;

  if (dense.size() == 2) {
    r.energyAdVsAnalytic = relativeError(dense[0].energy, dense[1].energy, floorE);
    r.gradientAdVsAnalytic = relativeError(dense[0].gradient, dense[1].gradient, floorG);
    if (options.checkHessian) r.hessianAdVsAnalytic = relativeError(dense[0].hessian, dense[1].hessian, floorH);
  }

  // FD of the energy (path-independent: AD vs analytic checks that the energies agree).
  const EvalOptions refOptions = withPath(options.evalOptions, paths.back());
  const double h0 = options.initialStep * ell;
  Eigen::VectorXd gFd(ndof), gErr(ndof);
  Eigen::VectorXd xs = x;
  for (Eigen::Index i = 0; i < ndof; ++i) {
    auto energyAlong = [&](double xi) {
      xs[i] = xi;
      Eigen::VectorXd v(1);
      v[0] = term.evaluate(xs, EvalRequest{}, refOptions);
      xs[i] = x[i];
      return v;
    };
    const Extrapolated d = extrapolatedDerivative(energyAlong, x[i], h0, options.extrapolationSteps,
                                                        options.maxSequences, options.sequenceAgreement, floorG);
    gFd[i] = d.derivative[0];
    gErr[i] = d.errorEstimate;
  }
  if (!gFd.allFinite()) r.finite = false;
  r.gradientFdUncertainty = relativeError(gFd + gErr, gFd, floorG);

  for (std::size_t k = 0; k < paths.size(); ++k) {
    PathCheck pc;
    pc.path = paths[k];
    pc.energy = dense[k].energy;
    pc.gradientVsFd = relativeError(dense[k].gradient, gFd, floorG);
    if (options.checkHessian) {
      const EvalOptions o = withPath(options.evalOptions, paths[k]);
      Eigen::MatrixXd J(ndof, ndof);
      double errSq = 0.0;
      for (Eigen::Index j = 0; j < ndof; ++j) {
        auto gradientAlong = [&](double xj) {
          xs[j] = xj;
          Eigen::VectorXd g = Eigen::VectorXd::Zero(ndof);
          term.evaluate(xs, EvalRequest{&g, nullptr, -1}, o);
          xs[j] = x[j];
          return g;
        };
        const Extrapolated d = extrapolatedDerivative(gradientAlong, x[j], h0, options.extrapolationSteps,
                                                          options.maxSequences, options.sequenceAgreement, floorH);
        J.col(j) = d.derivative;
        errSq += d.errorEstimate * d.errorEstimate;
      }
      if (!J.allFinite()) r.finite = false;
      const double jDenominator = std::max(J.norm(), floorH);
      pc.hessianVsFd = relativeError(dense[k].hessian, J, floorH);
      pc.hessianAsymmetry = (J - J.transpose()).norm() / jDenominator;
      pc.hessianFdUncertainty = std::sqrt(errSq) / jDenominator;
      if (dense[k].hessian.allFinite() && ndof > 0) {
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(dense[k].hessian, Eigen::EigenvaluesOnly);
        pc.hessianMinEigenvalue = eig.eigenvalues()[0] / std::max(dense[k].hessian.norm(), floorH);
      }
    }
    r.paths.push_back(pc);
  }
  return r;
}

std::vector<std::string> checkFailures(const DerivativeCheckResult& r, const DerivativeTolerances& tol) {
  std::vector<std::string> out;
  auto fail = [&](const std::string& what, double value, double limit, double fdUncertainty = 0.0) {
    if (value <= limit) return;  // also catches NaN
    std::ostringstream s;
    s << what << " = " << value << " > " << limit;
    if (fdUncertainty > limit) s << " (inconclusive: FD uncertainty " << fdUncertainty << ")";
    out.push_back(s.str());
  };
  if (!r.finite) out.push_back("non-finite energy, gradient, Hessian or finite difference");
  if (const auto ad = r.maxAdVsAnalytic()) fail("AD vs analytic", *ad, tol.adVsAnalytic);
  for (const PathCheck& p : r.paths) {
    const std::string name = p.path == DerivativePath::AutoDiff ? "AD" : "analytic";
    fail(name + " gradient vs FD", p.gradientVsFd, tol.vsFd, r.gradientFdUncertainty);
    if (!r.hessianChecked) continue;
    if (r.hessianIsExact) {
      fail(name + " Hessian vs FD", p.hessianVsFd, tol.vsFd, p.hessianFdUncertainty);
    } else {
      fail(name + " model Hessian: -(smallest eigenvalue)/|H|", -p.hessianMinEigenvalue, tol.psd);
    }
    fail(name + " FD Jacobian of the gradient: asymmetry", p.hessianAsymmetry, tol.asymmetry,
         p.hessianFdUncertainty);
  }
  return out;
}

double ParameterCheckResult::maxVsFd() const {
  double m = 0.0;
  for (const ParameterCheck& p : parameters) m = std::max({m, p.energyVsFd, p.mixedVsFd});
  return m;
}

double ParameterCheckResult::maxFdUncertainty() const {
  double m = 0.0;
  for (const ParameterCheck& p : parameters) m = std::max(m, p.fdUncertainty);
  return m;
}

ParameterCheckResult checkParameterDerivatives(EnergyTerm& term, const Eigen::VectorXd& x,
                                               const DerivativeCheckOptions& options) {
  ParameterCheckResult r;
  const std::vector<std::string> names = term.parameterNames();
  if (names.empty()) return r;
  const std::vector<double> p0 = term.parameterValues();
  const EvalOptions o = withPath(options.evalOptions,
                                 term.hasAnalytic() ? DerivativePath::Analytic : DerivativePath::AutoDiff);
  const double ell = options.lengthScale > 0.0 ? options.lengthScale : configurationLengthScale(x);
  const Eigen::Index ndof = x.size();
  Eigen::VectorXd g0 = Eigen::VectorXd::Zero(ndof);
  const double e0 = term.evaluate(x, EvalRequest{&g0, nullptr, -1}, o);
  double S = std::max(std::abs(e0), g0.norm() * ell);
  if (!(S > 0.0)) S = std::numeric_limits<double>::min();
  ParameterDerivatives d;
  term.evaluateParameterDerivatives(x, d);
  if (!(std::isfinite(e0) && g0.allFinite() && d.energy.allFinite() && d.mixed.allFinite())) r.finite = false;
  for (std::size_t j = 0; j < names.size(); ++j) {
    ParameterCheck pc;
    pc.name = names[j];
    pc.value = p0[j];
    const double sigma = p0[j] != 0.0 ? std::abs(p0[j]) : 1.0;
    const double floorE = options.floorFraction * S / sigma, floorG = floorE / ell;
    std::vector<double> p = p0;
    // Energy and gradient together as one vector function of p_j: [E, g].
    auto along = [&](double pj) {
      p[j] = pj;
      term.setParameterValues(p);
      Eigen::VectorXd v = Eigen::VectorXd::Zero(ndof + 1);
      Eigen::VectorXd g = Eigen::VectorXd::Zero(ndof);
      v[0] = term.evaluate(x, EvalRequest{&g, nullptr, -1}, o);
      v.tail(ndof) = g;
      return v;
    };
    const double h0 = options.initialStep * sigma;
    // Energy and gradient need separate floors, so they are extrapolated separately (the same evaluations).
    auto energyAlong = [&](double pj) { return Eigen::VectorXd(along(pj).head(1)); };
    auto gradientAlong = [&](double pj) { return Eigen::VectorXd(along(pj).tail(ndof)); };
    const Extrapolated de = extrapolatedDerivative(energyAlong, p0[j], h0, options.extrapolationSteps,
                                                   options.maxSequences, options.sequenceAgreement, floorE);
    const Extrapolated dg = extrapolatedDerivative(gradientAlong, p0[j], h0, options.extrapolationSteps,
                                                   options.maxSequences, options.sequenceAgreement, floorG);
    term.setParameterValues(p0);
    if (!(de.derivative.allFinite() && dg.derivative.allFinite())) r.finite = false;
    pc.energyVsFd = relativeError(d.energy[static_cast<Eigen::Index>(j)], de.derivative[0], floorE);
    pc.mixedVsFd = relativeError(Eigen::VectorXd(d.mixed.col(static_cast<Eigen::Index>(j))), dg.derivative, floorG);
    pc.fdUncertainty = std::max(de.errorEstimate / std::max(std::abs(de.derivative[0]), floorE),
                                dg.errorEstimate / std::max(dg.derivative.norm(), floorG));
    r.parameters.push_back(pc);
  }
  return r;
}

std::vector<std::string> checkFailures(const ParameterCheckResult& r, const DerivativeTolerances& tol) {
  std::vector<std::string> out;
  if (!r.finite) out.push_back("non-finite parameter derivative or finite difference");
  for (const ParameterCheck& p : r.parameters) {
    for (const auto& [what, value] : {std::pair<const char*, double>{"dE/dp", p.energyVsFd},
                                      std::pair<const char*, double>{"d2E/dxdp", p.mixedVsFd}}) {
      if (value <= tol.vsFd) continue;  // also catches NaN
      std::ostringstream s;
      s << "parameter '" << p.name << "' " << what << " vs FD = " << value << " > " << tol.vsFd;
      if (p.fdUncertainty > tol.vsFd) s << " (inconclusive: FD uncertainty " << p.fdUncertainty << ")";
      out.push_back(s.str());
    }
  }
  return out;
}

}  // namespace jetshell
