// The validation benchmarks: what a benchmark is (a reference path and a problem builder per mesh resolution),
// how a run is configured, and what it reports.
#pragma once

#include "core/mesh_generators.h"
#include "solvers/dynamic_relaxation.h"
#include "solvers/newton.h"
#include "solvers/shell_system.h"
#include "energies/shell/edge_rules.h"
#include "validation/reference_table.h"

#include <Eigen/Core>

#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace jetshell::validation {

/// How a clamped edge is modelled (a displacement-only shell has no rotation unknowns).
enum class ClampKind {
  Normal,    // fix the edge's nodes; BendingTerm::setClampedBoundary: missing neighbour normal := reference normal
  Mirrored,  // the same nodes; missing neighbour normal := the face normal mirrored about the reference normal
             // (the bending term's mirrored_clamp edge rule, energies/shell/edge_rules.h), so the mid-edge
             // normal keeps the reference direction
  TwoRow,    // fix the edge's nodes and the next row of nodes (the page's example; depends on the mesh)
};
const char* toString(ClampKind k);
/// "normal", "mirrored" or "two-row"; throws InputError otherwise.
ClampKind parseClampKind(const std::string& s);

/// How the equilibrium at each load level is found.
enum class SolverKind {
  LoadStepping,        // Newton on the static problem, load factor raised level by level (cut on failure)
  DynamicRelaxation,   // pseudo-time backward Euler with mass damping to rest (solvers/dynamic_relaxation.h)
};
const char* toString(SolverKind k);

/// How the n1 rows of nodes are spaced across the width between the free edges (the slit plate's radial
/// direction; the other benchmarks ignore it). Cosine: x_k = ½(1 − cos(π k/n1)), fine at both free edges, where
/// the bent plate's boundary layers sit (VALIDATION.md, "Why the slit plate converged at first order").
enum class MeshGrading { Uniform, Cosine };
const char* toString(MeshGrading g);
/// "uniform" | "cosine"; InputError naming --grading otherwise.
MeshGrading parseMeshGrading(const std::string& s);

/// A mesh resolution: two counts whose meaning each benchmark states (nx × ny elements, or radial × angular),
/// and the spacing of the n1 rows.
struct Resolution {
  int n1 = 0, n2 = 0;
  MeshGrading grading = MeshGrading::Uniform;
};

/// A displacement read from the solution: sign × (x − X) of component `component`, averaged over `vertices`.
struct Probe {
  std::vector<int> vertices;
  int component = 2;
  double sign = 1.0;
  double read(const Eigen::VectorXd& x, const Eigen::VectorXd& X) const;
};

/// One benchmark built at one resolution: the problem for the shell system (end moments included) and the
/// probes (one per reference quantity).
struct BenchmarkCase {
  ShellProblem problem;
  std::vector<Probe> probes;
};

/// How a row's relative error is taken.
enum class ErrorMeasure {
  PerQuantity,        // |q − q_ref| / |q_ref|
  DisplacementNorm,   // |q − q_ref| / ‖(q_ref)‖ over the row's quantities (references that pass through 0)
};

struct Benchmark {
  std::string name;         // command-line name
  std::string title;        // one line, with the Sze et al. section
  std::string resolutionMeaning;  // what n1 and n2 count
  ReferenceTable reference;
  ErrorMeasure errorMeasure = ErrorMeasure::PerQuantity;
  Resolution defaultResolution;  // (with its grading) what `validate` runs without --mesh: a mesh within 1% at every
                                 // level in a few CPU seconds, or the page's own mesh for the page's ring
                                 // (VALIDATION.md lists the 1% meshes and their times)
  Resolution minimumResolution{1, 1};  // the coarsest mesh `build` accepts; `validate --mesh` is checked against it
  SolverKind defaultSolver = SolverKind::LoadStepping;  // dynamic relaxation compares λ = 1 only
  std::function<BenchmarkCase(const Resolution&, ClampKind, QuadDiagonals)> build;
};

/// Every benchmark, in a fixed order.
const std::vector<Benchmark>& allBenchmarks();
/// The benchmark with this name; throws InputError listing the names otherwise (and `otherNames`, benchmarks the
/// caller runs by other means, such as the snap-through of validation/snap_through.h).
const Benchmark& findBenchmark(const std::string& name, const std::vector<std::string>& otherNames = {});

/// Newton's defaults with the per-element PSD projection off: on these large-rotation paths the projected
/// Hessian turns Newton's convergence linear (the slit annular plate at 4 x 32 quads: 658 iterations and
/// 8.1 s projected, 296 iterations and 1.3 s unprojected); indefinite systems are still handled by the linear
/// solver's diagonal-shift retries.
NewtonOptions benchmarkNewtonOptions();

/// The knobs that trade time for accuracy or robustness.
struct BenchmarkRunOptions {
  Resolution resolution;  // n1 = 0: the benchmark's default
  bool defaultGrading = true;  // take the benchmark's default grading instead of resolution.grading
  ClampKind clamp = ClampKind::Mirrored;
  EdgeRule freeRule = EdgeRule::SecondOrderFree;          // free edges carry no moment (VALIDATION.md: 2-3x closer
                                                 // than the spec's page_free on the slit plate)
  QuadDiagonals diagonals = QuadDiagonals::Uniform;  // alternating diagonals overestimate the twist 2x
  SolverKind solver = SolverKind::LoadStepping;
  bool useDefaultSolver = true;  // take the benchmark's solver instead of `solver`
  double maxIncrement = 1.0;     // largest load-factor increment of one Newton solve (tabulated levels are
                                 // always hit; an increment that fails is halved)
  double initialIncrement = 0.005;  // the first increment: from the flat state the linear response to the full
                                   // first level overshoots by far (plate: 6 failed 50-iteration attempts)
  double minIncrement = 1e-4;
  int predictorOrder = 3;        // start each Newton solve from the polynomial through this many + 1 past
                                 // equilibria (0: from the last equilibrium)
  NewtonOptions newton = benchmarkNewtonOptions();  // tolerances
  double relaxationTimeStep = 1.0 / 30.0;
  double relaxationMassDamping = 0.0;  // α [1/s]; 0 takes the material's α_R
  double relaxationTolerance = 1e-6;
  int relaxationMaxSteps = 20000;
  bool relaxationReuseFactor = RelaxationOptions{}.reuseFactor;              // modified Newton in each step
  bool relaxationReuseStepGradient = RelaxationOptions{}.reuseStepGradient;  // residual from the step's gradient
  std::ostream* log = nullptr;  // one line per Newton solve (load stepping), or null
};

struct BenchmarkRow {
  double lambda = 0.0;
  std::vector<double> computed, reference, relError;
  /// The error beyond the reference's printed precision: max(0, |q − q_ref| − half a unit of q_ref's last
  /// digit) over the same scale (equal to relError for closed forms).
  std::vector<double> relErrorBeyondDigits;
};

struct BenchmarkResult {
  std::string name;
  Resolution resolution;
  ClampKind clamp = ClampKind::Mirrored;
  QuadDiagonals diagonals = QuadDiagonals::Uniform;  // alternating diagonals overestimate the twist 2x
  SolverKind solver = SolverKind::LoadStepping;
  int vertices = 0, faces = 0;
  double wallSeconds = 0.0;
  double cpuSeconds = 0.0;    // process CPU time (all threads): the repeatable figure on a shared machine
  int newtonIterations = 0;
  int loadSteps = 0;          // accepted Newton solves (or relaxation steps)
  int cuts = 0;               // failed increments that were halved
  bool completed = false;     // every level reached
  std::string message;
  std::vector<std::string> quantities;
  std::vector<BenchmarkRow> rows;
  double maxRelError = 0.0;    // over all rows and quantities
  double finalRelError = 0.0;  // over the quantities at λ = 1
  double maxRelErrorBeyondDigits = 0.0;  // over all rows and quantities, beyond the table's printed digits
};

/// The case's boundary rules on the system: the bending term's mirrored_clamp edge rule on the clamped edges
/// (with ClampKind::Mirrored, else reference_clamp), and options.freeRule on every other boundary edge except the
/// end moment's (energies/shell/boundary_rules.h; on an edge whose nodes are fixed but not clamped, the
/// moment-free rule is a hinge).
void addBoundaryRules(ShellSystem& system, const BenchmarkCase& c, const BenchmarkRunOptions& options);

/// Runs one benchmark: builds its case, solves every tabulated level (or λ = 1 only) and compares.
BenchmarkResult runBenchmark(const Benchmark& benchmark, const BenchmarkRunOptions& options);

}  // namespace jetshell::validation
