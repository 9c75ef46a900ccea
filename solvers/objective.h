// The objective a minimizer works on: the sum of the active energy terms over one cached Hessian pattern, with
// the prescribed dofs eliminated.
//
// Terms are added once (addTerm), then finalize() builds the pattern: one assembler slot per term that has a
// Hessian stencil, the fixed-dof mask from the prescribed positions. Only active terms are ever added (see
// solvers/shell_system.h, which decides what a scene needs), so nothing inactive is built or evaluated.
// Every term has a role: Potential terms (elastic energies, gravity, loads) define the static problem; Transient
// terms (inertia, mass and stiffness damping, contact damping and friction) exist only inside a time step. The
// static residual of a dynamic system is the gradient of its Potential terms.
// Terms whose stencils follow the configuration (contact pairs) are brought up to date before every evaluation
// (EnergyTerm::updateStencils); the pattern is re-declared, at the next evaluation that asks for a Hessian, when
// one of them changed, exactly to the current stencils by default. setGrowOnlyPattern(true) keeps the union instead (HessianAssembler::setGrowOnly): pairs
// that leave contact stay as stored zeros, so while the contacts stay within the pairs seen before, the matrix
// pattern and its version stay and the linear solver reuses its symbolic analysis. It is off by default: on the
// T-shirt's first 20 steps new pairs appear on almost every iteration, and the stored zeros' fill made it 0.94x
// the speed of exact patterns (BENCHMARKS.md, Contact).
// Two optional hooks serve contact: step-start hooks (a time integrator calls beginStep before each step, so
// lagged quantities such as friction's normal forces are taken at the step start) and step bounds (the
// largest fraction α ≤ 1 of a Newton direction d that is safe to take from x; a Newton solver scales d by
// stepBound(x, d) before its line search, so fast motion cannot tunnel through a layer).
#pragma once

#include "core/assembly.h"
#include "core/term.h"
#include "solvers/prescribed_positions.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_set>
#include <vector>

namespace jetshell {

enum class TermRole { Potential, Transient };
/// Which terms an evaluation sums.
enum class TermSelection { All, PotentialOnly };

/// Scales that turn the solvers' dimensionless tolerances into physical units (see forceScale() and
/// solvers/newton.h). ShellSystem fills them from the scene; a hand-built objective should set them.
struct PhysicalScales {
  double force = 0.0;      // N: the largest external nodal force (weight m_v|g| plus applied force at λ = 1)
  double length = 1.0;     // m: the mean reference edge length
  double stiffness = 0.0;  // N/m: the membrane stiffness λ + 2μ (or (α + β)/L² where larger), largest over actors
  Eigen::VectorXd reference;  // rest positions (3N), against which prescribed displacements are measured
};

/// The force a residual is judged against, and where it came from.
struct ForceScale {
  double value = 0.0;  // N
  std::string source;  // "external_loads", "prescribed_motion", "material" or "initial_residual"
};

class Objective {
 public:
  /// An empty objective over numVertices vertices (3N dofs).
  explicit Objective(int numVertices);

  /// Adds an active term. Throws InputError when its name is already taken or after finalize().
  void addTerm(EnergyTermPtr term, TermRole role = TermRole::Potential);
  /// Sets the prescribed positions (before finalize()). Throws InputError for out-of-range vertices.
  void setPrescribed(PrescribedPositions prescribed);
  /// Builds the Hessian pattern and the fixed-dof mask. Called once; evaluate() calls it if needed.
  void finalize();
  bool finalized() const { return assembler_.finalized(); }

  /// Work to overlap with the assembly of the wide terms: called with the assembler holding the narrow terms'
  /// part of the Hessian, it returns a task (or an empty function). See evaluate().
  using NarrowAssembledHook = std::function<std::function<void()>(const HessianAssembler&)>;
  /// Element blocks of at most this many dofs (one triangle) make a term narrow.
  static constexpr int kNarrowBlockDofs = 9;

  /// Energy at x (size 3N) of the selected terms. When gradient is non-null it is overwritten (size 3N) with
  /// the gradient, fixed entries zeroed. When hessian is true the assembler's matrix is refilled (upper
  /// triangle; fixed dofs identity). Per-term energies are kept for reports (termEnergies()).
  /// With a Hessian and narrowAssembled: the narrow terms (element blocks of at most kNarrowBlockDofs dofs, or
  /// no Hessian) are evaluated first; narrowAssembled is then called, and the task it returns runs on a thread of
  /// its own while the wide terms (bending) are evaluated on the remaining OpenMP threads (with one OpenMP
  /// thread, before them). Exceptions of the task are rethrown here. Energy and gradient are summed in that
  /// order (round-off aside, the same values).
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient, bool hessian, const EvalOptions& options,
                  TermSelection selection = TermSelection::All, const NarrowAssembledHook& narrowAssembled = {});

  /// The Potential terms' gradient (fixed entries zeroed) from the last evaluate() that asked for a gradient, when
  /// that evaluation was taken at exactly x (every entry equal) with derivative path `path`; null otherwise. It is the
  /// static residual a time step's solver has already paid for at its last iterate (dynamic relaxation reads it
  /// instead of evaluating the terms again). The caller must know that no term changed since (load factors,
  /// parameters, origins): only x and the path are compared. Kept only when every Potential term comes before
  /// every Transient term (then it is bit for bit the PotentialOnly evaluation's gradient).
  const Eigen::VectorXd* lastPotentialGradient(const Eigen::VectorXd& x, DerivativePath path) const;

  /// Zeroes the entries of fixed dofs.
  void zeroFixed(Eigen::VectorXd& v) const;
  /// Writes the prescribed values at time t into x.
  void applyPrescribed(double t, Eigen::VectorXd& x) const { prescribed_.apply(t, x); }

  int numVertices() const { return numVertices_; }
  int numDofs() const { return 3 * numVertices_; }
  int numFreeDofs() const { return numFree_; }
  const std::vector<char>& fixedDof() const { return fixedDof_; }
  const PrescribedPositions& prescribed() const { return prescribed_; }

  /// The assembled Hessian and its pattern version (valid after an evaluate() with hessian = true).
  const HessianAssembler& assembler() const { return assembler_; }

  /// Names of the active terms, in evaluation order (the run summary lists them).
  std::vector<std::string> activeTermNames() const;
  /// The term with this name, or null.
  EnergyTermPtr term(const std::string& name) const;
  /// Per-term energies of the last evaluate() (0 for terms it did not select), in activeTermNames() order.
  const std::vector<double>& termEnergies() const { return termEnergies_; }
  /// Σ |term energy| of the last evaluate(): the magnitude that bounds its round-off.
  double energyMagnitude() const;

  void setScales(const PhysicalScales& scales) { scales_ = scales; }
  const PhysicalScales& scales() const { return scales_; }
  /// The force scale F of the configuration x (prescribed values applied) that residuals are judged against, the
  /// same for every solver: the larger of the largest external nodal force and the force of the prescribed motion
  /// (stiffness × largest prescribed displacement from the reference, in x or, after setPrescribedPath, anywhere
  /// on the path; a displacement within the coordinates' round-off, 64 ε (|X| + L), is no motion); when neither
  /// drives the problem, the material's force at unit strain (stiffness × length). It
  /// never depends on the current residual, so a wild starting point cannot loosen its own test. Only an objective
  /// with no scales at all falls back to initialResidual (source "initial_residual").
  ForceScale forceScale(const Eigen::VectorXd& x, double initialResidual) const;
  /// Set by solveStatics for its load path λ in [from, to] and by DynamicsSolver for its run t in [0, duration]:
  /// the prescribed motion is judged by its largest displacement over the path, as the loads are judged by their
  /// value at λ = 1 (after setScales and setPrescribed). By the displacement at the current λ alone, a motion
  /// that comes back left its tolerance at nothing while the deformation it caused remained: an end turned by 360°
  /// is back at its reference, and the tolerance fell to 1e-19 N there. clearPrescribedPath() returns to the
  /// current displacement alone.
  /// `solidMotion` [m]: how far a solid the path moves travels near the shell over it (a static path's keyframed
  /// volume actors, solvers/statics.h), judged as prescribed motion is: it drives the shell as a prescribed
  /// motion would, and the loads alone (a light sheet's weight) would hold its residual to a tolerance far below
  /// the contact forces it makes.
  void setPrescribedPath(double from, double to, double solidMotion = 0.0);
  void clearPrescribedPath() { prescribedPathMotion_ = 0.0; }

  using StepStartHook = std::function<void(const Eigen::VectorXd& xStart, double tStart, double timeStep)>;
  using StepBound = std::function<double(const Eigen::VectorXd& x, const Eigen::VectorXd& direction)>;
  void addStepStartHook(StepStartHook hook) { stepStartHooks_.push_back(std::move(hook)); }
  void addStepBound(StepBound bound) { stepBounds_.push_back(std::move(bound)); }
  /// Runs the step-start hooks (a time step from tStart to tStart + timeStep begins at xStart).
  void beginStep(const Eigen::VectorXd& xStart, double tStart, double timeStep);
  /// min(1, every step bound) at x along direction; 1 without bounds. Always in (0, 1].
  double stepBound(const Eigen::VectorXd& x, const Eigen::VectorXd& direction) const;
  /// Whether a term's stencils follow the configuration (contact pairs), so the pattern may change.
  bool hasMovingStencils() const;
  /// How many times the stencils were re-declared after the first finalize (moving contacts).
  int patternRebuilds() const { return patternRebuilds_; }
  /// Of these, how many built a new matrix pattern (grew it, or pruned it): each costs the linear solver a new
  /// symbolic analysis. The others fitted in the kept pattern.
  int patternGrowths() const { return assembler_.patternBuilds() > 0 ? assembler_.patternBuilds() - 1 : 0; }
  /// Grow-only pattern (default off; see the file comment). Off: every re-declaration builds the exact pattern.
  void setGrowOnlyPattern(bool on) { assembler_.setGrowOnly(on); }
  /// Wall seconds spent in each term's evaluate() (activeTermNames() order) and in updating stencils and
  /// rebuilding the pattern, since construction: the benchmarks' time split. patternSeconds() is the part of
  /// stencilSeconds() spent rebuilding the pattern (the rest updates the stencils: the contact broad phase).
  const std::vector<double>& termSeconds() const { return termSeconds_; }
  /// The kinds of request a term's evaluate() answers: a value, with a gradient, with the Hessian (unprojected),
  /// with the Hessian projected block by block.
  enum class RequestKind { Value, Gradient, Hessian, ProjectedHessian };
  static constexpr int kRequestKinds = 4;
  /// Per term (activeTermNames() order), per RequestKind: the calls and their wall seconds, since construction
  /// (`jetshell bench contact --term-split`). Their seconds add up to termSeconds().
  struct TermRequests {
    std::array<long, kRequestKinds> calls{};
    std::array<double, kRequestKinds> seconds{};
  };
  const std::vector<TermRequests>& termRequests() const { return termRequests_; }
  double stencilSeconds() const { return stencilSeconds_; }
  double patternSeconds() const { return patternSeconds_; }

 private:
  struct Entry {
    EnergyTermPtr term;
    TermRole role;
    int slot;  // assembler slot, -1 without a Hessian stencil
    int blockDofs = 0;  // 3 × stencil width: the size of the term's element Hessian blocks
    std::uint64_t stencilVersion = 0;  // as declared to the assembler
  };
  /// Declares every term's stencils to a fresh pattern and finalizes it.
  void rebuildPattern();
  int numVertices_;
  int numFree_;
  std::vector<Entry> terms_;
  std::unordered_set<std::string> termNames_;  // terms_' names, for addTerm's duplicate check in constant time
  PrescribedPositions prescribed_;
  std::vector<char> fixedDof_;
  HessianAssembler assembler_;
  std::vector<double> termEnergies_;
  PhysicalScales scales_;
  double prescribedPathMotion_ = 0.0;  // m: setPrescribedPath's largest prescribed displacement
  std::vector<StepStartHook> stepStartHooks_;
  std::vector<StepBound> stepBounds_;
  int patternRebuilds_ = 0;
  std::vector<double> termSeconds_;
  std::vector<TermRequests> termRequests_;
  double stencilSeconds_ = 0.0, patternSeconds_ = 0.0;
  // lastPotentialGradient(): the gradient, where it was taken and how; valid only when potentialGradientValid_.
  Eigen::VectorXd potentialGradient_, potentialGradientX_;
  DerivativePath potentialGradientPath_ = DerivativePath::Analytic;
  bool potentialGradientValid_ = false;
};

}  // namespace jetshell
