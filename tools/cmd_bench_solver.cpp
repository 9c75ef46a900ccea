// `jetshell bench solver`: the solver on the hanging cloth (tools/bench_cloth.h): `steps` backward-Euler steps
// of Δt, then one static solve from the last dynamic state, once with the exact and once with the Gauss–Newton
// bending Hessian (same tolerance). --orderings compares the fill-reducing orderings of the first step's
// Hessian and of its one-ring part instead (nnz(L), flops, times).
// Prints Newton iterations per step, milliseconds per phase per iteration, the counts (Hessians, factorizations,
// CG iterations, solves that assembled no Hessian; steady under load, unlike the times), symbolic analyses and
// peak RSS; --trace-from N prints the Newton trace of every time step of at least N iterations.
#include "tools/output/atomic_file.h"
#include "core/mesh_generators.h"
#include "solvers/cholmod_factor.h"
#include "solvers/one_ring_pattern.h"
#include "solvers/dynamics.h"
#include "solvers/shell_system.h"
#include "solvers/statics.h"
#include "solvers/time_step_policy.h"
#include "tools/bench_cloth.h"
#include "tools/output/atomic_file.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>
#include <omp.h>

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
  std::string ordering = "auto";
  std::string policy = "jetshell";
  int blasThreads = 1;
  std::string oneRingParts = "auto";  // LinearSolverOptions::oneRingParts
  bool orderings = false;
  double cgTolerance = 0.0;  // 0: the default's (statics) or the time-step policy's (dynamics)
  double maxForcing = -1.0;  // < 0: the policy's; 0: fixed CG tolerance; > 0: Eisenstat–Walker up to this
  std::string lineSearch = "armijo";
  std::string projection = "clamp";
  bool projectAll = false;  // time steps: project every block at every iteration (no exact-Hessian-first)
  int exactFirstProjectedDofs = -1;  // < 0: NewtonOptions' default
  bool hessianAtStart = false;  // time steps: assemble the start's Hessian with its gradient (no gradient-first)
  bool noOverlap = false;       // factor the preconditioner after the assembly, not during it
  std::string fallbackBending = "exact";  // NewtonOptions::fallbackBendingHessian
  double massDamping = 0.0;
  double stiffnessDamping = 0.0;
  bool skipStatics = false;
  int traceFrom = 0;  // > 0: print the Newton trace of every step that takes at least this many iterations
  std::string json;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// Per-iteration phase times (ms) over a set of Newton solves: medians over the iterations that solved a
/// system, and the totals.
struct PhaseFigures {
  int iterations = 0;
  int hessians = 0, factorizations = 0, fallbacks = 0, solves = 0, solvesWithoutHessian = 0;
  long cgTotal = 0;
  std::vector<double> assembly, factorization, overlapped, solve, lineSearch, newtonIteration, cgIterations;
  void add(const SolverSummary& s) {
    iterations += s.iterations;
    hessians += s.hessianEvaluations;
    factorizations += s.numericFactorizations;
    fallbacks += s.projectionFallbacks;
    ++solves;
    if (s.hessianEvaluations == 0) ++solvesWithoutHessian;
    for (const IterationRecord& r : s.trace) {
      if (r.factorizationSeconds == 0.0 && r.solveSeconds == 0.0) continue;  // no system solved
      cgTotal += r.cgIterations;
      assembly.push_back(1e3 * r.assemblySeconds);
      factorization.push_back(1e3 * r.factorizationSeconds);
      overlapped.push_back(1e3 * r.overlappedFactorizationSeconds);
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
              {"factorization_during_assembly", median(overlapped)},
              {"solve", median(solve)},
              {"line_search", median(lineSearch)},
              {"assembly_factorization_solve", median(newtonIteration)}}},
            {"median_cg_iterations", median(cgIterations)},
            {"cg_iterations", cgTotal},
            {"hessian_evaluations", hessians},
            {"numeric_factorizations", factorizations},
            {"projection_fallbacks", fallbacks},
            {"solves", solves},
            {"solves_without_hessian", solvesWithoutHessian}};
  }
  void print(const char* label) const {
    std::printf("%s: %d Newton iterations; median ms per iteration: assembly %.1f (with a factorization of %.1f "
                "during it), factorization %.1f, solve %.1f, line search %.1f; assembly+factorization+solve %.1f; "
                "median CG iterations %.0f\n"
                "%s  counts: %d Hessians (%d projection fallbacks), %d factorizations, %ld CG iterations; %d of %d "
                "solves without a Hessian\n",
                label, iterations, median(assembly), median(overlapped), median(factorization), median(solve),
                median(lineSearch),
                median(newtonIteration), median(cgIterations), label, hessians, fallbacks, factorizations, cgTotal,
                solvesWithoutHessian, solves);
  }
};

NewtonOptions newtonOptions(const SolverBenchOptions& o, const TriMesh& mesh) {
  NewtonOptions n;
  n.linear.oneRingParts = oneRingPartsFromString(o.oneRingParts);
  n.linear.oneRing = std::make_shared<OneRingFilter>(mesh.F, mesh.numVertices(),
                                                     oneRingPartsFor(n.linear, /*movingStencils=*/false));
  n.linear.type = linearSolverTypeFromString(o.linearSolver);
  n.linear.preconditioner = preconditionerFromString(o.preconditioner);
  n.linear.ordering = fillOrderingFromString(o.ordering);
  n.linear.blasThreads = o.blasThreads;
  if (o.cgTolerance > 0.0) n.linear.cgRelativeTolerance = o.cgTolerance;
  n.lineSearch = lineSearchTypeFromString(o.lineSearch);
  n.projection = psdProjectionFromString(o.projection);
  return n;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

/// The fill-reducing orderings on the first time step's Hessian: nnz(L) and flops (deterministic), then the
/// analysis and one numeric factorization timed (wall).
int runOrderingComparison(const SolverBenchOptions& o, const ShellProblem& problem, nlohmann::json& out) {
  ShellSystem dynamics(problem, AnalysisKind::Dynamics);
  DynamicsOptions d;
  d.timeStep = o.dt;
  const Eigen::VectorXd x = dynamics.restPositions();
  dynamics.inertia->setCentre(x, 1.0 / (o.dt * o.dt));  // the first step's inertia, at rest
  Objective& obj = dynamics.objective();
  Eigen::VectorXd g;
  obj.evaluate(x, &g, true, EvalOptions{});
  const Eigen::SparseMatrix<double>& full = obj.assembler().matrix();
  Eigen::SparseMatrix<double> oneRing;
  OneRingFilter(problem.mesh.F, problem.mesh.numVertices()).apply(full, oneRing);
  std::printf("fill-reducing orderings on the first step's Hessian (%ld dofs; nnz(upper H) %ld, of its one-ring "
              "part %ld):\n",
              static_cast<long>(full.rows()), static_cast<long>(full.nonZeros()), static_cast<long>(oneRing.nonZeros()));
  std::printf("  %-9s %-8s %-8s %12s %10s %10s %12s\n", "matrix", "asked", "used", "nnz(L)", "GFlop", "analyze ms",
              "factorize ms");
  nlohmann::json rows = nlohmann::json::array();
  for (const char* which : {"full", "one_ring"})
  for (FillOrdering ordering : {FillOrdering::AMD, FillOrdering::METIS, FillOrdering::NESDIS, FillOrdering::Auto}) {
    const Eigen::SparseMatrix<double>& H = std::string(which) == "full" ? full : oneRing;
    CholmodFactor factor(ordering, o.blasThreads);
    const double w0 = wallSeconds();
    if (factor.analyze(H) != CholmodFactor::Status::Ok) {
      std::printf("  %-8s analysis failed: %s\n", toString(ordering), factor.message().c_str());
      return kFailed;
    }
    const double w1 = wallSeconds();
    const CholmodFactor::Status f = factor.factorize(H, 0.0);
    const double w2 = wallSeconds();
    const FactorStatistics& st = factor.statistics();
    std::printf("  %-9s %-8s %-8s %12.0f %10.3f %10.1f %12.1f%s\n", which, toString(ordering), st.ordering.c_str(), st.nnzL,
                1e-9 * st.flops, 1e3 * (w1 - w0), 1e3 * (w2 - w1),
                f == CholmodFactor::Status::Ok ? "" : " (factorization failed)");
    rows.push_back({{"matrix", which},
                    {"asked", toString(ordering)},
                    {"used", st.ordering},
                    {"nnz_A", st.nnzA},
                    {"nnz_L", st.nnzL},
                    {"flops", st.flops},
                    {"analyze_ms", 1e3 * (w1 - w0)},
                    {"factorize_ms", 1e3 * (w2 - w1)}});
  }
  out["orderings"] = rows;
  return kOk;
}

int runSolverBench(const SolverBenchOptions& o) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // line-buffered: long runs show progress when redirected
  if (o.threads > 0) omp_set_num_threads(o.threads);
  nlohmann::json out;
  const ShellProblem problem = hangingCloth(o.n, o.massDamping, o.stiffnessDamping);
  std::printf("jetshell bench solver: %d×%d-square cloth, %d vertices, %d faces, pinned at two corners; %d threads\n",
              o.n, o.n, problem.mesh.numVertices(), problem.mesh.numFaces(), omp_get_max_threads());
  out["mesh"] = {{"squares_per_side", o.n},
                 {"vertices", problem.mesh.numVertices()},
                 {"faces", problem.mesh.numFaces()}};
  out["threads"] = omp_get_max_threads();
  if (o.orderings) {
    const int code = runOrderingComparison(o, problem, out);
    if (!o.json.empty()) writeFileAtomically(o.json, out.dump(2) + "\n");
    return code;
  }

  // Dynamics.
  ShellSystem dynamics(problem, AnalysisKind::Dynamics);
  DynamicsOptions d;
  d.integrator = timeIntegratorFromString(o.integrator);
  d.timeStep = o.dt;
  d.newton = newtonOptions(o, problem.mesh);
  applyTimeStepPolicy(timeStepPolicyFromString(o.policy), d);
  if (o.projectAll) d.newton.exactHessianFirst = false;
  if (o.exactFirstProjectedDofs >= 0) d.newton.exactFirstProjectedDofs = o.exactFirstProjectedDofs;
  if (o.hessianAtStart) d.newton.gradientFirstStart = false;
  if (o.noOverlap) d.newton.overlapPreconditioner = false;
  d.newton.fallbackBendingHessian = hessianModelFromString(o.fallbackBending);
  if (o.cgTolerance > 0.0) d.newton.linear.cgRelativeTolerance = o.cgTolerance;  // the policy sets its own
  if (o.maxForcing == 0.0) d.newton.adaptiveLinearTolerance = false;
  if (o.maxForcing > 0.0) {
    d.newton.adaptiveLinearTolerance = true;
    d.newton.maxForcingTerm = o.maxForcing;
  }
  DynamicsSolver solver(dynamics, d);
  std::printf("dynamics (%s, dt = %.5g s, %d steps, policy %s), active terms: %s\n", o.integrator.c_str(), o.dt,
              o.steps, o.policy.c_str(),
              joined(dynamics.objective().activeTermNames()).c_str());
  PhaseFigures dyn;
  nlohmann::json steps = nlohmann::json::array();
  std::vector<int> iterationsPerStep;
  const double cpu0 = processCpuSeconds(), wall0 = wallSeconds();
  const DynamicsResult run = simulate(solver, o.steps * o.dt, [&](const StepReport& r, DynamicsSolver&) {
    for (const SolverSummary& s : r.solves) {
      dyn.add(s);
      if (o.traceFrom > 0 && s.iterations >= o.traceFrom)
        std::printf("  step %d (t = %.4f s):\n%s", r.step, r.time, s.fullReport().c_str());
    }
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
  std::printf("  %s\n  wall %.2f s (load %.1f), process CPU %.2f s: %.1f ms wall and %.1f ms CPU per Newton iteration "
              "(everything); %.1f steps per second (wall)\n",
              run.message.c_str(), dynWall, loadAverage(), dynCpu, 1e3 * dynWall / std::max(1, run.newtonIterations),
              1e3 * dynCpu / std::max(1, run.newtonIterations), run.steps / std::max(dynWall, 1e-9));
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
                     {"policy", o.policy},
                     {"load_average", loadAverage()},
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
    for (HessianModel bh : {HessianModel::Exact, HessianModel::GaussNewton}) {
      const char* name = bh == HessianModel::Exact ? "exact" : "gauss_newton";
      LoadSteppingOptions ls;
      ls.newton = newtonOptions(o, problem.mesh);
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

const RegisterSubcommand registerBenchSolver("bench solver", [](CLI::App& app, int& exitCode) {
  CLI::App* bench = benchCommand(app);
  auto opts = std::make_shared<SolverBenchOptions>();
  CLI::App* cmd = bench->add_subcommand("solver", "Newton, linear solver and time stepping on a hanging cloth");
  cmd->add_option("--n", opts->n, "Cloth squares per side (vertices = (n+1)^2)")->check(CLI::Range(2, 2000));
  cmd->add_option("--steps", opts->steps, "Dynamic steps")->check(CLI::Range(0, 100000));
  cmd->add_option("--dt", opts->dt, "Time step [s]")->check(finiteNumber());
  cmd->add_option("--threads", opts->threads, "OpenMP threads (default: OpenMP's)")->check(CLI::Range(1, 256));
  cmd->add_option("--integrator", opts->integrator, "backward_euler | bdf2")
      ->check(CLI::IsMember({"backward_euler", "bdf2"}));
  cmd->add_option("--linear-solver", opts->linearSolver, "auto | cholmod | ldlt | pcg")
      ->check(CLI::IsMember({"auto", "cholmod", "ldlt", "pcg"}));
  cmd->add_option("--preconditioner", opts->preconditioner,
                  "PCG preconditioner: jacobi | block_jacobi | ic | lagged_cholesky | one_ring_cholesky")
      ->check(CLI::IsMember({"jacobi", "block_jacobi", "ic", "lagged_cholesky", "one_ring_cholesky"}));
  cmd->add_option("--blas-threads", opts->blasThreads, "Threads of CHOLMOD's BLAS (OpenBLAS OpenMP build)")
      ->check(CLI::Range(1, 256));
  cmd->add_option("--one-ring-parts", opts->oneRingParts,
                  "The one-ring preconditioner as 1 factor, 2 (the mesh bisected, one factor per core), or auto "
                  "(2 with contact, else 1: the default)")
      ->check(CLI::IsMember({"auto", "1", "2"}));
  cmd->add_option("--policy", opts->policy,
                  "Time-step Newton policy: jetshell | page | reference (Newton to 1e-10 of the force scale)")
      ->check(CLI::IsMember({"jetshell", "page", "reference"}));
  cmd->add_option("--ordering", opts->ordering, "CHOLMOD fill-reducing ordering: auto | amd | metis | nesdis")
      ->check(CLI::IsMember({"auto", "amd", "metis", "nesdis"}));
  cmd->add_flag("--orderings", opts->orderings,
                "Only compare the fill-reducing orderings (nnz(L), flops, times) on the first step's Hessian");
  cmd->add_option("--cg-tolerance", opts->cgTolerance,
                  "PCG relative residual tolerance (default: the time-step policy's in dynamics)")
      ->check(finiteNumber());
  cmd->add_option("--max-forcing", opts->maxForcing,
                  "PCG in dynamics: 0 = fixed --cg-tolerance; > 0 = Eisenstat-Walker forcing terms up to this value "
                  "(default: the policy's)")
      ->check(finiteRange(0.0, 0.9));
  cmd->add_option("--line-search", opts->lineSearch, "none | armijo | residual | wolfe")
      ->check(CLI::IsMember({"none", "armijo", "residual", "wolfe"}));
  cmd->add_flag("--project-all", opts->projectAll,
                "Time steps: project every element block at every iteration (default: small blocks first, "
                "every block only where the system is indefinite)");
  cmd->add_option("--exact-first-projected-dofs", opts->exactFirstProjectedDofs,
                  "Time steps: element blocks of at most this many dofs are projected in the first try (0: none; "
                  "default: NewtonOptions')")
      ->check(CLI::Range(0, 1000));
  cmd->add_flag("--hessian-at-start", opts->hessianAtStart,
                "Time steps: assemble the start's Hessian with its gradient instead of judging the start on its "
                "gradient first");
  cmd->add_flag("--no-overlap", opts->noOverlap,
                "Time steps: factor the one-ring preconditioner after the whole assembly instead of during the "
                "bending terms' assembly (NewtonOptions::overlapPreconditioner)");
  cmd->add_option("--fallback-bending", opts->fallbackBending,
                  "Time steps: the bending Hessian of the projected assembly an indefinite try falls back to: "
                  "gaussNewton (positive semi-definite, not projected) or exact (projected block by block, the "
                  "default)")
      ->check(CLI::IsMember({"gaussNewton", "exact"}));
  cmd->add_option("--projection", opts->projection, "none | clamp | abs")
      ->check(CLI::IsMember({"none", "clamp", "abs"}));
  cmd->add_option("--mass-damping", opts->massDamping, "alpha_R [1/s]")
      ->check(finiteNumber(std::numeric_limits<double>::max(), true));
  cmd->add_option("--stiffness-damping", opts->stiffnessDamping, "beta_R [s]")
      ->check(finiteNumber(std::numeric_limits<double>::max(), true));
  cmd->add_flag("--skip-statics", opts->skipStatics, "Dynamics only");
  cmd->add_option("--trace-from", opts->traceFrom,
                  "Print the Newton trace of every time step that takes at least this many iterations")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--json", opts->json, "Write the figures as JSON")->check(outputFile());
  cmd->callback([opts, &exitCode]() { exitCode = runSolverBench(*opts); });
});

}  // namespace
}  // namespace jetshell::cli
