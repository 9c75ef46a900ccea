// `jetshell bench fit`: derivative-free against gradient-based fitting on a synthetic recovery. The fit file
// (default examples/fit_synthetic_plate.json) is fitted once per algorithm from its initial values; the truth is
// the scene's own material values (the observations were made with them). Reports per algorithm: forward
// evaluations (each solves every observed load level), evaluations until every parameter is within --tolerance
// of the truth (relative), Newton iterations and factorizations, the derivative cost (exact-Hessian
// factorizations and triangular solves), wall and CPU time, final misfit and parameter error.
#include "tools/fit/fit_setup.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

namespace jetshell::cli {
namespace {

struct Args {
  std::string fit = std::string(JETSHELL_SOURCE_DIR) + "/examples/fit_synthetic_plate.json";
  std::vector<std::string> algorithms{"levenberg-marquardt", "lbfgs", "mma", "bobyqa", "nelder-mead"};
  double tolerance = 1e-6;
  int maxEvaluations = 400;
  std::string json;
};

double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double maxRelativeError(const Eigen::VectorXd& q, const Eigen::VectorXd& truth) {
  double e = 0.0;
  for (Eigen::Index i = 0; i < q.size(); ++i) e = std::max(e, std::abs(q[i] / truth[i] - 1.0));
  return e;
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string a;
  in >> a;
  return a.empty() ? "?" : a;
}

int run(const Args& a) {
  const FitFile file = loadFitFile(a.fit);
  Eigen::VectorXd truth(static_cast<Eigen::Index>(file.parameters.size()));
  for (std::size_t i = 0; i < file.parameters.size(); ++i)
    truth[static_cast<Eigen::Index>(i)] = materialBaseValue(file.material, file.parameters[i].name);
  nlohmann::json rows = nlohmann::json::array();
  std::printf("fit file: %s (%zu parameters; truth = the scene's values)\n", a.fit.c_str(), file.parameters.size());
  std::printf("load average at start: %s\n\n", loadAverage().c_str());
  std::printf("| algorithm | evaluations | to %.0e | full solves to %.0e | Newton it. | Newton fact. | deriv. fact. | deriv. solves | per-gradient solves/level | wall s | CPU s | final misfit | max rel. error |\n",
              a.tolerance, a.tolerance);
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  int failures = 0;
  for (const std::string& name : a.algorithms) {
    FitOptions o = file.options;
    o.algorithm = fitAlgorithmFromString(name);
    o.maxEvaluations = a.maxEvaluations;
    o.misfitTolerance = 0.0;  // stop on the parameter step only, the same rule for every algorithm
    FitSetup setup(file);
    const int levels = static_cast<int>(setup.problem().levels().size());
    const double cpu0 = cpuSeconds();
    const FitResult r = runFit(setup.problem(), setup.variables(), o);
    const double cpu = cpuSeconds() - cpu0;
    int reached = -1;
    for (const FitRecord& h : r.history)
      if (h.ok && maxRelativeError(h.q, truth) <= a.tolerance) {
        reached = h.evaluation;
        break;
      }
    const FitCounters& k = r.counters;
    const int derivativeEvaluations = k.gradientEvaluations + k.jacobianEvaluations;
    const double perGradient = derivativeEvaluations > 0
                                   ? static_cast<double>(k.sensitivitySolves) / (derivativeEvaluations * levels)
                                   : 0.0;
    const double error = r.q.size() > 0 ? maxRelativeError(r.q, truth) : std::numeric_limits<double>::infinity();
    if (reached < 0) ++failures;
    std::printf("| %s | %d | %s | %s | %d | %d | %d | %d | %.2g | %.2f | %.2f | %.3e | %.1e |\n", name.c_str(),
                k.evaluations, reached > 0 ? std::to_string(reached).c_str() : "not reached",
                reached > 0 ? std::to_string(reached * levels).c_str() : "-", k.newtonIterations,
                k.newtonFactorizations, k.sensitivityFactorizations, k.sensitivitySolves, perGradient, r.wallSeconds,
                cpu, r.misfit, error);
    rows.push_back({{"algorithm", name},
                    {"termination", r.termination},
                    {"evaluations", k.evaluations},
                    {"evaluations_to_tolerance", reached},
                    {"levels", levels},
                    {"full_solves", k.fullSolves},
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
  std::printf("load average at end: %s\n", loadAverage().c_str());
  if (!a.json.empty()) {
    nlohmann::json j = {{"fit_file", a.fit}, {"tolerance", a.tolerance}, {"runs", rows},
                        {"best_gradient_based", gradientBest}, {"best_derivative_free", freeBest}};
    std::ofstream out(a.json);
    if (!out) throw InputError("--json: cannot write '" + a.json + "'");
    out << j.dump(2) << "\n";
  }
  return failures == 0 ? kOk : kFailed;
}

const RegisterSubcommand reg("bench-fit", [](CLI::App& app, int& exitCode) {
  auto a = std::make_shared<Args>();
  CLI::App* cmd = benchCommand(app)->add_subcommand(
      "fit", "Fitting: derivative-free against gradient-based on a synthetic recovery (solves, time, misfit)");
  cmd->add_option("--fit", a->fit, "Fit file whose scene's material values are the truth");
  cmd->add_option("--algorithms", a->algorithms, "Algorithms to compare")->delimiter(',');
  cmd->add_option("--tolerance", a->tolerance, "Relative parameter error that counts as recovered")->check(CLI::PositiveNumber);
  cmd->add_option("--max-evaluations", a->maxEvaluations, "Evaluation cap per algorithm")->check(CLI::Range(1, 100000));
  cmd->add_option("--json", a->json, "Write the figures as JSON");
  cmd->callback([a, &exitCode] { exitCode = run(*a); });
});

}  // namespace
}  // namespace jetshell::cli
