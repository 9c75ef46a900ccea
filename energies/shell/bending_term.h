// Bending term Σ_f scale · area_f · W_b(κ_f), κ = B_origin − b, on the four-triangle stencil with Kelvin-inverted
// mid-edge normals, evaluated as a stage graph (core/stage_graph.h, bending_graph.cpp): face normals once per
// face, edge means and mid-edge normals once per edge (a boundary edge's from its ghost-normal rule), the second
// fundamental form and the density per stencil (energies/shell/shell_stages.h), chained by the framework: no
// derivative by hand. Every edge rule goes through the same graph (a moment-free edge's minimized density is the
// density stage's, differentiated like the rest).
//
// Inputs: the mesh, its topology and reference state (B, A⁻¹, areas), the moduli α, β; per boundary edge a rule
// (energies/shell/edge_rules.h; page_free until set): ghost-normal rules close the edge's mid-edge normal, and
// on a face with second_order_free edges the density is minimized over those edges' normals (closed form).
// Outputs: energy, gradient, Hessian (exact, Gauss–Newton, either projected per element), parameter and
// origin derivatives.
#pragma once

#include "core/mesh.h"
#include "core/stage_graph.h"
#include "core/stage_graph_evaluator.h"
#include "energies/shell/shell_stages.h"
#include "energies/shell/reference_state.h"
#include "core/term.h"
#include "core/topology.h"
#include "energies/shell/edge_rules.h"
#include "energies/shell/shell_geometry.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

class BendingTerm : public EnergyTerm {
 public:
  BendingTerm(const TriMesh& mesh, const Topology& topology, const ShellReference& reference, double alpha,
              double beta);
  std::string name() const override { return name_; }
  StencilTable stencils() const override { return table_; }
  bool hasAnalytic() const override { return true; }
  /// Zero at the reference configuration until the origin is moved (stiffness damping: zero at x_prev).
  bool zeroAtRest() const override { return !originMoved_; }
  /// Invariant while no boundary edge has a rule holding reference data or a fixed direction (the clamps, the
  /// symmetry plane); the free rules keep it invariant.
  bool rigidInvariant() const override { return rigidEdges_ == 0; }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override;

  /// Parameters: "alpha", "beta" (α, β of W_b); a stiffness-damping term (makeStiffnessDamping) has "beta_R",
  /// "alpha", "beta" (its energy is β_R-scaled W_b with these moduli).
  /// Derivatives from duals seeded on them over the whole stencil (core/parameter_derivatives.h).
  std::vector<std::string> parameterNames() const override;
  std::vector<double> parameterValues() const override;
  void setParameterValues(const std::vector<double>& values) override;
  void evaluateParameterDerivatives(const Eigen::VectorXd& x, ParameterDerivatives& out) override;

  /// Gives the boundary edges whose two endpoints are both marked in vertexMask (size N) the rule
  /// (energies/shell/edge_rules.h). Other edges keep theirs. Returns the number of edges set. `axis` is the
  /// symmetry plane's normal for SymmetryPlane (any finite nonzero length; InputError otherwise), unused by
  /// the other rules. Until the curvature origin is moved, the origin of a face with a symmetry-plane edge
  /// becomes b(X) with that rule (X the rest positions), so the term stays zero at rest; the other rules
  /// close the edge with the face's rest normal at rest and leave B as given.
  int setEdgeRule(const std::vector<char>& vertexMask, EdgeRule rule,
                  const Eigen::Vector3d& axis = Eigen::Vector3d::Zero());
  /// The rule of boundary edge e (PageFree for every edge until set).
  EdgeRule edgeRule(int e) const { return rules_[static_cast<std::size_t>(e)]; }

  /// Every boundary edge back to the page's free rule, then the reference clamp on the edges marked in
  /// vertexMask: the missing neighbour's normal becomes the face's reference normal, so the mid-edge normal
  /// resists rotation about the edge (a mesh-independent clamp). Returns the number of clamped edges.
  int setClampedBoundary(const std::vector<char>& vertexMask);

  /// Moves the curvature origin to b(xOrigin) and scales the energy: with scale = β_R/Δt and xOrigin = x_prev
  /// this is the stiffness-damping potential Δt·β_R·W_b(κ̇), κ̇ = (κ(x) − κ(x_prev))/Δt.
  void setCurvatureOrigin(const Eigen::VectorXd& xOrigin, double scale);
  void setName(std::string name) { name_ = std::move(name); }
  /// (∂²E/∂x∂y) S at x, y the curvature origin last given to setCurvatureOrigin (zero before): how the gradient
  /// moves when the origin moves along the columns of S (3N × P, P ≤ 8). From duals (core/origin_derivatives.h).
  Eigen::MatrixXd originCrossDerivatives(const Eigen::VectorXd& x, const Eigen::MatrixXd& S) const;
  /// Makes this the stiffness-damping term: its parameter becomes β_R (value betaR > 0), and the energy
  /// scales with β_R / betaR relative to the scale given to setCurvatureOrigin.
  void makeStiffnessDamping(double betaR);

  /// The graph's window plan (core/stage_window_plan.h), for the benches.
  const StageWindowPlan& windowPlan() const { return graph_->windowPlan(); }

 private:
  // ---- the stage graph (bending_graph.cpp) ----
  /// The bending energy as a stage graph (core/stage_graph.h): face normals per face, edge means and their
  /// Kelvin inversions per edge, then per stencil the second fundamental form and the density.
  using Graph = StageGraph<6,
                           Shared<FaceNormalStage, 3, Difference, Difference>,  // n_f, per face
                           Shared<EdgeMeanStage, 4, From<0>, From<0>>,           // m_e, per edge
                           Shared<KelvinStage, 4, From<1>>,                      // n̄_e, per edge
                           Local<SecondFormStage, Difference, Difference, From<2>, From<2>, From<2>>,  // b
                           Local<BendingDensityStage, From<3>>>;                 // the stencil's energy
  /// b at every face of xOrigin from the graph (values only), into ref_.secondFundamentalForm.
  void graphCurvatureOrigin(const Eigen::VectorXd& xOrigin);
  /// Builds the graph's tables (in the constructor).
  void buildGraph();
  /// Points the stages at this term's rules, reference and current parameters (before each evaluation).
  void bindStages();
  std::unique_ptr<Graph> graph_;
  std::unique_ptr<StageGraphEvaluator<Graph>> graphEvaluator_;

  /// After a rule change: the counts, the per-face moment-free flags and (origin not moved) the rest origin.
  void updateRuleState();
  /// Brings ruledQuadratic_ up to date with α, β and the rules: for the faces with moment-free edges (before a
  /// derivative pass of the analytic path), or for every face (before a Hessian pass of the AD path).
  void updateRuledQuadratics(bool everyFace);
  StencilEdges stencilEdges(int f) const;
  /// scale_, times β_R / β_R(reference) for a stiffness-damping term.
  double energyScale() const { return dampingReference_ > 0.0 ? scale_ * dampingValue_ / dampingReference_ : scale_; }

  std::string name_ = "bending";
  Faces F_;
  Topology topo_;
  ShellReference ref_;  // secondFundamentalForm = curvature origin
  double alpha_, beta_;
  double scale_ = 1.0;
  double dampingReference_ = 0.0;  // > 0: a stiffness-damping term with parameter β_R (this value at scale_)
  double dampingValue_ = 0.0;
  bool originMoved_ = false;
  Eigen::VectorXd origin_;  // the positions the curvature origin was taken from
  StencilTable table_;
  ElementSchedule schedule_;
  std::vector<EdgeRule> rules_;                            // per edge (boundary edges only matter)
  std::vector<EdgeRuleData> ruleData_;                     // per edge
  int rigidEdges_ = 0;                                     // boundary edges whose rule sees rigid motions
  std::vector<std::array<bool, 3>> minimized_;             // per face, per edge i: a moment-free boundary edge
  // A face with moment-free edges has a density that is a constant quadratic form in b (a Schur complement of
  // W_b's form, edge_rules.h): W = ½ (b − B)ᵀ A_f (b − B). The analytic path takes w and W'' from A_f, taken
  // once from Jets of the rule's density, instead of nested Jets per face and evaluation (measured: a third of
  // the slit ring's gradient). Every face's density is such a quadratic form (A_f = W_b'' for the other faces), so
  // the AD path takes W'' of every face from here and only w from first-order Jets per evaluation; the derivative
  // checks compare it with the finite-difference Jacobian of that gradient. Kept for the α, β and rules it was
  // taken with.
  std::vector<Eigen::Matrix3d> ruledQuadratic_;
  double quadraticAlpha_ = 0.0, quadraticBeta_ = 0.0;
  bool quadraticStale_ = true;
  bool quadraticEveryFace_ = false;
  Eigen::VectorXd restPositions_;                          // X (the symmetry plane's rest origin)
  std::vector<Sym2> givenForm_;                       // B as given (the page's free rule at every edge)
  std::vector<double> elementEnergy_;
};

}  // namespace jetshell
