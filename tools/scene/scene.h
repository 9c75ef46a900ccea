// A scene: shell actors and rigid volume actors, their boundary conditions, loads and probes, gravity, the
// analysis (static, dynamic, dynamic relaxation), solver settings and outputs. The C++ form of a scene file
// (tools/scene/scene_json.h reads one; SCENES.md documents both).
#pragma once

#include "tools/scene/actor_params.h"
#include "tools/scene/selector.h"

#include <Eigen/Core>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

namespace jetshell {

/// The load factor λ drives applied loads and prescribed motion, and in statics the weight too: in statics λ runs
/// over the load steps to 1 from the unloaded rest state; in dynamics λ(t) = min(1, t / loadRampTime) (1 throughout
/// when loadRampTime is 0) and gravity acts in full; dynamic relaxation works at λ = 1.
struct FixedCondition {
  int actor = 0;
  VertexSelection select;
  std::array<bool, 3> components{true, true, true};  // which of x, y, z are prescribed
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // m, reached at λ = 1: u = λ·displacement
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      // m/s, dynamics only: u += velocity·t
  struct Rotation {  // rigid rotation of the selected vertices about an axis, angle λ·radians
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radians = 0.0;
  };
  std::optional<Rotation> rotation;
  /// Also clamp the rotation about the boundary edges among the selected vertices (a mesh-independent clamp:
  /// fixing edge nodes alone is a hinge).
  bool clampRotation = false;
  std::string where;  // for messages, e.g. "/actors/0/fixed/1"
};

/// A force on the selected vertices, scaled by λ.
struct LoadCondition {
  enum class Distribution {
    Uniform,     // `force` is the total, shared equally
    EdgeLength,  // the total, shared by length along the boundary edges joining selected vertices (line loads)
    Area,        // the total, shared by lumped area (pressure-like, in a fixed direction)
    PerVertex    // `force` on every selected vertex
  };
  int actor = 0;
  VertexSelection select;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // N
  Distribution distribution = Distribution::Uniform;
  std::string name;  // optional, unique among loads: a fit can scale this load alone (FITTING.md, loadScale)
  std::string where;
};

/// A moment along a boundary edge (an end moment, energies/end_moment_term.h), scaled by λ; static analyses only.
/// The selected vertices must form one open chain of boundary edges; the moment turns the faces along it about
/// the edge's current direction, oriented the way `axis` points at rest (right-hand rule).
struct MomentLoad {
  int actor = 0;
  VertexSelection select;
  double moment = 0.0;                             // N·m, the total at λ = 1
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();  // nonzero, not perpendicular to the edge
  std::string where;
};

/// A vertex whose displacement is reported (probes.csv, summary.json). The selection must pick exactly one.
struct Probe {
  std::string name;
  int actor = 0;
  VertexSelection select;
  std::string where;
};

enum class AnalysisType { Static, Dynamic, DynamicRelaxation };
enum class Integrator { BackwardEuler, BDF2 };

/// Static analyses: how the path is followed (solvers/path_control.h; SCENES.md "Path following").
struct PathControlSettings {
  std::string type = "load";  // load | arcLength | displacement
  int maxSteps = 1000;        // arcLength, displacement: path points before the run gives up
  double loadScaling = 0.0;   // arcLength: ψ (0 cylindrical, 1 spherical)
  std::string probe;          // displacement: the probe whose vertex is driven
  int component = 2;          // displacement: 0, 1, 2 for x, y, z
  double displacement = 0.0;  // displacement: that component's displacement at the last level [m]
};

struct AnalysisSettings {
  AnalysisType type = AnalysisType::Static;
  int loadSteps = 10;                // static: λ = k / loadSteps, k = 1..loadSteps (displacement control: τ)
  PathControlSettings pathControl;   // static
  bool branchSwitching = true;       // static, load control: leave a bifurcation for the stable branch
  double timeStep = 1.0 / 60.0;      // s, dynamic and dynamic relaxation
  double duration = 1.0;             // s, dynamic
  Integrator integrator = Integrator::BackwardEuler;
  double loadRampTime = 0.0;         // s, dynamic: loads and prescribed motion reach λ = 1 at this time
  int maxSteps = 1000;               // dynamic relaxation: give up after this many steps
  double tolerance = 1e-6;           // dynamic relaxation: stop when the static residual ≤ tolerance × force scale
  double massDamping = 0.0;          // dynamic relaxation: α [1/s]; 0 takes the material's massDampingCoefficient
};

/// Nonlinear and linear solver options. Unset values take the analysis' defaults (see SCENES.md).
struct SolverSettings {
  std::optional<int> maxIterations;          // Newton iterations per step (load step or time step)
  std::optional<double> residualTolerance;   // × force scale [N] (see solvers/newton.h)
  std::optional<double> decrementTolerance;  // × force scale × length scale [J]
  std::string lineSearch = "default";        // default | none | armijo | residual | wolfe
  std::string linearSolver = "auto";         // auto | cholmod | ldlt | pcg
  std::string preconditioner = "ic";         // pcg only: jacobi | block_jacobi | ic
  std::string psdProjection = "auto";        // auto (static: none, else clamp) | none | clamp | abs
  std::string derivatives = "analytic";      // analytic | autodiff
  std::string bendingHessian = "exact";      // exact | gaussNewton
  std::string fallbackBendingHessian = "exact";  // time steps: exact | gaussNewton (NewtonOptions)
  std::string frictionHessian = "exact";     // exact | majorizer (core/term.h, energies/contact/contact_ramp.h)
  std::string evaluator = "perFace";         // the membrane's: perFace | staged (tools/scene/scene_evaluator.h)
  int threads = 0;                           // 0: all cores
  /// Dynamics: take the last iterate when Newton reaches maxIterations (the spec engine's behaviour, with 4)
  /// instead of cutting the time step.
  bool acceptIterationCap = false;
};

struct OutputSettings {
  bool vtu = true;        // frames/frame_NNNNN.vtu + frames.pvd
  bool obj = false;       // obj/frame_NNNNN.obj
  int frameStride = 1;    // write every n-th step (the last step is always written)
  bool probesCsv = true;  // probes.csv
  bool png = true;        // final.png: a shaded picture of the last frame
  bool plots = true;      // probes.png: probe displacement over the run
};

/// How the bending term treats boundary edges (VALIDATION.md, "Boundary rules"; SCENES.md).
struct EdgeRuleSettings {
  std::string clamp = "mirrored_clamp";    // clampRotation edges: mirrored_clamp | reference_clamp
  std::string free = "second_order_free";  // free edges: second_order_free (no moment across) | page_free
  struct SymmetryPlane {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  };
  std::vector<SymmetryPlane> symmetryPlanes;  // boundary edges on a plane keep their mid-edge normal in it
};

struct Scene {
  std::string description;
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  // m/s²
  std::vector<ShellActorParams> shells;
  std::vector<VolumeActorParams> volumes;
  std::vector<FixedCondition> fixed;
  std::vector<LoadCondition> loads;
  std::vector<MomentLoad> moments;  // written in a shell actor's "loads" with "moment" instead of "force"
  std::vector<Probe> probes;
  AnalysisSettings analysis;
  SolverSettings solver;
  OutputSettings outputs;
  EdgeRuleSettings edgeRules;

  /// Adds a shell actor after validating it; an empty name becomes "shell<index>". Returns its index.
  /// Throws InputError for an invalid actor or a name already used.
  int addShellActor(ShellActorParams params);
  /// Adds a rigid volume actor after validating it; an empty name becomes "<kind><index>".
  int addVolumeActor(VolumeActorParams params);
  /// The index of the shell actor with this name; throws InputError naming `where` when there is none.
  int shellIndex(const std::string& name, const std::string& where) const;

 private:
  // The names in `shells` and `volumes`, so that adding an actor checks its name in constant time (a scene of
  // 100,000 actors spent 80% of 22 s comparing names). Rebuilt when a vector was changed directly (its size
  // differs); validate() checks every name again.
  std::unordered_set<std::string> shellNames_, volumeNames_;
};

/// The sizes a scene's memory grows with, summed over its actors.
struct SceneTotals {
  std::int64_t shells = 0, volumes = 0;
  std::int64_t vertices = 0, faces = 0;  // of all shell actors (stacked)
  std::int64_t sdfSamples = 0;           // of all SDF grid files, each counted once (a run holds each once)
  std::int64_t keyframes = 0;            // of all volume actors
  std::map<std::string, std::int64_t> sdfFiles;  // the files counted: resolved path -> samples
  void add(const ShellActorParams& s);
  void add(const VolumeActorParams& v);
};
SceneTotals sceneTotals(const Scene& scene);
/// Throws InputError, message starting with `where`, when the totals pass inputLimits(): vertices, faces,
/// actors, shell x volume actor pairs, volume actors x vertices, SDF samples, keyframes. The scene reader checks
/// them after each actor (so that no actor is built past a bound) and validate() once more.
void checkSceneTotals(const SceneTotals& totals, const std::string& where);

/// Checks everything that can be checked without solving: every actor, condition (actor index in range,
/// selectors, finite vectors, at least one component), load, probe (unique names), the analysis and the solver
/// option names. Throws InputError naming the field.
void validate(const Scene& scene);

/// What the scene asks for that its analysis does only in part (a volume actor's constant velocities outside
/// dynamics, every motion in a relaxation, keyframes a static path does not reach), one line each.
std::vector<std::string> unsupportedFeatures(const Scene& scene);

/// What runs a volume actor's path in each analysis (RigidPath::readBy; as solvers/shell_system.h's pathClock).
PathClock pathClock(AnalysisType t);
/// A volume actor's path as the scene's analysis reads it.
RigidPath rigidPath(const VolumeActorParams& p, AnalysisType t);

const char* toString(AnalysisType t);
const char* toString(Integrator i);
const char* toString(LoadCondition::Distribution d);

}  // namespace jetshell
