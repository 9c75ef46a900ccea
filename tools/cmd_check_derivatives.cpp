// `jetshell check-derivatives`: every registered energy term (energies/registry.h), or those named with --term,
// checked on random and adversarial configurations (tools/checks/check_configurations.h) of two small meshes: AD vs
// analytic, each path vs Richardson-extrapolated central differences, symmetry of the gradient's Jacobian, and
// PSD-ness of model (Gauss–Newton) Hessians (tools/checks/derivative_check.h). Prints a table of the largest errors per
// term; exits 1 when a tolerance is exceeded.
#include "core/format.h"
#include "core/math_constants.h"
#include "tools/output/atomic_file.h"
#include "tools/checks/check_configurations.h"
#include "tools/checks/derivative_check.h"
#include "energies/registry.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

namespace jetshell::cli {
namespace {

struct CheckOptions {
  std::vector<std::string> terms;
  std::vector<std::string> kinds;
  int configs = 5;
  int threads = 1;
  std::uint64_t seed = 1;
  std::string json;
  bool list = false;
  bool byKind = false;
  bool verbose = false;
  bool parameters = false;
  DerivativeTolerances tolerances;
  ConfigurationOptions configuration;
  DerivativeCheckOptions check;
};

/// Largest errors over a set of checks (one term, or one term and kind).
struct Summary {
  int checked = 0;
  int failed = 0;
  bool hasAnalytic = false;
  bool hessianIsExact = true;
  double adVsAnalytic = 0.0;
  double gradientVsFd = 0.0;
  double hessianVsFd = 0.0;
  double asymmetry = 0.0;
  double fdUncertainty = 0.0;
  double minEigenvalue = std::numeric_limits<double>::infinity();
  double worstVsFd = -1.0;
  std::string worstConfiguration;
  std::vector<std::string> failures;

  void add(const DerivativeCheckResult& r, const std::string& description, const DerivativeTolerances& tol) {
    ++checked;
    hessianIsExact = r.hessianIsExact;
    if (const auto ad = r.maxAdVsAnalytic()) {
      hasAnalytic = true;
      adVsAnalytic = std::max(adVsAnalytic, *ad);
    }
    for (const PathCheck& p : r.paths) {
      gradientVsFd = std::max(gradientVsFd, p.gradientVsFd);
      hessianVsFd = std::max(hessianVsFd, p.hessianVsFd);
    }
    asymmetry = std::max(asymmetry, r.maxHessianAsymmetry());
    fdUncertainty = std::max(fdUncertainty, r.maxFdUncertainty());
    minEigenvalue = std::min(minEigenvalue, r.minHessianEigenvalue());
    if (r.maxVsFd() > worstVsFd) {
      worstVsFd = r.maxVsFd();
      worstConfiguration = description;
    }
    const std::vector<std::string> f = checkFailures(r, tol);
    if (!f.empty()) {
      ++failed;
      for (const std::string& line : f) failures.push_back(description + ": " + line);
    }
  }
  double judgedVsFd() const { return hessianIsExact ? std::max(gradientVsFd, hessianVsFd) : gradientVsFd; }
};

/// Geometry of the configurations of one kind (the same for every term).
struct KindGeometry {
  int count = 0;
  double minAspect = std::numeric_limits<double>::infinity();
  double maxFoldDeg = 0.0;
  double maxStretch = 0.0;
};

std::string sci(double v) { return formatNumber("%.1e", v); }

nlohmann::json nullable(bool present, double v) { return present ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json toJson(const Summary& s) {
  nlohmann::json j;
  j["checked"] = s.checked;
  j["failed"] = s.failed;
  j["max_rel_err_ad_vs_analytic"] = nullable(s.hasAnalytic, s.adVsAnalytic);
  j["max_rel_err_vs_fd"] = s.judgedVsFd();
  j["max_rel_err_gradient_vs_fd"] = s.gradientVsFd;
  j["max_rel_err_hessian_vs_fd"] = s.hessianVsFd;
  j["hessian"] = s.hessianIsExact ? "exact" : "gauss_newton";
  j["max_jacobian_asymmetry"] = s.asymmetry;
  j["max_fd_uncertainty"] = s.fdUncertainty;
  if (!s.hessianIsExact) j["min_rel_eigenvalue"] = s.minEigenvalue;
  j["worst_configuration"] = s.worstConfiguration;
  j["pass"] = s.failed == 0;
  return j;
}

void printRow(const std::string& name, const Summary& s) {
  const std::string hess = s.hessianIsExact ? sci(s.hessianVsFd) : "(" + sci(s.hessianVsFd) + ")";
  const std::string eig = s.hessianIsExact ? "-" : sci(s.minEigenvalue);
  std::printf("%-24s %7d  %9s  %9s  %11s  %9s  %9s  %9s  %s\n", name.c_str(), s.checked,
              s.hasAnalytic ? sci(s.adVsAnalytic).c_str() : "-", sci(s.gradientVsFd).c_str(), hess.c_str(),
              sci(s.asymmetry).c_str(), sci(s.fdUncertainty).c_str(), eig.c_str(),
              s.failed == 0 ? "pass" : ("FAIL " + std::to_string(s.failed)).c_str());
}

std::uint64_t configurationSeed(std::uint64_t base, std::size_t mesh, ConfigurationKind kind, int index) {
  // splitmix64 of the coordinates: independent streams, the same for every term.
  std::uint64_t z = base * 0x9E3779B97F4A7C15ull + mesh * 1000003ull + static_cast<std::uint64_t>(kind) * 7919ull +
                    static_cast<std::uint64_t>(index);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// `--parameters`: ∂E/∂p and ∂²E/∂x∂p of every term with parameters against finite differences in p.
bool runParameterChecks(const CheckOptions& o, const std::vector<const RegisteredTerm*>& terms,
                        const std::vector<CheckMesh>& meshes,
                        const std::vector<std::vector<CheckConfiguration>>& configurations, nlohmann::json& out) {
  const ShellMaterialParams material;
  std::printf("\nparameter derivatives (dual numbers seeded on the parameters) vs central differences in p\n");
  std::printf("%-28s %-22s %7s  %9s  %9s  %9s  %s\n", "term", "parameters", "checked", "dE/dp", "d2E/dxdp",
              "FD-noise", "result");
  bool allPass = true;
  for (const RegisteredTerm* entry : terms) {
    DerivativeCheckOptions options = o.check;
    options.evalOptions = entry->options;
    int checked = 0, failed = 0;
    double maxEnergy = 0.0, maxMixed = 0.0, maxNoise = 0.0;
    std::string names;
    std::vector<std::string> failures;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const CheckMesh& cm = meshes[m];
      const EnergyTermPtr term = entry->make(TermSetup{cm.mesh, cm.topology, cm.reference, material});
      names.clear();
      for (const std::string& n : term->parameterNames()) names += (names.empty() ? "" : ",") + n;
      if (names.empty()) break;
      for (const CheckConfiguration& c : configurations[m]) {
        const ParameterCheckResult r = checkParameterDerivatives(*term, c.x, options);
        ++checked;
        for (const ParameterCheck& pc : r.parameters) {
          maxEnergy = std::max(maxEnergy, pc.energyVsFd);
          maxMixed = std::max(maxMixed, pc.mixedVsFd);
        }
        maxNoise = std::max(maxNoise, r.maxFdUncertainty());
        const std::vector<std::string> f = checkFailures(r, o.tolerances);
        if (!f.empty()) ++failed;
        for (const std::string& line : f) failures.push_back(c.description + ": " + line);
      }
    }
    if (names.empty()) {
      std::printf("%-28s %-22s %7s\n", entry->name.c_str(), "(none)", "-");
      continue;
    }
    std::printf("%-28s %-22s %7d  %9s  %9s  %9s  %s\n", entry->name.c_str(), names.c_str(), checked,
                sci(maxEnergy).c_str(), sci(maxMixed).c_str(), sci(maxNoise).c_str(),
                failed == 0 ? "pass" : ("FAIL " + std::to_string(failed)).c_str());
    for (std::size_t i = 0; i < failures.size() && i < 5; ++i) std::printf("    failed: %s\n", failures[i].c_str());
    allPass = allPass && failed == 0;
    nlohmann::json j;
    j["term"] = entry->name;
    j["parameters"] = names;
    j["checked"] = checked;
    j["failed"] = failed;
    j["max_rel_err_energy_vs_fd"] = maxEnergy;
    j["max_rel_err_mixed_vs_fd"] = maxMixed;
    j["max_fd_uncertainty"] = maxNoise;
    j["pass"] = failed == 0;
    out.push_back(j);
  }
  std::printf("\ntolerance: vs FD %.0e\n%s\n", o.tolerances.vsFd,
              allPass ? "all parameter checks passed" : "SOME PARAMETER CHECKS FAILED");
  return allPass;
}

int run(const CheckOptions& o) {
  if (o.list) {
    for (const RegisteredTerm& t : termRegistry()) std::printf("%-24s %s\n", t.name.c_str(), t.summary.c_str());
    return kOk;
  }
  std::vector<const RegisteredTerm*> terms;
  if (o.terms.empty()) {
    for (const RegisteredTerm& t : termRegistry()) terms.push_back(&t);
  } else {
    for (const std::string& name : o.terms) terms.push_back(findRegisteredTerm(name));  // validated by CLI11
  }
  std::vector<ConfigurationKind> kinds;
  if (o.kinds.empty()) {
    kinds.assign(std::begin(kConfigurationKinds), std::end(kConfigurationKinds));
  } else {
    for (const std::string& k : o.kinds) kinds.push_back(configurationKindFromString(k));
  }

  // The check meshes have a dozen faces: parallel loops would only add their overhead (20x on a loaded
  // 2-core machine, measured). Thread-count determinism is tested separately (tests/core/assembly_test.cpp).
  omp_set_num_threads(o.threads);
  const std::vector<CheckMesh> meshes = makeCheckMeshes();
  const ShellMaterialParams material;
  // Configurations are generated once and shared by every term.
  std::vector<std::vector<CheckConfiguration>> configurations(meshes.size());
  std::map<ConfigurationKind, KindGeometry> geometry;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    for (ConfigurationKind kind : kinds) {
      for (int i = 0; i < o.configs; ++i) {
        configurations[m].push_back(
            makeCheckConfiguration(meshes[m], kind, configurationSeed(o.seed, m, kind, i), o.configuration));
        const ConfigurationGeometry& g = configurations[m].back().geometry;
        KindGeometry& k = geometry[kind];
        ++k.count;
        k.minAspect = std::min(k.minAspect, g.minAspectRatio);
        k.maxFoldDeg = std::max(k.maxFoldDeg, g.maxFoldAngle * 180.0 / 3.14159265358979323846);
        k.maxStretch = std::max(k.maxStretch, g.maxStretch);
      }
    }
  }

  std::printf("jetshell check-derivatives: %zu term(s), %d configuration(s) per kind and mesh on %zu meshes\n",
              terms.size(), o.configs, meshes.size());
  std::printf("configurations (geometry over both meshes):\n");
  for (ConfigurationKind kind : kinds) {
    const KindGeometry& k = geometry[kind];
    std::printf("  %-10s  %3d  min aspect %.1e  max fold angle %8.3f deg  max stretch %.2f\n", toString(kind),
                k.count, k.minAspect, k.maxFoldDeg, k.maxStretch);
  }
  if (o.parameters) {
    nlohmann::json out = nlohmann::json::array();
    const bool pass = runParameterChecks(o, terms, meshes, configurations, out);
    if (!o.json.empty()) {
      writeFileAtomically(o.json, out.dump(2) + "\n");
    }
    return pass ? kOk : kFailed;
  }
  std::printf("\nrelative errors (max over configurations; see tools/checks/derivative_check.h for the definition)\n");
  std::printf("%-24s %7s  %9s  %9s  %11s  %9s  %9s  %9s  %s\n", "term", "checked", "AD-vs-an", "grad-FD",
              "Hess-FD", "asym(J)", "FD-noise", "min-eig", "result");

  nlohmann::json out = nlohmann::json::array();
  bool allPass = true;
  for (const RegisteredTerm* entry : terms) {
    Summary total;
    std::map<ConfigurationKind, Summary> perKind;
    DerivativeCheckOptions options = o.check;
    options.evalOptions = entry->options;
    options.hessianIsExact = entry->hessianIsExact;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const CheckMesh& cm = meshes[m];
      const EnergyTermPtr term = entry->make(TermSetup{cm.mesh, cm.topology, cm.reference, material});
      for (const CheckConfiguration& c : configurations[m]) {
        if (entry->singularAtFold && c.kind == ConfigurationKind::Fold) continue;  // infinite there by design
        const DerivativeCheckResult r = checkDerivatives(*term, c.x, options);
        total.add(r, c.description, o.tolerances);
        perKind[c.kind].add(r, c.description, o.tolerances);
        if (o.verbose) {
          std::printf("  %-22s %-60s AD-an %s  vs-FD %s  asym %s  noise %s\n", entry->name.c_str(),
                      c.description.c_str(), r.maxAdVsAnalytic() ? sci(*r.maxAdVsAnalytic()).c_str() : "-",
                      sci(r.maxVsFd()).c_str(), sci(r.maxHessianAsymmetry()).c_str(),
                      sci(r.maxFdUncertainty()).c_str());
        }
      }
    }
    printRow(entry->name, total);
    if (o.byKind) {
      for (ConfigurationKind kind : kinds) printRow("  " + std::string(toString(kind)), perKind[kind]);
    }
    for (std::size_t i = 0; i < total.failures.size() && i < 5; ++i)
      std::printf("    failed: %s\n", total.failures[i].c_str());
    if (total.failures.size() > 5) std::printf("    ... %zu more\n", total.failures.size() - 5);
    allPass = allPass && total.failed == 0;

    nlohmann::json j = toJson(total);
    j["term"] = entry->name;
    nlohmann::json kindsJson = nlohmann::json::object();
    for (ConfigurationKind kind : kinds) kindsJson[toString(kind)] = toJson(perKind[kind]);
    j["per_kind"] = kindsJson;
    out.push_back(j);
  }
  std::printf("\ntolerances: AD vs analytic %.0e, vs FD %.0e, asymmetry %.0e, model Hessian eigenvalue >= -%.0e|H|\n",
              o.tolerances.adVsAnalytic, o.tolerances.vsFd, o.tolerances.asymmetry, o.tolerances.psd);
  std::printf("%s\n", allPass ? "all checks passed" : "SOME CHECKS FAILED");

  if (!o.json.empty()) {
    writeFileAtomically(o.json, out.dump(2) + "\n");
  }
  return allPass ? kOk : kFailed;
}

const RegisterSubcommand registerCheckDerivatives("check-derivatives", [](CLI::App& app, int& exitCode) {
  auto o = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand(
      "check-derivatives",
      "Check every registered energy term's gradient and Hessian (AD, analytic) against each other and against\n"
      "Richardson-extrapolated central finite differences, on random and adversarial configurations (large\n"
      "rotations, x3 stretch, folds near 180 deg, near-degenerate triangles) of a 4-face bending-stencil patch\n"
      "and a 12-face grid. Prints the largest relative errors per term; exit 1 when a tolerance is exceeded.\n"
      "Relative error = |A - B| / max(|B|, floor), B the reference (analytic, or finite differences), the floor\n"
      "1e-3 of the term's scale (see tools/checks/derivative_check.h).");
  const std::vector<std::string> names = registeredTermNames();
  std::string allNames;
  for (const std::string& n : names) allNames += (allNames.empty() ? "" : ", ") + n;
  cmd->add_option("--term", o->terms, "Check only these terms (repeatable): " + allNames)
      ->check(CLI::IsMember(names));
  cmd->add_option("--configs", o->configs, "Configurations per kind and mesh (2 meshes)")
      ->default_val(o->configs)
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--kind", o->kinds, "Only these configuration kinds (repeatable)")
      ->check(CLI::IsMember({"random", "rotation", "stretch", "fold", "degenerate"}));
  cmd->add_option("--seed", o->seed, "Seed of the configuration generator")->default_val(o->seed);
  cmd->add_option("--json", o->json, "Write one object per term to FILE (term, checked, max_rel_err_ad_vs_analytic, "
                                     "max_rel_err_vs_fd, pass, per_kind, ...)")->check(outputFile());
  cmd->add_option("--threads", o->threads, "OpenMP threads for the evaluations")
      ->default_val(o->threads)
      ->check(CLI::Range(1, 256));
  cmd->add_flag("--list", o->list, "List the registered terms and exit");
  cmd->add_flag("--parameters", o->parameters,
                "Check the parameter derivatives instead (dE/dp and d2E/dxdp from duals vs central differences in p)");
  cmd->add_flag("--by-kind", o->byKind, "Also print one row per configuration kind under each term");
  cmd->add_flag("-v,--verbose", o->verbose, "Print every configuration's errors");
  cmd->add_option("--tol-ad", o->tolerances.adVsAnalytic, "Tolerance, AD vs analytic")
      ->default_val(o->tolerances.adVsAnalytic)
      ->check(finiteNumber());
  cmd->add_option("--tol-fd", o->tolerances.vsFd, "Tolerance, each path vs finite differences")
      ->default_val(o->tolerances.vsFd)
      ->check(finiteNumber());
  cmd->add_option("--tol-asym", o->tolerances.asymmetry, "Tolerance, asymmetry of the FD Jacobian of the gradient")
      ->default_val(o->tolerances.asymmetry)
      ->check(finiteNumber());
  cmd->add_option("--fd-initial-step", o->check.initialStep, "First finite-difference step / length scale")
      ->default_val(o->check.initialStep)
      ->check(finiteNumber(1.0));
  cmd->add_option("--fd-steps", o->check.extrapolationSteps,
                  "Finite-difference steps (each half the previous) in the Richardson tableau")
      ->default_val(o->check.extrapolationSteps)
      ->check(CLI::Range(2, 60));
  cmd->add_option("--fold-min-delta", o->configuration.foldMinDelta,
                  "Folds: smallest 180 deg - (angle between normals), rad (> 0: the Kelvin inversion diverges at 0)")
      ->default_val(o->configuration.foldMinDelta)
      ->check(finiteNumber(kPi));
  cmd->add_option("--degenerate-aspect", o->configuration.degenerateAspect,
                  "Near-degenerate triangles: altitude / longest edge of the squashed face")
      ->default_val(o->configuration.degenerateAspect)
      ->check(finiteNumber(1.0));
  cmd->add_option("--fold-max-delta", o->configuration.foldMaxDelta, "Folds: largest 180 deg - angle, rad")
      ->default_val(o->configuration.foldMaxDelta)
      ->check(finiteNumber(kPi));
  cmd->callback([o, &exitCode] {
    if (!(o->configuration.foldMinDelta <= o->configuration.foldMaxDelta))
      throw CLI::ValidationError("--fold-min-delta", "must not exceed --fold-max-delta (" +
                                                         std::to_string(o->configuration.foldMinDelta) + " > " +
                                                         std::to_string(o->configuration.foldMaxDelta) + ")");
    exitCode = run(*o);
  });
});

}  // namespace
}  // namespace jetshell::cli
