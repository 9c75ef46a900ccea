// `jetshell bench solver`: the solver on a hanging cloth. An n×n-square, 1 m cloth (the spec's T-shirt
// material: E 1e5 Pa, ν 0.25, ρ0 1000 kg/m³, h 2 mm) lies flat in the z = 0 plane, pinned at the two corners
// of its y = 1 edge, and falls under gravity −z: `steps` backward-Euler steps of Δt, then one static solve from
// the last dynamic state, once with the exact and once with the Gauss–Newton bending Hessian (same tolerance).
// Prints Newton iterations per step, milliseconds per phase per iteration, symbolic analyses and peak RSS.
#include "tools/output/atomic_file.h"
#include "core/mesh_generators.h"
#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "solvers/statics.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <ctime>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace jetshell::cli {
namespace {

struct SolverBenchOptions {
  int n = 100;
  int steps = 60;
  double dt = 1.0 / 60.0;
  int threads = 0;  // 0 = OpenMP's default
  std::string integrator = "backward_euler";
  std::string linearSolver = "auto";
  std::string preconditioner = "ic";
  double cgTolerance = LinearSolverOptions{}.cgRelativeTolerance;
  std::string lineSearch = "armijo";
  std::string projection = "clamp";
  double massDamping = 0.0;
  double stiffnessDamping = 0.0;
  bool skipStatics = false;
  std::string json;
};

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

/// CPU seconds of the whole process (all threads): on a shared, oversubscribed machine the single-thread CPU time
/// is the repeatable figure, wall time is not.
double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double wallSeconds() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// Per-iteration phase times (ms) over a set of Newton solves: medians over the iterations that solved a
/// system, and the totals.
struct PhaseFigures {
  int iterations = 0;
  std::vector<double> assembly, factorization, solve, lineSearch, newtonIteration, cgIterations;
  void add(const SolverSummary& s) {
    iterations += s.iterations;
    for (const IterationRecord& r : s.trace) {
      if (r.factorizationSeconds == 0.0 && r.solveSeconds == 0.0) continue;  // no system solved
      assembly.push_back(1e3 * r.assemblySeconds);
      factorization.push_back(1e3 * r.factorizationSeconds);
      solve.push_back(1e3 * r.solveSeconds);
      lineSearch.push_back(1e3 * r.lineSearchSeconds);
      newtonIteration.push_back(1e3 * (r.assemblySeconds + r.factorizationSeconds + r.solveSeconds));
      cgIterations.push_back(r.cgIterations);
    }
  }
  nlohmann::json toJson() const {
    return {{"iterations", iterations},
            {"median_ms_per_iteration",
             {{"assembly", median(assembly)},
              {"factorization", median(factorization)},
              {"solve", median(solve)},
              {"line_search", median(lineSearch)},
              {"assembly_factorization_solve", median(newtonIteration)}}},
            {"median_cg_iterations", median(cgIterations)}};
  }
  void print(const char* label) const {
    std::printf("%s: %d Newton iterations; median ms per iteration: assembly %.1f, factorization %.1f, solve %.1f, "
                "line search %.1f; assembly+factorization+solve %.1f; median CG iterations %.0f\n",
                label, iterations, median(assembly), median(factorization), median(solve), median(lineSearch),
                median(newtonIteration), median(cgIterations));
  }
};

ShellProblem clothProblem(const SolverBenchOptions& o) {
  ShellProblem p;
  p.mesh = makeRectangleGrid(1.0, 1.0, o.n, o.n);
  p.material = ShellMaterialParamsFrom3dIsotropic(1e5, 0.25, 1000.0, 0.002);
  p.material.massDampingCoefficient = o.massDamping;
  p.material.stiffnessDampingCoefficient = o.stiffnessDamping;
  p.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  const int topLeft = o.n * (o.n + 1), topRight = topLeft + o.n;
  p.prescribed.fixVertex(topLeft, p.mesh.V.row(topLeft).transpose());
  p.prescribed.fixVertex(topRight, p.mesh.V.row(topRight).transpose());
  return p;
}

NewtonOptions newtonOptions(const SolverBenchOptions& o) {
  NewtonOptions n;
  n.linear.type = linearSolverTypeFromString(o.linearSolver);
  n.linear.preconditioner = preconditionerFromString(o.preconditioner);
  n.linear.cgRelativeTolerance = o.cgTolerance;
  n.lineSearch = lineSearchTypeFromString(o.lineSearch);
  n.projection = psdProjectionFromString(o.projection);
  return n;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

int runSolverBench(const SolverBenchOptions& o) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // line-buffered: long runs show progress when redirected
  if (o.threads > 0) omp_set_num_threads(o.threads);
  nlohmann::json out;
  const ShellProblem problem = clothProblem(o);
  std::printf("jetshell bench solver: %d×%d-square cloth, %d vertices, %d faces, pinned at two corners; %d threads\n",
              o.n, o.n, problem.mesh.numVertices(), problem.mesh.numFaces(), omp_get_max_threads());
  out["mesh"] = {{"squares_per_side", o.n},
                 {"vertices", problem.mesh.numVertices()},
                 {"faces", problem.mesh.numFaces()}};
  out["threads"] = omp_get_max_threads();

  // Dynamics.
  ShellSystem dynamics(problem, AnalysisKind::Dynamics);
  DynamicsOptions d;
  d.integrator = timeIntegratorFromString(o.integrator);
  d.timeStep = o.dt;
  d.newton = newtonOptions(o);
  DynamicsSolver solver(dynamics, d);
  std::printf("dynamics (%s, dt = %.5g s, %d steps), active terms: %s\n", o.integrator.c_str(), o.dt, o.steps,
              joined(dynamics.objective().activeTermNames()).c_str());
  PhaseFigures dyn;
  nlohmann::json steps = nlohmann::json::array();
  std::vector<int> iterationsPerStep;
  const double cpu0 = processCpuSeconds(), wall0 = wallSeconds();
  const DynamicsResult run = simulate(solver, o.steps * o.dt, [&](const StepReport& r, DynamicsSolver&) {
    for (const SolverSummary& s : r.solves) dyn.add(s);
    iterationsPerStep.push_back(r.newtonIterations);
    steps.push_back({{"step", r.step},
                     {"time", r.time},
                     {"newton_iterations", r.newtonIterations},
                     {"cuts", r.cuts},
                     {"assembly_ms", 1e3 * r.assemblySeconds},
                     {"factorization_ms", 1e3 * r.factorizationSeconds},
                     {"solve_ms", 1e3 * r.solveSeconds},
                     {"line_search_ms", 1e3 * r.lineSearchSeconds}});
    return true;
  });
  const double dynCpu = processCpuSeconds() - cpu0, dynWall = wallSeconds() - wall0;
  std::printf("  %s\n  wall %.2f s, process CPU %.2f s: %.1f ms wall and %.1f ms CPU per Newton iteration (everything)\n",
              run.message.c_str(), dynWall, dynCpu, 1e3 * dynWall / std::max(1, run.newtonIterations),
              1e3 * dynCpu / std::max(1, run.newtonIterations));
  std::printf("  Newton iterations per step:");
  for (int it : iterationsPerStep) std::printf(" %d", it);
  std::printf("\n");
  dyn.print("  dynamics");
  const int dynamicAnalyses = solver.newton().linearSolver().symbolicAnalyses();
  std::printf("  linear solver %s, symbolic analyses %d, Hessian nnz (upper) %ld, pattern+scatter %.1f MB\n",
              solver.newton().linearSolver().name().c_str(), dynamicAnalyses,
              static_cast<long>(dynamics.objective().assembler().matrix().nonZeros()),
              static_cast<double>(dynamics.objective().assembler().memoryBytes()) / 1e6);
  out["dynamics"] = {{"integrator", o.integrator},
                     {"time_step", o.dt},
                     {"steps", steps},
                     {"completed", run.completed},
                     {"message", run.message},
                     {"active_terms", dynamics.objective().activeTermNames()},
                     {"linear_solver", solver.newton().linearSolver().name()},
                     {"symbolic_analyses", dynamicAnalyses},
                     {"wall_seconds", dynWall},
                     {"process_cpu_seconds", dynCpu},
                     {"phases", dyn.toJson()}};

  // Statics from the last dynamic state: exact against Gauss–Newton bending Hessians.
  if (!o.skipStatics) {
    ShellSystem statics(problem, AnalysisKind::Statics);
    std::printf("statics from the last dynamic state, active terms: %s\n",
                joined(statics.objective().activeTermNames()).c_str());
    nlohmann::json cases = nlohmann::json::object();
    for (BendingHessian bh : {BendingHessian::Exact, BendingHessian::GaussNewton}) {
      const char* name = bh == BendingHessian::Exact ? "exact" : "gauss_newton";
      LoadSteppingOptions ls;
      ls.newton = newtonOptions(o);
      ls.newton.bendingHessian = bh;
      ls.newton.maxIterations = 200;
      Eigen::VectorXd x = solver.positions();
      const double c0 = processCpuSeconds();
      const StaticsResult r = solveStatics(statics, x, ls);
      const double cpu = processCpuSeconds() - c0;
      PhaseFigures st;
      double seconds = 0.0;
      int analyses = 0;
      for (const LoadStepResult& s : r.steps) {
        st.add(s.summary);
        seconds += s.summary.totalSeconds;
        analyses += s.summary.symbolicAnalyses;
      }
      std::printf("  %-12s %s; %.2f s wall, %.2f s process CPU", name, r.message.c_str(), seconds, cpu);
      if (!r.steps.empty()) std::printf("; %s", r.steps.back().summary.briefReport().c_str());
      std::printf("\n");
      st.print("    ");
      nlohmann::json c = {{"completed", r.completed},
                          {"message", r.message},
                          {"load_steps", r.steps.size()},
                          {"cuts", r.totalCuts},
                          {"newton_iterations", r.newtonIterations},
                          {"seconds", seconds},
                          {"process_cpu_seconds", cpu},
                          {"symbolic_analyses", analyses},
                          {"phases", st.toJson()}};
      if (!r.steps.empty()) c["final_step"] = toJson(r.steps.back().summary);
      cases[name] = c;
    }
    out["statics"] = cases;
  }
  const double rss = peakRssMb();
  std::printf("peak RSS %.0f MB\n", rss);
  out["peak_rss_mb"] = rss;
  if (!o.json.empty()) {
    writeFileAtomically(o.json, out.dump(2) + "\n");
    std::printf("wrote %s\n", o.json.c_str());
  }
  return run.completed ? kOk : kFailed;
}

const RegisterSubcommand reg("bench solver", [](CLI::App& app, int& exitCode) {
  CLI::App* bench = benchCommand(app);
  auto opts = std::make_shared<SolverBenchOptions>();
  CLI::App* cmd = bench->add_subcommand("solver", "Newton, linear solver and time stepping on a hanging cloth");
  cmd->add_option("--n", opts->n, "Cloth squares per side (vertices = (n+1)^2)")->check(CLI::Range(2, 2000));
  cmd->add_option("--steps", opts->steps, "Dynamic steps")->check(CLI::Range(0, 100000));
  cmd->add_option("--dt", opts->dt, "Time step [s]")->check(CLI::PositiveNumber);
  cmd->add_option("--threads", opts->threads, "OpenMP threads (default: OpenMP's)")->check(CLI::Range(1, 256));
  cmd->add_option("--integrator", opts->integrator, "backward_euler | bdf2")
      ->check(CLI::IsMember({"backward_euler", "bdf2"}));
  cmd->add_option("--linear-solver", opts->linearSolver, "auto | cholmod | ldlt | pcg")
      ->check(CLI::IsMember({"auto", "cholmod", "ldlt", "pcg"}));
  cmd->add_option("--preconditioner", opts->preconditioner,
                  "PCG preconditioner: jacobi | block_jacobi | ic | lagged_cholesky")
      ->check(CLI::IsMember({"jacobi", "block_jacobi", "ic", "lagged_cholesky"}));
  cmd->add_option("--cg-tolerance", opts->cgTolerance, "PCG relative residual tolerance")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--line-search", opts->lineSearch, "none | armijo | residual | wolfe")
      ->check(CLI::IsMember({"none", "armijo", "residual", "wolfe"}));
  cmd->add_option("--projection", opts->projection, "none | clamp | abs")
      ->check(CLI::IsMember({"none", "clamp", "abs"}));
  cmd->add_option("--mass-damping", opts->massDamping, "alpha_R [1/s]")->check(CLI::NonNegativeNumber);
  cmd->add_option("--stiffness-damping", opts->stiffnessDamping, "beta_R [s]")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--skip-statics", opts->skipStatics, "Dynamics only");
  cmd->add_option("--json", opts->json, "Write the figures as JSON");
  cmd->callback([opts, &exitCode]() { exitCode = runSolverBench(*opts); });
});

}  // namespace
}  // namespace jetshell::cli
