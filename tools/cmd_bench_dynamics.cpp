// `jetshell bench dynamics`: run time against trajectory error for implicit time stepping, on the hanging cloth
// (tools/bench_cloth.h) falling from rest. Each run (integrator × policy × Δt) is compared with a reference
// trajectory (BDF2, the reference policy, Δt_min / reference-divisor) at every multiple of the largest Δt:
//   RMS error  = sqrt(mean over samples and vertices of |x − x_ref|²)   [m]
//   final error = sqrt(mean over vertices of |x − x_ref|²) at the last sample   [m]
// against the run's wall and process-CPU seconds (the load average is printed next to them). Prints a table
// (markdown), writes --json and a log-log PNG chart of RMS error against wall (or, --chart-time cpu, process CPU)
// time (--png); --replot redraws the chart from an earlier --json without running anything.
// --newton-error also checks every step a jetshell run's iterate test passed: the step is solved again from the
// same state, by a second solver on its own system, on from the passed iterate to η = 1e-6, and the iterate's
// mass-weighted RMS distance from that solution is compared with the threshold the test claimed to meet (wall
// times then include the second solves; the run itself is the plain run's).
#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "solvers/time_step_policy.h"
#include "tools/bench_cloth.h"
#include "tools/bench_newton_error.h"
#include "tools/bench_trajectory.h"
#include "tools/output/atomic_file.h"
#include "tools/render/plot.h"
#include "tools/scene/json_reader.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace jetshell::cli {
namespace {

constexpr int kMaxListEntries = 16;

struct DynamicsBenchOptions {
  int n = 20;
  std::string material = "cloth";  // cloth | steel-foil (tools/bench_cloth.h)
  double waveLimit = DynamicsOptions{}.extrapolationWaveLimit;  // the runs' (not the reference's)
  double youngsModulus = 0.0;  // Pa; > 0: instead of the material's
  double thickness = 0.0;      // m; > 0: instead of the material's
  double duration = 0.5;
  std::string dts = "1/30,1/60,1/120,1/240";
  std::string integrators = "backward_euler,bdf2";
  std::string policies = "page,jetshell";
  std::string etas;  // η values for extra jetshell runs
  int referenceDivisor = 4;
  int threads = 0;
  std::string linearSolver = "auto";  // each policy's choice
  std::string preconditioner = "one_ring_cholesky";
  double cgTolerance = 1e-6;
  std::string ordering = "auto";
  std::string json, png;
  std::string chartTime = "wall";  // wall | cpu
  std::string replot;
  bool newtonError = false;
};

std::vector<std::string> splitList(const std::string& text, const char* field) {
  std::vector<std::string> out;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    if (item.empty()) throw InputError(std::string(field) + ": empty entry in '" + text + "'");
    out.push_back(item);
  }
  if (out.empty()) throw InputError(std::string(field) + ": empty list");
  if (out.size() > static_cast<std::size_t>(kMaxListEntries))
    throw InputError(std::string(field) + ": at most " + std::to_string(kMaxListEntries) + " entries");
  return out;
}

/// "0.01" or "1/60".
double parsePositive(const std::string& text, const char* field) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    const std::size_t slash = text.find('/');
    if (slash == std::string::npos) {
      value = std::stod(text, &used);
      if (used != text.size()) throw std::invalid_argument("trailing characters");
    } else {
      const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
      std::size_t ua = 0, ub = 0;
      const double num = std::stod(a, &ua), den = std::stod(b, &ub);
      if (ua != a.size() || ub != b.size()) throw std::invalid_argument("trailing characters");
      value = num / den;
    }
  } catch (const std::exception&) {
    throw InputError(std::string(field) + ": '" + text + "' is not a number or a fraction");
  }
  if (!(std::isfinite(value) && value > 0.0)) throw InputError(std::string(field) + ": '" + text + "' must be > 0");
  return value;
}

/// Positions sampled every `interval` seconds (the first sample at t = interval).
struct Trajectory {
  std::vector<Eigen::VectorXd> samples;
};


struct RunFigures {
  std::string integrator, policy, label;
  double eta = 0.0;
  double dt = 0.0;
  bool completed = false;
  std::string message;
  int steps = 0, newtonIterations = 0, cuts = 0, movedOn = 0, factorizations = 0;
  double wall = 0.0, cpu = 0.0, loadBefore = 0.0, loadAfter = 0.0;
  double rmsError = 0.0, finalError = 0.0;
  Trajectory trajectory;
  NewtonErrorTally newtonError;  // --newton-error
};

RunFigures runOne(const ShellProblem& problem, const DynamicsBenchOptions& o, TimeIntegrator integrator,
                  TimeStepPolicy policy, double eta, double dt, double sampleInterval, int samples) {
  RunFigures f;
  f.integrator = toString(integrator);
  f.policy = toString(policy);
  f.eta = eta;
  f.dt = dt;
  ShellSystem system(problem, AnalysisKind::Dynamics);
  DynamicsOptions d;
  d.integrator = integrator;
  d.timeStep = dt;
  d.newton.linear.type = linearSolverTypeFromString(o.linearSolver);
  d.newton.linear.preconditioner = preconditionerFromString(o.preconditioner);
  d.newton.linear.cgRelativeTolerance = o.cgTolerance;
  d.newton.linear.ordering = fillOrderingFromString(o.ordering);
  applyTimeStepPolicy(policy, d);
  if (policy == TimeStepPolicy::Jetshell && eta > 0.0) d.updateTolerance = eta;
  if (policy != TimeStepPolicy::Reference) d.extrapolationWaveLimit = o.waveLimit;
  f.eta = d.updateTolerance;
  DynamicsSolver solver(system, d);
  // --newton-error: a second solver on its own system, so the check leaves the run untouched.
  std::unique_ptr<NewtonErrorWatch> watch;
  if (o.newtonError && policy == TimeStepPolicy::Jetshell) {
    auto tightSystem = std::make_unique<ShellSystem>(problem, AnalysisKind::Dynamics);
    watch = std::make_unique<NewtonErrorWatch>(solver, std::move(tightSystem));
  }
  const int stepsPerSample = static_cast<int>(std::lround(sampleInterval / dt));
  f.loadBefore = loadAverage();
  const double w0 = wallSeconds(), c0 = processCpuSeconds();
  const DynamicsResult r = simulate(solver, samples * sampleInterval, [&](const StepReport& rep, DynamicsSolver& s) {
    for (const SolverSummary& sum : rep.solves) f.factorizations += sum.numericFactorizations;
    if (rep.step % stepsPerSample == 0) f.trajectory.samples.push_back(s.positions());
    if (watch) watch->afterStep(rep);
    return true;
  });
  f.wall = wallSeconds() - w0;
  f.cpu = processCpuSeconds() - c0;
  f.loadAfter = loadAverage();
  if (watch) f.newtonError = watch->tally();
  f.completed = r.completed && static_cast<int>(f.trajectory.samples.size()) == samples;
  f.message = r.message;
  f.steps = r.steps;
  f.newtonIterations = r.newtonIterations;
  f.cuts = r.cuts;
  f.movedOn = r.movedOn;
  return f;
}

void measureErrors(RunFigures& f, const Trajectory& reference) {
  const std::size_t k = std::min(f.trajectory.samples.size(), reference.samples.size());
  if (k == 0) return;
  double sum = 0.0;
  double last = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    const double rms = vertexDistance(f.trajectory.samples[i], reference.samples[i]).rms;
    last = rms * rms;
    sum += last;
  }
  f.rmsError = std::sqrt(sum / static_cast<double>(k));
  f.finalError = std::sqrt(last);
}

std::string seriesLabel(const RunFigures& f) {
  std::ostringstream s;
  s << f.integrator << " " << f.policy;
  if (f.policy == "jetshell") s << " eta " << f.eta;
  return s.str();
}

nlohmann::json toJson(const RunFigures& f) {
  nlohmann::json j = {{"integrator", f.integrator}, {"policy", f.policy},     {"eta", f.eta},
          {"dt", f.dt},                 {"completed", f.completed}, {"message", f.message},
          {"steps", f.steps},           {"newton_iterations", f.newtonIterations},
          {"cuts", f.cuts},             {"moved_on", f.movedOn},  {"factorizations", f.factorizations},
          {"wall_seconds", f.wall},     {"process_cpu_seconds", f.cpu},
          {"load_before", f.loadBefore}, {"load_after", f.loadAfter},
          {"rms_error_m", f.rmsError},  {"final_error_m", f.finalError}};
  if (!f.newtonError.empty()) j["newton_error"] = f.newtonError.toJson();
  return j;
}

void plotRuns(const std::vector<RunFigures>& runs, int vertices, const DynamicsBenchOptions& o) {
    PlotSpec spec;
    const bool cpu = o.chartTime == "cpu";
    spec.title = "Hanging cloth, " + std::to_string(vertices) + " vertices: trajectory error against " +
                 (cpu ? "process CPU time" : "wall time");
    spec.xLabel = cpu ? "process CPU time [s]" : "wall time [s]";
    spec.yLabel = "RMS vertex position error over time [m]";
    spec.logX = spec.logY = true;
    std::vector<std::string> labels;
    for (const RunFigures& f : runs)
      if (std::find(labels.begin(), labels.end(), f.label) == labels.end()) labels.push_back(f.label);
    for (const std::string& label : labels) {
      std::vector<double> x, y;
      for (const RunFigures& f : runs)
        if (f.label == label && f.completed && f.rmsError > 0.0) {
          x.push_back(std::max(cpu ? f.cpu : f.wall, 1e-6));
          y.push_back(f.rmsError);
        }
      if (!x.empty()) spec.series.emplace_back(label, x, y, "linespoints", "", label.find("page") != std::string::npos ? 2 : 1);
    }
    plotPng(spec, o.png);
    std::printf("wrote %s\n", o.png.c_str());
  }

/// Redraws the chart from an earlier --json.
int replot(const DynamicsBenchOptions& o) {
  if (o.png.empty()) throw InputError("--replot: needs --png");
  // A regular file of bounded size and nesting, as scenes are (a FIFO given here blocked the read).
  const nlohmann::json j = json::parseFile(o.replot, "bench dynamics JSON file");
  if (!j.contains("runs") || !j["runs"].is_array() || !j.contains("mesh"))
    throw InputError(o.replot + ": /runs or /mesh missing: not a 'bench dynamics' JSON file");
  if (j["runs"].size() > 4096) throw InputError(o.replot + ": /runs: more than 4096 runs");
  std::vector<RunFigures> runs;
  std::size_t i = 0;
  for (const nlohmann::json& r : j["runs"]) {
    RunFigures f;
    try {
      f.integrator = r.at("integrator").get<std::string>();
      f.policy = r.at("policy").get<std::string>();
      f.eta = r.at("eta").get<double>();
      f.completed = r.at("completed").get<bool>();
      f.wall = r.at("wall_seconds").get<double>();
      f.cpu = r.at("process_cpu_seconds").get<double>();
      f.rmsError = r.at("rms_error_m").get<double>();
    } catch (const std::exception& e) {
      throw InputError(o.replot + ": /runs/" + std::to_string(i) + ": " + e.what());
    }
    f.label = seriesLabel(f);
    runs.push_back(std::move(f));
    ++i;
  }
  int vertices = 0;
  try {
    vertices = j.at("mesh").at("vertices").get<int>();
  } catch (const std::exception& e) {
    throw InputError(o.replot + ": /mesh/vertices: " + e.what());
  }
  plotRuns(runs, vertices, o);
  return kOk;
}

int runDynamicsBench(const DynamicsBenchOptions& o) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (!o.replot.empty()) return replot(o);
  if (o.threads > 0) omp_set_num_threads(o.threads);
  // Inputs.
  std::vector<double> dts;
  for (const std::string& t : splitList(o.dts, "--dts")) dts.push_back(parsePositive(t, "--dts"));
  std::vector<TimeIntegrator> integrators;
  for (const std::string& t : splitList(o.integrators, "--integrators")) integrators.push_back(timeIntegratorFromString(t));
  std::vector<TimeStepPolicy> policies;
  for (const std::string& t : splitList(o.policies, "--policies")) policies.push_back(timeStepPolicyFromString(t));
  if (o.newtonError && std::find(policies.begin(), policies.end(), TimeStepPolicy::Jetshell) == policies.end())
    throw InputError("--newton-error: it checks the jetshell policy's runs; add jetshell to --policies");
  std::vector<double> etas{0.0};  // 0: the policy's own η
  if (!o.etas.empty()) {
    etas.clear();
    for (const std::string& t : splitList(o.etas, "--etas")) etas.push_back(parsePositive(t, "--etas"));
  }
  const double sampleInterval = *std::max_element(dts.begin(), dts.end());
  const double minDt = *std::min_element(dts.begin(), dts.end());
  for (double dt : dts) {
    const double ratio = sampleInterval / dt;
    if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio)
      throw InputError("--dts: every time step must divide the largest one (" + std::to_string(dt) + ")");
  }
  const int samples = static_cast<int>(std::lround(o.duration / sampleInterval));
  if (samples < 1) throw InputError("--duration: shorter than the largest time step");
  if (samples * sampleInterval / (minDt / o.referenceDivisor) > 2e6)
    throw InputError("--duration: the reference would need more than 2e6 steps");

  const SheetMaterial material = o.material == "steel-foil" ? SheetMaterial::SteelFoil : SheetMaterial::Cloth;
  const ShellProblem problem = hangingCloth(o.n, 0.0, 0.0, material, o.youngsModulus, o.thickness);
  nlohmann::json out;
  std::printf("jetshell bench dynamics: %d×%d-square hanging %s, %d vertices, %d threads, %.4g s (%d samples "
              "every %.4g s); linear solver %s%s\n",
              o.n, o.n, o.material == "steel-foil" ? "steel foil" : "cloth", problem.mesh.numVertices(),
              omp_get_max_threads(), samples * sampleInterval, samples,
              sampleInterval, o.linearSolver.c_str(),
              o.linearSolver == "pcg" ? (" + " + o.preconditioner).c_str() : "");
  out["mesh"] = {{"squares_per_side", o.n}, {"vertices", problem.mesh.numVertices()}};
  out["material"] = o.material;
  out["youngs_modulus"] = o.youngsModulus > 0.0 ? nlohmann::json(o.youngsModulus) : nlohmann::json("material's");
  out["thickness"] = o.thickness > 0.0 ? nlohmann::json(o.thickness) : nlohmann::json("material's");
  out["extrapolation_wave_limit"] = std::isinf(o.waveLimit) ? nlohmann::json("inf") : nlohmann::json(o.waveLimit);
  {
    const ShellSystem sheet(problem, AnalysisKind::Dynamics);
    std::printf("the runs drop an actor's extrapolated acceleration when its membrane wave crosses more than %g "
                "edges a step and its edges are more than %g thicknesses long; this sheet: %.3g edges at the largest "
                "time step, %.3g thicknesses\n",
                o.waveLimit, DynamicsOptions{}.extrapolationThinLimit,
                sampleInterval * sheet.membraneWaveRate()[0], sheet.edgeOverThickness()[0]);
  }
  out["threads"] = omp_get_max_threads();
  out["duration"] = samples * sampleInterval;
  out["linear_solver"] = o.linearSolver;
  if (o.linearSolver == "pcg") out["preconditioner"] = o.preconditioner;

  // Reference.
  const double refDt = minDt / o.referenceDivisor;
  RunFigures ref = runOne(problem, o, TimeIntegrator::BDF2, TimeStepPolicy::Reference, 0.0, refDt, sampleInterval,
                          samples);
  std::printf("reference: bdf2, dt = %.4g s, %s; %.2f s wall (load %.1f), %.2f s CPU\n", refDt, ref.message.c_str(),
              ref.wall, ref.loadBefore, ref.cpu);
  out["reference"] = toJson(ref);
  if (!ref.completed) {
    std::printf("the reference run failed: no errors can be measured\n");
    if (!o.json.empty()) writeFileAtomically(o.json, out.dump(2) + "\n");
    return kFailed;
  }

  // Runs.
  std::vector<RunFigures> runs;
  std::printf("\n| integrator | policy | eta | dt [s] | steps | Newton it. | factorizations | moved on | cuts | "
              "RMS error [m] | final error [m] | wall [s] | CPU [s] | load |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (TimeIntegrator integrator : integrators)
    for (TimeStepPolicy policy : policies)
      for (double eta : (policy == TimeStepPolicy::Jetshell ? etas : std::vector<double>{0.0}))
        for (double dt : dts) {
          RunFigures f = runOne(problem, o, integrator, policy, eta, dt, sampleInterval, samples);
          measureErrors(f, ref.trajectory);
          f.label = seriesLabel(f);
          std::printf("| %s | %s | %s | %.5g | %d | %d | %d | %d | %d | %s | %s | %.2f | %.2f | %.1f |\n",
                      f.integrator.c_str(), f.policy.c_str(),
                      f.policy == "jetshell" ? std::to_string(f.eta).substr(0, 5).c_str() : "-", f.dt, f.steps,
                      f.newtonIterations, f.factorizations, f.movedOn, f.cuts,
                      f.completed ? std::to_string(f.rmsError).c_str() : "failed",
                      f.completed ? std::to_string(f.finalError).c_str() : "failed", f.wall, f.cpu,
                      0.5 * (f.loadBefore + f.loadAfter));
          if (!f.completed) std::printf("  (%s)\n", f.message.c_str());
          f.newtonError.print("  ");
          runs.push_back(std::move(f));
        }
  nlohmann::json rows = nlohmann::json::array();
  for (const RunFigures& f : runs) rows.push_back(toJson(f));
  out["runs"] = rows;

  if (!o.png.empty()) plotRuns(runs, problem.mesh.numVertices(), o);
  if (!o.json.empty()) {
    writeFileAtomically(o.json, out.dump(2) + "\n");
    std::printf("wrote %s\n", o.json.c_str());
  }
  return kOk;
}

const RegisterSubcommand registerBenchDynamics("bench dynamics", [](CLI::App& app, int& exitCode) {
  CLI::App* bench = benchCommand(app);
  auto opts = std::make_shared<DynamicsBenchOptions>();
  CLI::App* cmd = bench->add_subcommand("dynamics", "Trajectory error against run time for time stepping (hanging cloth)");
  cmd->add_option("--n", opts->n, "Cloth squares per side (vertices = (n+1)^2)")->check(CLI::Range(2, 400));
  cmd->add_option("--material", opts->material,
                  "cloth (the spec's T-shirt material) or steel-foil (E 2e11 Pa, 0.1 mm: a membrane far stiffer "
                  "than a step's inertia)")
      ->check(CLI::IsMember({"cloth", "steel-foil"}));
  cmd->add_option("--youngs-modulus", opts->youngsModulus, "Young's modulus [Pa] instead of the material's")
      ->check(finiteRange(1.0, 1e13));
  cmd->add_option("--thickness", opts->thickness, "Thickness [m] instead of the material's")
      ->check(finiteRange(1e-6, 0.1));
  cmd->add_option("--extrapolation-wave-limit", opts->waveLimit,
                  "The runs drop the extrapolated acceleration of a thin sheet whose membrane wave crosses more "
                  "than this many edges a step (inf: never; the solver's default otherwise)")
      ->check(CLI::Range(0.0, std::numeric_limits<double>::infinity()));
  cmd->add_option("--duration", opts->duration, "Simulated time [s]")->check(finiteRange(1e-3, 60.0));
  cmd->add_option("--dts", opts->dts, "Time steps, comma-separated (e.g. 1/30,1/60); each divides the largest");
  cmd->add_option("--integrators", opts->integrators, "Comma-separated: backward_euler, bdf2");
  cmd->add_option("--policies", opts->policies, "Comma-separated: page, jetshell, reference");
  cmd->add_option("--etas", opts->etas, "jetshell policy: update tolerances eta to compare, comma-separated");
  cmd->add_option("--reference-divisor", opts->referenceDivisor, "Reference dt = smallest dt / this")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--threads", opts->threads, "OpenMP threads (default: OpenMP's)")->check(CLI::Range(1, 256));
  cmd->add_option("--linear-solver", opts->linearSolver, "auto | cholmod | ldlt | pcg")
      ->check(CLI::IsMember({"auto", "cholmod", "ldlt", "pcg"}));
  cmd->add_option("--preconditioner", opts->preconditioner,
                  "PCG preconditioner: jacobi | block_jacobi | ic | lagged_cholesky | one_ring_cholesky")
      ->check(CLI::IsMember({"jacobi", "block_jacobi", "ic", "lagged_cholesky", "one_ring_cholesky"}));
  cmd->add_option("--cg-tolerance", opts->cgTolerance, "PCG relative residual tolerance")
      ->check(finiteRange(1e-14, 0.5));
  cmd->add_option("--ordering", opts->ordering, "CHOLMOD fill-reducing ordering: auto | amd | metis | nesdis")
      ->check(CLI::IsMember({"auto", "amd", "metis", "nesdis"}));
  cmd->add_option("--json", opts->json, "Write the figures as JSON")->check(outputFile());
  cmd->add_option("--png", opts->png, "Write the error-against-time chart (PNG)")->check(outputFile());
  cmd->add_flag("--newton-error", opts->newtonError,
               "Solve every step (or part of a cut step) a jetshell run's iterate test passed again to eta 1e-6 "
               "and report the error left against the threshold claimed");
  cmd->add_option("--replot", opts->replot, "Only redraw --png from the JSON of an earlier run");
  cmd->add_option("--chart-time", opts->chartTime, "Time axis of the chart: wall | cpu (process CPU, steadier on a busy machine)")
      ->check(CLI::IsMember({"wall", "cpu"}));
  cmd->callback([opts, &exitCode]() { exitCode = runDynamicsBench(*opts); });
});

}  // namespace
}  // namespace jetshell::cli
