// Runs a benchmark: the statics path (solvers/statics.h, landing on every tabulated λ) or dynamic
// relaxation, then the comparison with the reference.
#include "solvers/dynamic_relaxation.h"
#include "solvers/statics.h"
#include "validation/benchmark.h"
#include "energies/shell/bending_term.h"
#include "energies/shell/boundary_rules.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <limits>
#include <ostream>
#include <sstream>
#include <utility>
#include <vector>

namespace jetshell::validation {
namespace {

double seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void compare(const Benchmark& b, int row, const std::vector<double>& computed, BenchmarkResult& r) {
  BenchmarkRow out;
  out.lambda = b.reference.lambda[row];
  out.computed = computed;
  out.reference = b.reference.value[row];
  double norm = 0.0;
  for (double v : out.reference) norm += v * v;
  norm = std::sqrt(norm);
  const bool printed = row < static_cast<int>(b.reference.halfUnit.size());
  for (std::size_t q = 0; q < computed.size(); ++q) {
    const double scale = b.errorMeasure == ErrorMeasure::PerQuantity ? std::abs(out.reference[q]) : norm;
    const double difference = std::abs(computed[q] - out.reference[q]);
    const double half = printed ? b.reference.halfUnit[row][q] : 0.0;
    out.relError.push_back(difference / scale);
    out.relErrorBeyondDigits.push_back(std::max(0.0, difference - half) / scale);
  }
  r.rows.push_back(std::move(out));
}

}  // namespace

void addBoundaryRules(ShellSystem& system, const BenchmarkCase& c, const BenchmarkRunOptions& o) {
  if (!system.bending) return;
  BoundaryRuleChoice choice;
  choice.free = o.freeRule;
  choice.clamp = o.clamp == ClampKind::Mirrored ? EdgeRule::MirroredClamp : EdgeRule::ReferenceClamp;
  applyBoundaryRules(*system.bending, system.mesh(), c.problem.clampedVertices, momentLoadedVertices(c.problem),
                     choice);
}


NewtonOptions benchmarkNewtonOptions() { return staticNewtonOptions(); }

BenchmarkResult runBenchmark(const Benchmark& b, const BenchmarkRunOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const double cpuStart = processCpuSeconds();
  BenchmarkResult r;
  r.name = b.name;
  r.resolution = o.resolution.n1 > 0 ? o.resolution : b.defaultResolution;
  r.resolution.grading = o.defaultGrading ? b.defaultResolution.grading : o.resolution.grading;
  r.clamp = o.clamp;
  r.diagonals = o.diagonals;
  r.solver = o.useDefaultSolver ? b.defaultSolver : o.solver;
  r.quantities = b.reference.quantities;
  const BenchmarkCase c = b.build(r.resolution, r.clamp, r.diagonals);
  r.vertices = c.problem.mesh.numVertices();
  r.faces = c.problem.mesh.numFaces();
  const Eigen::VectorXd X = flatten(c.problem.mesh.V);
  auto read = [&](const Eigen::VectorXd& x) {
    std::vector<double> q;
    for (const Probe& p : c.probes) q.push_back(p.read(x, X));
    return q;
  };

  if (r.solver == SolverKind::DynamicRelaxation) {
    if (!c.problem.endMoments.empty())
      throw InputError("validate: " + b.name + " has an end moment, which dynamic relaxation cannot unwrap");
    ShellSystem system(c.problem, AnalysisKind::DynamicRelaxation);
    addBoundaryRules(system, c, o);
    RelaxationOptions ro;
    ro.timeStep = o.relaxationTimeStep;
    ro.massDamping = o.relaxationMassDamping;
    ro.maxSteps = o.relaxationMaxSteps;
    ro.residualTolerance = o.relaxationTolerance;
    ro.reuseFactor = o.relaxationReuseFactor;
    ro.reuseStepGradient = o.relaxationReuseStepGradient;
    ro.newton = o.newton;
    Eigen::VectorXd x = X;
    const RelaxationResult rr = relaxToStatic(system, x, ro);
    r.newtonIterations = rr.newtonIterations;
    r.loadSteps = rr.steps;
    r.cuts = rr.cuts;
    r.completed = rr.converged;
    r.message = rr.message;
    compare(b, b.reference.rows() - 1, read(x), r);
  } else {
    ShellSystem system(c.problem, AnalysisKind::Statics);
    addBoundaryRules(system, c, o);
    LoadSteppingOptions so;
    so.levels = b.reference.lambda;
    so.targetLoadFactor = b.reference.lambda.back();
    so.initialIncrement = o.initialIncrement;
    so.maxIncrement = o.maxIncrement;
    so.minIncrement = o.minIncrement;
    so.predictorOrder = o.predictorOrder;
    so.newton = o.newton;
    Eigen::VectorXd x = X;
    int row = 0;
    const StaticsResult sr = solveStatics(system, x, so, [&](const LoadStepResult& s) {
      if (o.log != nullptr) {
        *o.log << "  lambda -> " << s.loadFactor << ": " << s.summary.briefReport();
        if (s.atLevel) {
          // The energy split at each level: a membrane share that falls slowly under refinement is locking.
          Eigen::VectorXd xs = s.x;
          system.objective().evaluate(xs, nullptr, false, EvalOptions{});
          const std::vector<std::string> names = system.objective().activeTermNames();
          const std::vector<double>& e = system.objective().termEnergies();
          *o.log << "; energies";
          for (std::size_t k = 0; k < names.size() && k < e.size(); ++k) *o.log << " " << names[k] << " " << e[k];
        }
        *o.log << "\n";
      }
      if (s.atLevel && row < b.reference.rows()) compare(b, row++, read(s.x), r);
      return true;
    });
    r.newtonIterations = sr.newtonIterations;
    r.loadSteps = static_cast<int>(sr.steps.size());
    r.cuts = sr.totalCuts;
    r.completed = sr.completed && row == b.reference.rows();
    r.message = sr.message;
    if (r.completed) r.message = "every level reached";
  }
  for (const BenchmarkRow& row : r.rows) {
    for (double e : row.relError) r.maxRelError = std::max(r.maxRelError, e);
    for (double e : row.relErrorBeyondDigits) r.maxRelErrorBeyondDigits = std::max(r.maxRelErrorBeyondDigits, e);
  }
  if (r.completed && !r.rows.empty())
    for (double e : r.rows.back().relError) r.finalRelError = std::max(r.finalRelError, e);
  else
    r.finalRelError = r.maxRelError = r.maxRelErrorBeyondDigits = std::numeric_limits<double>::infinity();
  r.wallSeconds = seconds(start);
  r.cpuSeconds = processCpuSeconds() - cpuStart;
  return r;
}

}  // namespace jetshell::validation
