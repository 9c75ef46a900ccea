// Runs a benchmark: the level driver (load stepping that lands on every tabulated λ) or dynamic relaxation,
// then the comparison with the reference.
#include "solvers/dynamic_relaxation.h"
#include "validation/benchmark.h"
#include "energies/shell/bending_term.h"

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

/// Raises the load factor from 0 through every level, one Newton solve per increment. An increment that
/// does not converge is halved (from the last equilibrium); one that converges in few iterations grows
/// back towards maxIncrement. solveStatics (solvers/statics.h) always starts from λ = 0 and cannot be told to
/// land on given levels or to drive the end-moment term, hence this driver.
class LevelDriver {
 public:
  LevelDriver(ShellSystem& system, EndMomentTerm* moment, const BenchmarkRunOptions& o)
      : system_(system), moment_(moment), options_(o), newton_(system.objective(), o.newton),
        increment_(std::min(o.initialIncrement, o.maxIncrement)) {
    history_.push_back({0.0, system.restPositions()});
  }

  /// Advances the equilibrium x from the current λ to `level`. False when the increment fell below
  /// minIncrement (x keeps the last equilibrium).
  bool advanceTo(double level, Eigen::VectorXd& x, BenchmarkResult& r) {
    while (lambda_ < level - 1e-12) {
      const double next = std::min(level, lambda_ + increment_);
      Eigen::VectorXd trial = predict(next, x);
      system_.objective().applyPrescribed(next, trial);
      setLoadFactor(next);
      const SolverSummary s = newton_.minimize(trial);
      r.newtonIterations += s.iterations;
      if (options_.log != nullptr)
        *options_.log << "  lambda " << lambda_ << " -> " << next << ": " << s.briefReport() << "\n";
      if (!s.converged()) {
        ++r.cuts;
        increment_ = 0.5 * (next - lambda_);
        if (increment_ < options_.minIncrement) {
          setLoadFactor(lambda_);
          std::ostringstream m;
          m << "increment to lambda = " << next << " failed (" << toString(s.reason) << ": " << s.message
            << ") and was cut below " << options_.minIncrement << "; stopped at lambda = " << lambda_;
          r.message = m.str();
          return false;
        }
        continue;
      }
      x = trial;
      lambda_ = next;
      history_.insert(history_.begin(), {lambda_, x});
      if (static_cast<int>(history_.size()) > options_.predictorOrder + 1) history_.pop_back();
      ++r.loadSteps;
      if (moment_ != nullptr) moment_->advance(x);
      if (s.iterations <= 6) increment_ = std::min(options_.maxIncrement, increment_ * 1.5);
    }
    return true;
  }

 private:
  /// The start of the Newton solve at λ = next: the polynomial through the last accepted equilibria (as many
  /// as predictorOrder + 1, Lagrange form) extrapolated to next; the last equilibrium when there are none.
  /// Rotation-free shells need this: Newton's linearization of a large rotation stretches the membrane, so
  /// without a good start each increment costs tens of iterations whatever its size.
  Eigen::VectorXd predict(double next, const Eigen::VectorXd& x) const {
    const int n = static_cast<int>(history_.size());
    if (n < 2) return x;
    Eigen::VectorXd p = Eigen::VectorXd::Zero(x.size());
    for (int i = 0; i < n; ++i) {
      double w = 1.0;
      for (int j = 0; j < n; ++j)
        if (j != i) w *= (next - history_[j].first) / (history_[i].first - history_[j].first);
      p += w * history_[i].second;
    }
    return p;
  }

  void setLoadFactor(double lambda) {
    if (system_.nodalForces) system_.nodalForces->setLoadFactor(lambda);
    if (moment_ != nullptr) moment_->setLoadFactor(lambda);
  }

  ShellSystem& system_;
  EndMomentTerm* moment_;
  const BenchmarkRunOptions& options_;
  NewtonSolver newton_;
  double lambda_ = 0.0;
  double increment_;
  std::vector<std::pair<double, Eigen::VectorXd>> history_;  // accepted (λ, x), newest first
};

void compare(const Benchmark& b, int row, const std::vector<double>& computed, BenchmarkResult& r) {
  BenchmarkRow out;
  out.lambda = b.reference.lambda[row];
  out.computed = computed;
  out.reference = b.reference.value[row];
  double norm = 0.0;
  for (double v : out.reference) norm += v * v;
  norm = std::sqrt(norm);
  for (std::size_t q = 0; q < computed.size(); ++q) {
    const double scale = b.errorMeasure == ErrorMeasure::PerQuantity ? std::abs(out.reference[q]) : norm;
    out.relError.push_back(std::abs(computed[q] - out.reference[q]) / scale);
  }
  r.rows.push_back(std::move(out));
}

/// The mirrored clamp: the bending term's mirrored_clamp edge rule on the clamped edges.
void addMirroredClamp(ShellSystem& system, const BenchmarkCase& c, ClampKind clamp) {
  if (clamp != ClampKind::Mirrored || !system.bending) return;
  system.bending->setEdgeRule(c.problem.clampedVertices, EdgeRule::MirroredClamp);
}

}  // namespace

NewtonOptions benchmarkNewtonOptions() {
  NewtonOptions o;
  o.projection = PsdProjection::None;
  return o;
}

BenchmarkResult runBenchmark(const Benchmark& b, const BenchmarkRunOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const double cpuStart = processCpuSeconds();
  BenchmarkResult r;
  r.name = b.name;
  r.resolution = o.resolution.n1 > 0 ? o.resolution : b.defaultResolution;
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
    if (!c.momentEdge.empty())
      throw InputError("validate: " + b.name + " has an end moment, which dynamic relaxation cannot unwrap");
    ShellSystem system(c.problem, AnalysisKind::DynamicRelaxation);
    addMirroredClamp(system, c, r.clamp);
    RelaxationOptions ro;
    ro.timeStep = o.relaxationTimeStep;
    ro.massDamping = o.relaxationMassDamping;
    ro.maxSteps = o.relaxationMaxSteps;
    ro.residualTolerance = o.relaxationTolerance;
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
    addMirroredClamp(system, c, r.clamp);
    std::shared_ptr<EndMomentTerm> moment;
    if (!c.momentEdge.empty()) {
      moment = makeEndMomentTerm(c.problem.mesh, c.momentEdge, c.momentAxis, c.moment);
      system.objective().addTerm(moment);
      // Without nodal forces the Newton tolerances need a force scale: the couple of nodal forces that
      // carries one segment's share of the moment across one element.
      PhysicalScales scales = system.objective().scales();
      scales.force = std::abs(c.moment) / (static_cast<double>(c.momentEdge.size() - 1) * scales.length);
      system.objective().setScales(scales);
    }
    LevelDriver driver(system, moment.get(), o);
    Eigen::VectorXd x = X;
    r.completed = true;
    for (int row = 0; row < b.reference.rows(); ++row) {
      if (!driver.advanceTo(b.reference.lambda[row], x, r)) {
        r.completed = false;
        break;
      }
      compare(b, row, read(x), r);
    }
    if (r.completed) r.message = "every level reached";
  }
  for (const BenchmarkRow& row : r.rows)
    for (double e : row.relError) r.maxRelError = std::max(r.maxRelError, e);
  if (r.completed && !r.rows.empty())
    for (double e : r.rows.back().relError) r.finalRelError = std::max(r.finalRelError, e);
  else
    r.finalRelError = r.maxRelError = std::numeric_limits<double>::infinity();
  r.wallSeconds = seconds(start);
  r.cpuSeconds = processCpuSeconds() - cpuStart;
  return r;
}

}  // namespace jetshell::validation
