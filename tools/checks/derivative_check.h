// Finite-difference validation of an energy term's derivatives (in the spirit of Ceres' GradientChecker).
//
// At one configuration x, checkDerivatives() evaluates the term on every derivative path it has (AutoDiff, and
// Analytic when hasAnalytic()), and compares
//   - AD with analytic: energy, gradient, Hessian;
//   - each path's gradient with central differences of the energy;
//   - each path's Hessian with central differences of that path's gradient (the full, unsymmetrized Jacobian J);
//   - the symmetry of J itself: a gradient whose Jacobian is not symmetric is not the gradient of any energy.
// The assembled Hessian is symmetric by construction (the assembler reads only the upper triangle of element
// blocks), so symmetry is checked where it can fail: on J, and by comparing both triangles of H with J.
//
// Finite differences: for each coordinate, central differences D(h) = (f(x + h e_i) − f(x − h e_i)) / (step
// actually taken) on the steps h0, h0/2, h0/4, ... (h0 = initialStep · lengthScale) are extrapolated with
// Richardson's tableau (Ridders' method), which cancels the h², h⁴, ... error terms; the entry with the smallest
// estimated error (never below the round-off of its differences) is kept. Step selection: that estimate can be
// fooled by a function that looks smooth on scales larger than its own feature size (a fold within 1e-4 rad of
// 180°, or a triangle of aspect 1e-5, probed with steps of 1e-3), so further tableaus starting at ever smaller
// h0 are run until two consecutive ones agree accurately. The reported FD uncertainty is the larger of the
// estimate and that disagreement; when it exceeds the tolerance too, a failure is reported as inconclusive.
// Measured reach (tools/cmd_check_derivatives.cpp): folds to 2e-5 rad from 180° and aspect ratios to 1e-5;
// beyond, the checks fail (in the sweeps they never passed falsely).
//
// Relative errors: relErr(A, B) = ‖A − B‖ / max(‖B‖, floor) (Euclidean norm for vectors, Frobenius for
// matrices), with B the reference (analytic for AD vs analytic; finite differences for the FD checks). The floor
// keeps quantities that vanish (the gradient at rest, the Hessian of a linear term) from turning round-off into
// huge relative errors. It is tied to the term's scale at x: with ℓ the length scale,
//   S = max(|E|, ‖g‖ ℓ, ‖H‖ ℓ²)   (an energy),
//   floor_E = τ S,  floor_g = τ S / ℓ,  floor_H = τ S / ℓ²,   τ = floorFraction (default 1e-3),
// i.e. errors in a small gradient count relative to the force a deformation of τ·ℓ would produce. g and H are
// those of the reference path (analytic when present).
#pragma once

#include "core/term.h"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace jetshell {

/// Energy, gradient (3N) and dense symmetric Hessian (3N×3N, both triangles) of one term at x.
struct DenseDerivatives {
  double energy = 0.0;
  Eigen::VectorXd gradient;
  Eigen::MatrixXd hessian;  // empty when not requested
};

/// Evaluates the term through the ordinary assembly path (HessianAssembler, upper triangle) and mirrors the
/// Hessian into a dense symmetric matrix. For tests and checks on small meshes only.
DenseDerivatives evaluateDense(EnergyTerm& term, const Eigen::VectorXd& x, const EvalOptions& options,
                               bool wantHessian = true);

/// ‖a − b‖ / max(‖b‖, floor) with the Euclidean / Frobenius norm (see the file comment).
double relativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double floor);
double relativeError(double a, double b, double floor);

/// Characteristic length of a configuration: the RMS distance of the vertices from their centroid (1 when
/// all vertices coincide). Rigid motions do not change it.
double configurationLengthScale(const Eigen::VectorXd& x);

struct DerivativeCheckOptions {
  /// Options for every evaluation; `path` is set by the checker. Use projection None: a projected Hessian is not
  /// a derivative.
  EvalOptions evalOptions;
  /// False for model Hessians that are not the derivative of the gradient (Gauss–Newton bending): their
  /// comparison with finite differences is reported but not judged, and they are required to be PSD instead.
  bool hessianIsExact = true;
  bool checkHessian = true;
  double lengthScale = 0.0;   // ℓ; 0 = configurationLengthScale(x)
  double initialStep = 1e-2;  // h0 / ℓ
  int extrapolationSteps = 10;  // steps h0, h0/2, ..., h0/2^(n−1) in one Richardson tableau
  int maxSequences = 4;         // tableaus tried, each starting 2^(2n/3) smaller, until two agree
  double sequenceAgreement = 1e-9;  // target accuracy, relative to max(|D|, floor): two tableaus agree within
                                    // their estimates or this, and the search goes on while worse than 100× it
  double floorFraction = 1e-3;  // τ
};

/// One derivative path compared with finite differences.
struct PathCheck {
  DerivativePath path = DerivativePath::AutoDiff;
  double energy = 0.0;
  double gradientVsFd = 0.0;      // relErr(g, FD of E)
  double hessianVsFd = 0.0;       // relErr(H, J), J = FD of this path's gradient (0 when not checked)
  double hessianAsymmetry = 0.0;  // ‖J − Jᵀ‖ / max(‖J‖, floor_H)
  double hessianFdUncertainty = 0.0;  // Richardson's error estimate of J, relative like hessianVsFd
  double hessianMinEigenvalue = 0.0;  // smallest eigenvalue of H / max(‖H‖, floor_H) (PSD check of models)
};

struct DerivativeCheckResult {
  double lengthScale = 0.0;  // ℓ
  double energyScale = 0.0;  // S
  bool hessianIsExact = true;
  bool hessianChecked = true;
  bool finite = true;  // every evaluated energy, gradient and Hessian entry is finite
  /// AD vs analytic (reference: analytic); absent when the term has no analytic path.
  std::optional<double> energyAdVsAnalytic, gradientAdVsAnalytic, hessianAdVsAnalytic;
  double gradientFdUncertainty = 0.0;  // Richardson's error estimate of the FD gradient, relative
  std::vector<PathCheck> paths;       // AutoDiff first, then Analytic when present

  /// The largest AD-vs-analytic error (energy, gradient, Hessian), or nothing without an analytic path.
  std::optional<double> maxAdVsAnalytic() const;
  /// The largest judged error against finite differences over paths: gradient, and Hessian when exact.
  double maxVsFd() const;
  double maxHessianAsymmetry() const;
  /// The smallest relative eigenvalue over paths (only meaningful when the Hessian was checked).
  double minHessianEigenvalue() const;
  double maxFdUncertainty() const;
};

/// Checks the term's derivatives at x (size 3N). Costs about 2·n·3N energy evaluations and 2·n·3N gradient
/// evaluations per path (n = extrapolationSteps): meant for meshes of a few dozen vertices.
DerivativeCheckResult checkDerivatives(EnergyTerm& term, const Eigen::VectorXd& x,
                                       const DerivativeCheckOptions& options = {});

/// Pass/fail limits for a DerivativeCheckResult. Measured over 1000 configurations per registered term
/// (`jetshell check-derivatives --configs 100 --seed 7`): AD vs analytic <= 3.1e-13, vs FD <= 1.5e-10,
/// asymmetry <= 2.2e-10, FD uncertainty <= 4.2e-9, Gauss–Newton smallest eigenvalue >= −2.4e-16 ‖H‖. The limits
/// leave a margin of ~100× (AD vs analytic: the 1e-10); a real derivative bug is typically >= 1e-6.
struct DerivativeTolerances {
  double adVsAnalytic = 1e-10;
  double vsFd = 1e-8;
  double asymmetry = 1e-8;
  double psd = 1e-12;  // model Hessians: smallest eigenvalue >= −psd · ‖H‖
};

/// The violated tolerances, one human-readable line each; empty when the check passes. Non-finite values fail.
std::vector<std::string> checkFailures(const DerivativeCheckResult& result, const DerivativeTolerances& tolerances);

/// One parameter p_j of a term (EnergyTerm::parameterNames()) checked at x: the dual-number derivatives
/// (evaluateParameterDerivatives) against Richardson-extrapolated central differences in p_j of the energy and
/// of the gradient (the term's parameters are changed with setParameterValues and restored).
/// Relative errors as above, with σ_j = |p_j| (1 when p_j = 0) as the parameter's scale:
/// floor(∂E/∂p_j) = τ S / σ_j, floor(∂g/∂p_j) = τ S / (ℓ σ_j), S = max(|E|, ‖g‖ ℓ).
struct ParameterCheck {
  std::string name;
  double value = 0.0;
  double energyVsFd = 0.0;     // relErr(∂E/∂p_j, FD)
  double mixedVsFd = 0.0;      // relErr(∂²E/∂x∂p_j, FD of the gradient)
  double fdUncertainty = 0.0;  // Richardson's error estimate, relative like the errors (max of both)
};

struct ParameterCheckResult {
  bool finite = true;
  std::vector<ParameterCheck> parameters;  // in parameterNames() order
  double maxVsFd() const;
  double maxFdUncertainty() const;
};

/// Checks ∂E/∂p and ∂²E/∂x∂p of every parameter of the term at x (nothing for a term without parameters).
/// Uses options.evalOptions (the analytic path when the term has one), initialStep (relative to σ_j),
/// extrapolationSteps, maxSequences, sequenceAgreement and floorFraction.
ParameterCheckResult checkParameterDerivatives(EnergyTerm& term, const Eigen::VectorXd& x,
                                               const DerivativeCheckOptions& options = {});

/// Failures of a parameter check against tolerances.vsFd (one line each; non-finite values fail).
std::vector<std::string> checkFailures(const ParameterCheckResult& result, const DerivativeTolerances& tolerances);

}  // namespace jetshell
