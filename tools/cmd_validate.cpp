// `jetshell validate NAME | --all`: runs the validation benchmarks (validation/benchmarks.cpp) and compares
// every tabulated load level with its reference; prints the table, writes a PNG of the load paths and, with
// --json, one object per benchmark. VALIDATION.md explains the benchmarks, the options and the figures.
#include "core/input_limits.h"
#include "tools/output/atomic_file.h"
#include "tools/output/directories.h"
#include "core/mesh.h"
#include "tools/subcommand.h"
#include "solvers/linear_solver.h"
#include "solvers/newton.h"
#include "tools/validation/validation_plots.h"
#include "validation/benchmark.h"
#include "validation/report.h"
#include "validation/snap_through.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace jetshell::cli {
namespace {

using namespace jetshell::validation;

struct ValidateArgs {
  std::vector<std::string> names;
  bool all = false;
  bool list = false;
  std::string json;
  std::string plots = "validation-output";
  bool noPlot = false;
  std::string mesh;
  std::string clamp = "mirrored";
  std::string diagonals = "uniform";
  std::string grading;
  std::string freeEdge = "second_order_free";
  std::string solver;
  std::string projection = "none";
  std::string linearSolver = "auto";
  double maxIncrement = 1.0;
  double initialIncrement = 0.005;
  int predictor = BenchmarkRunOptions{}.predictorOrder;
  double residualTolerance = NewtonOptions{}.residualTolerance;
  double maxError = 0.0;
  bool log = false;
  bool relaxationFreshFactors = false;
  bool relaxationEvaluateResidual = false;
  // The snap-through benchmark (validation/snap_through.h).
  double thickness = RoofOptions{}.thickness;
  double load = RoofOptions{}.load;
  double maxDeflection = RoofOptions{}.maxDeflection;
  double pathIncrement = RoofOptions{}.increment;
  double pathMaxIncrement = RoofOptions{}.maxIncrement;
  double loadScaling = RoofOptions{}.loadScaling;
};

constexpr const char* kRoof = "hinged-cylindrical-roof";

Resolution parseMesh(const std::string& s);

/// The snap-through benchmark: arc length against displacement control on one mesh. Fails (exit 1) when arc
/// length does not pass both limit points, or with --max-error when the two controls' limit loads differ by more.
bool runRoof(const ValidateArgs& a, nlohmann::json& out) {
  RoofOptions o;
  if (!a.mesh.empty()) o.resolution = parseMesh(a.mesh);
  o.thickness = a.thickness;
  o.load = a.load;
  o.maxDeflection = a.maxDeflection;
  o.increment = a.pathIncrement;
  o.maxIncrement = std::max(a.pathIncrement, a.pathMaxIncrement);
  o.loadScaling = a.loadScaling;
  o.residualTolerance = a.residualTolerance;
  if (a.log) o.log = &std::cerr;
  const RoofResult r = runHingedRoof(o);
  std::cout << kRoof << ": " << formatRoof(r) << "\n";
  out.push_back(toJson(r));
  bool ok = r.bothLimitsPassed && r.displacement.completed;
  if (a.maxError > 0.0 && !(r.limitLoadDifference <= a.maxError)) {
    std::cout << kRoof << ": FAILED: limit loads differ by " << 100.0 * r.limitLoadDifference << "% > --max-error "
              << 100.0 * a.maxError << "%\n\n";
    ok = false;
  }
  return ok;
}

/// "N1xN2": two counts from 1 to 100000 whose grid stays within the vertex limit (no silent wrap-around).
Resolution parseMesh(const std::string& s) {
  const std::string usage = "--mesh: '" + s + "' is not N1xN2 with counts from 1 to 100000 (e.g. 8x64)";
  const std::size_t x = s.find_first_of("xX");
  if (x == std::string::npos) throw InputError(usage);
  auto count = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos)
      throw InputError(usage);
    const long value = std::stol(digits);
    if (value < 1 || value > 100000) throw InputError(usage);
    return static_cast<int>(value);
  };
  Resolution r;
  r.n1 = count(s.substr(0, x));
  r.n2 = count(s.substr(x + 1));
  const std::int64_t vertices = (std::int64_t{r.n1} + 1) * (std::int64_t{r.n2} + 1);
  if (vertices > inputLimits().maxVertices)
    throw InputError("--mesh: " + s + " gives " + std::to_string(vertices) + " vertices, too many (at most " +
                     std::to_string(inputLimits().maxVertices) + ")");
  return r;
}

BenchmarkRunOptions runOptions(const ValidateArgs& a) {
  BenchmarkRunOptions o;
  if (!a.mesh.empty()) o.resolution = parseMesh(a.mesh);
  o.clamp = parseClampKind(a.clamp);
  o.diagonals = quadDiagonalsFromString(a.diagonals);
  if (!a.grading.empty()) {
    o.defaultGrading = false;
    o.resolution.grading = parseMeshGrading(a.grading);
  }
  if (a.freeEdge != "page_free" && a.freeEdge != "second_order_free")
    throw InputError("--free-edge: '" + a.freeEdge + "' is not one of: page_free, second_order_free");
  o.freeRule = edgeRuleFromString(a.freeEdge);
  if (!a.solver.empty()) {
    o.useDefaultSolver = false;
    if (a.solver == "load-stepping")
      o.solver = SolverKind::LoadStepping;
    else if (a.solver == "dynamic-relaxation")
      o.solver = SolverKind::DynamicRelaxation;
    else
      throw InputError("--solver: '" + a.solver + "' is not one of: load-stepping, dynamic-relaxation");
  }
  if (a.projection == "none")
    o.newton.projection = PsdProjection::None;
  else if (a.projection == "clamp")
    o.newton.projection = PsdProjection::Clamp;
  else
    throw InputError("--projection: '" + a.projection + "' is not one of: none, clamp");
  try {
    o.newton.linear.type = linearSolverTypeFromString(a.linearSolver);
  } catch (const InputError& e) {
    throw InputError(std::string("--linear-solver: ") + e.what());
  }
  o.maxIncrement = a.maxIncrement;
  o.initialIncrement = std::min(a.initialIncrement, a.maxIncrement);
  o.predictorOrder = a.predictor;
  o.newton.residualTolerance = a.residualTolerance;
  if (a.log) o.log = &std::cerr;
  o.relaxationReuseFactor = !a.relaxationFreshFactors;
  o.relaxationReuseStepGradient = !a.relaxationEvaluateResidual;
  return o;
}

int runValidate(const ValidateArgs& a) {
  if (a.list) {
    for (const Benchmark& b : allBenchmarks())
      std::cout << b.name << ": " << b.title << " (default mesh " << b.defaultResolution.n1 << "x"
                << b.defaultResolution.n2 << " " << toString(b.defaultResolution.grading) << ", " << b.resolutionMeaning << ")\n";
    std::cout << kRoof << ": Hinged cylindrical roof snap-through (Sze et al. 2004), arc length against displacement "
              << "control (default mesh " << RoofOptions{}.resolution.n1 << "x" << RoofOptions{}.resolution.n2
              << ", quads across the arc x along the axis, both even)\n";
    return kOk;
  }
  std::vector<const Benchmark*> selected;
  if (a.all)
    for (const Benchmark& b : allBenchmarks()) selected.push_back(&b);
  bool roof = a.all;
  for (const std::string& n : a.names) {
    if (n == kRoof)
      roof = true;
    else
      selected.push_back(&findBenchmark(n, {kRoof}));
  }
  if (selected.empty() && !roof) throw InputError("validate: name a benchmark, or --all, or --list");
  const BenchmarkRunOptions options = runOptions(a);
  for (const Benchmark* b : selected) {
    const Resolution& least = b->minimumResolution;
    if (!a.mesh.empty() && (options.resolution.n1 < least.n1 || options.resolution.n2 < least.n2))
      throw InputError("--mesh: " + a.mesh + " is too coarse for " + b->name + " (at least " +
                       std::to_string(least.n1) + "x" + std::to_string(least.n2) + ")");
  }
  if (!a.noPlot) createOutputDirectory(a.plots, "--plots");
  checkOutputOption(a.json, "--json");  // here, not on the command line: it may go in the --plots directory

  nlohmann::json out = nlohmann::json::array();
  bool ok = true;
  for (const Benchmark* b : selected) {
    const BenchmarkResult r = runBenchmark(*b, options);
    std::cout << b->name << ": " << formatSummary(*b, r) << formatTable(r) << "\n";
    if (!r.completed) ok = false;
    if (a.maxError > 0.0 && !(r.maxRelError <= a.maxError)) {
      std::cout << b->name << ": FAILED: max relative error " << 100.0 * r.maxRelError << "% > --max-error "
                << 100.0 * a.maxError << "%\n\n";
      ok = false;
    }
    nlohmann::json j = toJson(*b, r);
    if (!a.noPlot && !r.rows.empty()) {
      const std::string png = (std::filesystem::path(a.plots) / (b->name + ".png")).string();
      try {
        plotLoadPath(*b, r, png);
        j["plot"] = png;
        std::cout << "plot: " << png << "\n\n";
      } catch (const InputError& e) {
        std::cout << "note: no plot (" << e.what() << ")\n\n";
      }
    }
    out.push_back(std::move(j));
  }
  if (roof && !runRoof(a, out)) ok = false;
  if (!a.json.empty()) {
    writeFileAtomically(a.json, out.dump(2) + "\n");
  }
  return ok ? kOk : kFailed;
}

const RegisterSubcommand registerValidate("validate", [](CLI::App& app, int& exitCode) {
  auto a = std::make_shared<ValidateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "validate", "Run the nonlinear shell benchmarks (Sze et al. 2004, the page's slit ring) against their references");
  cmd->add_option("names", a->names, "Benchmarks to run (see --list)");
  cmd->add_flag("--all", a->all, "Run every benchmark");
  cmd->add_flag("--list", a->list, "List the benchmarks and their default meshes");
  cmd->add_option("--json", a->json, "Write the results (one object per benchmark) to this JSON file");
  cmd->add_option("--plots", a->plots, "Directory for the load-path PNGs (default validation-output)");
  cmd->add_flag("--no-plot", a->noPlot, "Skip the PNGs");
  cmd->add_option("--mesh", a->mesh, "Resolution N1xN2 instead of the benchmark's default (see --list)");
  cmd->add_option("--clamp", a->clamp, "Clamped edges: mirrored (default), normal, two-row");
  cmd->add_option("--diagonals", a->diagonals, "Quad split: uniform (default) or alternating");
  cmd->add_option("--grading", a->grading,
                  "Spacing of the rings between free edges: uniform or cosine (default: the benchmark's, see --list)");
  cmd->add_option("--free-edge", a->freeEdge, "Free edges' rule: second_order_free (default: no moment across the edge) or page_free");
  cmd->add_option("--solver", a->solver, "load-stepping or dynamic-relaxation (default: the benchmark's)");
  cmd->add_option("--projection", a->projection, "Newton's per-element PSD projection: none (default) or clamp");
  cmd->add_option("--linear-solver", a->linearSolver,
                  "Newton's linear solver: auto (default: CHOLMOD up to 300,000 unknowns, PCG above), cholmod, ldlt, pcg");
  cmd->add_option("--max-increment", a->maxIncrement, "Largest load-factor increment of one Newton solve")
      ->check(finiteNumber());
  cmd->add_option("--initial-increment", a->initialIncrement, "The first load-factor increment")
      ->check(finiteNumber());
  cmd->add_option("--predictor", a->predictor, "Order of the extrapolated start of each solve (0: last equilibrium)")
      ->check(CLI::Range(0, 5));
  cmd->add_option("--residual-tolerance", a->residualTolerance,
                  "Newton's residual tolerance (x the largest applied nodal force)")
      ->check(finiteNumber(kMaxRelativeTolerance));
  cmd->add_option("--max-error", a->maxError, "Fail (exit 1) when a benchmark's max relative error exceeds this")
      ->check(finiteNumber());
  cmd->add_flag("--log", a->log, "One line per Newton solve on stderr");
  cmd->add_flag("--relaxation-fresh-factors", a->relaxationFreshFactors,
                "Dynamic relaxation: assemble and factor the Hessian at every Newton iteration instead of reusing "
                "an earlier step's factor while it contracts");
  cmd->add_flag("--relaxation-evaluate-residual", a->relaxationEvaluateResidual,
                "Dynamic relaxation: evaluate each step's static residual instead of reading it from the step's "
                "last gradient");
  cmd->add_option("--thickness", a->thickness, "hinged-cylindrical-roof: shell thickness (12.7 or 6.35 in Sze et al.)")
      ->check(finiteNumber(1000.0));  // mm; the roof's radius is 2540
  cmd->add_option("--load", a->load, "hinged-cylindrical-roof: the point load P at lambda = 1 [N]")
      ->check(finiteNumber(1e9));
  cmd->add_option("--max-deflection", a->maxDeflection,
                  "hinged-cylindrical-roof: the load point's deflection that ends displacement control [mm]")
      ->check(finiteNumber(1e4));
  cmd->add_option("--path-increment", a->pathIncrement,
                  "hinged-cylindrical-roof: first and largest increment (lambda for arc length, a fraction of "
                  "--max-deflection for displacement control)")
      ->check(finiteRange(1e-4, 1.0));
  cmd->add_option("--path-max-increment", a->pathMaxIncrement,
                  "hinged-cylindrical-roof: largest increment, in the units of --path-increment")
      ->check(finiteRange(1e-4, 1.0));
  cmd->add_option("--load-scaling", a->loadScaling, "hinged-cylindrical-roof: arc length's psi (0 cylindrical, 1 spherical)")
      ->check(finiteRange(0.0, 1e6));
  cmd->callback([a, &exitCode] { exitCode = runValidate(*a); });
});

}  // namespace
}  // namespace jetshell::cli
