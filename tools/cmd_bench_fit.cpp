// `jetshell bench fit`: derivative-free against gradient-based fitting on a synthetic recovery. The fit file
// (default examples/fit_synthetic_plate.json) is fitted once per algorithm from its initial values; the truth is
// the scene's own material values (the observations were made with them). Reports per algorithm: forward
// evaluations (each solves every observed load level), evaluations until every parameter is within --tolerance
// of the truth (relative), Newton iterations and factorizations, the derivative cost (exact-Hessian
// factorizations and triangular solves), wall and CPU time, final misfit and parameter error.
// --demos adds the two demos of FITTING.md: the cloth overhang (fitted flexural rigidity against the self-weight
// elastica and ASTM D1388's G = w (l/2)³) and the slit annular plate's effective E against Sze's curves.
// --dynamic adds the same comparison on a dynamic recovery (examples/fit_swinging_strip.json: mass damping and
// density of a swinging strip from tip positions at eight times; each evaluation is one run of 16 time steps, the
// derivatives forward sensitivities carried through them).
#include "tools/bench_cloth.h"

#include "core/math_constants.h"
#include "tools/fit/fit_optimizer.h"
#include "tools/fit/fit_setup.h"
#include "tools/output/atomic_file.h"
#include "tools/subcommand.h"
#include "validation/self_weight_elastica.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>

namespace jetshell::cli {
namespace {

struct FitBenchArgs {
  std::string fit = std::string(JETSHELL_SOURCE_DIR) + "/examples/fit_synthetic_plate.json";
  std::vector<std::string> algorithms{"levenberg-marquardt", "lbfgs", "mma", "bobyqa", "nelder-mead"};
  double tolerance = 1e-6;
  int maxEvaluations = 400;
  bool demos = false;
  bool dynamic = false;
  bool skipSynthetic = false;
  std::string json;
};

/// Runs one example fit file with its own settings; prints and returns its figures.
nlohmann::json runDemo(const std::string& name, const std::function<nlohmann::json(const FitFile&, const FitResult&)>& compare) {
  const std::string path = std::string(JETSHELL_SOURCE_DIR) + "/examples/" + name;
  const FitFile file = loadFitFile(path);
  FitSetup setup(file);
  const double cpu0 = processCpuSeconds();
  const FitResult r = runFit(setup.problem(), setup.variables(), file.options);
  const double cpu = processCpuSeconds() - cpu0;
  nlohmann::json j = {{"fit_file", name},
                      {"algorithm", toString(r.algorithm)},
                      {"success", r.success},
                      {"termination", r.termination},
                      {"evaluations", r.counters.evaluations},
                      {"full_solves", r.counters.fullSolves},
                      {"newton_iterations", r.counters.newtonIterations},
                      {"sensitivity_solves", r.counters.sensitivitySolves},
                      {"wall_seconds", r.wallSeconds},
                      {"cpu_seconds", cpu},
                      {"misfit", r.misfit},
                      {"value", r.q.size() > 0 ? r.q[0] : 0.0},
                      {"standard_deviation", r.uncertainty.available ? r.uncertainty.standardDeviation[0] : 0.0}};
  std::printf("\n%s: %s (%s), %d evaluations (%d full solves, %d Newton iterations), %.2f s wall, %.2f s CPU, misfit %.4e\n",
              name.c_str(), r.success ? "converged" : "NOT converged", r.termination.c_str(), r.counters.evaluations,
              r.counters.fullSolves, r.counters.newtonIterations, r.wallSeconds, cpu, r.misfit);
  if (r.q.size() > 0)
    std::printf("  %s = %.8g +- %.3g\n", r.variables[0].label.c_str(), r.q[0],
                r.uncertainty.available ? r.uncertainty.standardDeviation[0] : 0.0);
  j.update(compare(file, r));
  return j;
}

nlohmann::json overhangComparison(const FitFile& file, const FitResult& r) {
  // The strip's geometry and weight from the example: l 0.05 m, w = ρ_A g, flexural rigidity D = β per width.
  const double l = 0.05, w = file.material.shell.density * 9.81, theta = 41.5 * kPi / 180.0;
  const double elastica = validation::rigidityForChordAngle(l, w, theta);  // per unit width (w per area)
  const double astm = w * std::pow(0.5 * l, 3.0);
  const double c = validation::peirceBendingLength(l, theta);
  const double peirce = w * c * c * c;
  const double fitted = r.q.size() > 0 ? r.q[0] : 0.0;
  std::printf("  flexural rigidity [N m]: fitted %.6e, elastica %.6e (fitted/elastica - 1 = %+.3f%%), ASTM w (l/2)^3 %.6e "
              "(%+.3f%%), Peirce's cos/tan formula %.6e (%+.3f%%)\n",
              fitted, elastica, 100.0 * (fitted / elastica - 1.0), astm, 100.0 * (fitted / astm - 1.0), peirce,
              100.0 * (fitted / peirce - 1.0));
  return {{"elastica_rigidity", elastica}, {"astm_rigidity", astm}, {"peirce_rigidity", peirce},
          {"relative_difference_to_elastica", fitted / elastica - 1.0}};
}

nlohmann::json slitPlateComparison(const FitFile&, const FitResult& r) {
  const double E = r.q.size() > 0 ? r.q[0] : 0.0;
  std::printf("  effective E / 21e6 = %.5f (the discretization's stiffness relative to Sze's reference)\n", E / 21e6);
  return {{"relative_to_nominal", E / 21e6}};
}

double maxRelativeError(const Eigen::VectorXd& q, const Eigen::VectorXd& truth) {
  double e = 0.0;
  for (Eigen::Index i = 0; i < q.size(); ++i) e = std::max(e, std::abs(q[i] / truth[i] - 1.0));
  return e;
}

int runSynthetic(const FitBenchArgs& a, nlohmann::json& out) {
  const FitFile file = loadFitFile(a.fit);
  Eigen::VectorXd truth(static_cast<Eigen::Index>(file.parameters.size()));
  for (std::size_t i = 0; i < file.parameters.size(); ++i)
    truth[static_cast<Eigen::Index>(i)] = materialBaseValue(file.material, file.parameters[i].name);
  nlohmann::json rows = nlohmann::json::array();
  std::printf("fit file: %s (%zu parameters; truth = the scene's values; levels are %ss)\n", a.fit.c_str(),
              file.parameters.size(), file.scene.analysis.type == AnalysisType::Dynamic ? "time" : "load factor");
  std::printf("\n");
  std::printf("| algorithm | evaluations | to %.0e | full solves to %.0e | time steps | Newton it. | Newton fact. | deriv. fact. | deriv. solves | solves per deriv. fact. | wall s | CPU s | final misfit | max rel. error |\n",
              a.tolerance, a.tolerance);
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  int failures = 0;
  for (const std::string& name : a.algorithms) {
    FitOptions o = file.options;
    o.algorithm = fitAlgorithmFromString(name);
    o.maxEvaluations = a.maxEvaluations;
    o.misfitTolerance = 0.0;  // stop on the parameter step only, the same rule for every algorithm
    FitSetup setup(file);
    const int levels = static_cast<int>(setup.problem().levels().size());
    const double cpu0 = processCpuSeconds();
    const FitResult r = runFit(setup.problem(), setup.variables(), o);
    const double cpu = processCpuSeconds() - cpu0;
    int reached = -1;
    for (const FitRecord& h : r.history)
      if (h.ok && maxRelativeError(h.q, truth) <= a.tolerance) {
        reached = h.evaluation;
        break;
      }
    const FitCounters& k = r.counters;
    // Triangular solves per exact-Hessian factorization: per observed level (static) or per time step (dynamic),
    // 1 for an adjoint gradient, Q for forward sensitivities.
    const double perGradient =
        k.sensitivityFactorizations > 0 ? static_cast<double>(k.sensitivitySolves) / k.sensitivityFactorizations : 0.0;
    const double error = r.q.size() > 0 ? maxRelativeError(r.q, truth) : std::numeric_limits<double>::infinity();
    if (reached < 0) ++failures;
    std::printf("| %s | %d | %s | %s | %d | %d | %d | %d | %d | %.2g | %.2f | %.2f | %.3e | %.1e |\n", name.c_str(),
                k.evaluations, reached > 0 ? std::to_string(reached).c_str() : "not reached",
                reached > 0 ? std::to_string(reached * k.fullSolves / std::max(1, k.evaluations)).c_str() : "-",
                k.timeSteps, k.newtonIterations,
                k.newtonFactorizations, k.sensitivityFactorizations, k.sensitivitySolves, perGradient, r.wallSeconds,
                cpu, r.misfit, error);
    rows.push_back({{"algorithm", name},
                    {"termination", r.termination},
                    {"evaluations", k.evaluations},
                    {"evaluations_to_tolerance", reached},
                    {"levels", levels},
                    {"full_solves", k.fullSolves},
                    {"time_steps", k.timeSteps},
                    {"newton_iterations", k.newtonIterations},
                    {"newton_factorizations", k.newtonFactorizations},
                    {"gradient_evaluations", k.gradientEvaluations},
                    {"jacobian_evaluations", k.jacobianEvaluations},
                    {"sensitivity_factorizations", k.sensitivityFactorizations},
                    {"sensitivity_solves", k.sensitivitySolves},
                    {"wall_seconds", r.wallSeconds},
                    {"cpu_seconds", cpu},
                    {"final_misfit", r.misfit},
                    {"max_relative_error", error}});
  }
  // The target: gradient-based needs at least 5x fewer solves than derivative-free to reach the tolerance.
  auto best = [&](bool derivatives) {
    int b = -1;
    for (const nlohmann::json& row : rows) {
      const int e = row["evaluations_to_tolerance"];
      if (usesDerivatives(fitAlgorithmFromString(row["algorithm"])) == derivatives && e > 0 && (b < 0 || e < b)) b = e;
    }
    return b;
  };
  const int gradientBest = best(true), freeBest = best(false);
  if (gradientBest > 0 && freeBest > 0)
    std::printf("\nsolves to %.0e: best derivative-free %d, best gradient-based %d: ratio %.1f\n", a.tolerance, freeBest,
                gradientBest, static_cast<double>(freeBest) / gradientBest);
  out = {{"fit_file", a.fit}, {"tolerance", a.tolerance}, {"runs", rows},
         {"best_gradient_based", gradientBest}, {"best_derivative_free", freeBest}};
  return failures == 0 ? kOk : kFailed;
}

int run(const FitBenchArgs& a) {
  nlohmann::json j;
  int code = kOk;
  std::printf("load average at start: %.2f\n", loadAverage());
  if (!a.skipSynthetic) {
    nlohmann::json synthetic;
    code = runSynthetic(a, synthetic);
    j["synthetic"] = synthetic;
  }
  if (a.dynamic) {
    FitBenchArgs d = a;
    d.fit = std::string(JETSHELL_SOURCE_DIR) + "/examples/fit_swinging_strip.json";
    nlohmann::json dynamic;
    std::printf("\n");
    const int c = runSynthetic(d, dynamic);
    if (c != kOk) code = c;
    j["dynamic"] = dynamic;
  }
  if (a.demos) {
    j["overhang"] = runDemo("fit_cloth_overhang.json", overhangComparison);
    j["slit_plate"] = runDemo("fit_sze_slit_plate.json", slitPlateComparison);
  }
  std::printf("load average at end: %.2f\n", loadAverage());
  if (!a.json.empty()) writeFileAtomically(a.json, j.dump(2) + "\n");
  return code;
}

const RegisterSubcommand registerBenchFit("bench-fit", [](CLI::App& app, int& exitCode) {
  auto a = std::make_shared<FitBenchArgs>();
  CLI::App* cmd = benchCommand(app)->add_subcommand(
      "fit", "Fitting: derivative-free against gradient-based on a synthetic recovery (solves, time, misfit)");
  cmd->add_option("--fit", a->fit, "Fit file whose scene's material values are the truth");
  cmd->add_option("--algorithms", a->algorithms, "Algorithms to compare")->delimiter(',');
  cmd->add_option("--tolerance", a->tolerance, "Relative parameter error that counts as recovered")
      ->check(finiteNumber());
  cmd->add_option("--max-evaluations", a->maxEvaluations, "Evaluation cap per algorithm")->check(CLI::Range(1, 100000));
  cmd->add_flag("--demos", a->demos, "Also run the overhang and slit-plate demos (FITTING.md)");
  cmd->add_flag("--dynamic", a->dynamic, "Also compare the algorithms on the dynamic recovery (swinging strip)");
  cmd->add_flag("--no-synthetic", a->skipSynthetic, "Skip the synthetic (static) algorithm comparison");
  cmd->add_option("--json", a->json, "Write the figures as JSON")->check(outputFile());
  cmd->callback([a, &exitCode] { exitCode = run(*a); });
});

}  // namespace
}  // namespace jetshell::cli
