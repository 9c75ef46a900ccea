// Bending term Σ_f scale · area_f · W_b(κ_f), κ = B_origin − b, on the four-triangle stencil with Kelvin-inverted
// mid-edge normals, differentiated in stages (see bending_term.cpp for the data flow). Two evaluators of the same
// energy: the hand-chained passes of bending_term.cpp (the default, faster today, see BENCHMARKS.md) and, after
// setStaged(), the stage framework (core/stage_graph.h, bending_term_staged.cpp): face normals once per face,
// edge means and mid-edge normals once per edge (a boundary edge's from its ghost-normal rule), the second
// fundamental form and the density per stencil (energies/shell/shell_stages.h), chained by the framework: no
// derivative by hand. Both take
// every edge rule (a moment-free edge's minimized density is the density stage's, differentiated like the rest).
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

  /// Evaluates on the stage framework instead of the hand-chained passes (same energy, to rounding).
  void setStaged(bool staged);
  bool staged() const { return staged_; }
  /// The staged evaluator's window plan (core/stage_window_plan.h), for the benches; null until setStaged(true).
  const StageWindowPlan* windowPlan() const { return graph_ ? &graph_->windowPlan() : nullptr; }

 private:
  // ---- the staged evaluator (bending_term_staged.cpp) ----
  /// The bending energy as a stage graph (core/stage_graph.h): face normals per face, edge means and their
  /// Kelvin inversions per edge, then per stencil the second fundamental form and the density.
  using Graph = StageGraph<6,
                           Shared<FaceNormalStage, 3, Difference, Difference>,  // n_f, per face
                           Shared<EdgeMeanStage, 4, From<0>, From<0>>,           // m_e, per edge
                           Shared<KelvinStage, 4, From<1>>,                      // n̄_e, per edge
                           Local<SecondFormStage, Difference, Difference, From<2>, From<2>, From<2>>,  // b
                           Local<BendingDensityStage, From<3>>>;                 // the stencil's energy
  double evaluateStaged(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options);
  /// b at every face of xOrigin from the graph (values only), into ref_.secondFundamentalForm.
  void stagedCurvatureOrigin(const Eigen::VectorXd& xOrigin);
  /// Builds the graph's tables (once, on the first staged use).
  void buildGraph();
  /// Points the stages at this term's rules, reference and current parameters (before each evaluation).
  void bindStages();
  bool staged_ = false;
  std::unique_ptr<Graph> graph_;
  std::unique_ptr<StageGraphEvaluator<Graph>> graphEvaluator_;

  // ---- the hand-chained evaluator (bending_term.cpp) ----
  // Stage results are split by order so that a pass touches only what it needs (the stencil pass is bound by
  // memory traffic): values and Jacobians together, Hessians apart (exact Hessian only).
  struct FaceStage {
    Eigen::Vector3d n;
    Eigen::Matrix3d dndc;
  };
  struct EdgeStage {
    Eigen::Vector3d nbar;
    Eigen::Matrix3d dndm;
  };
  /// A boundary edge's ghost stage: ∂m/∂n = ½(I + ∂n_ghost/∂n) and ½ ∇²n_ghost,k (from Jets of its rule).
  struct GhostStage {
    Eigen::Matrix3d dmdn;
    std::array<Eigen::Matrix3d, 3> hessians;
  };
  using StageHessian = std::array<Eigen::Matrix3d, 3>;  // ∇² of each output component

  /// stageHessians: keep the stages' Hessians (order 2) per face and edge for the stencils; without, an order-2
  /// pass leaves them to contractCurvature (the ghost rules' Hessians are kept either way).
  /// hessian: also keep ∂n/∂x per face (faceJacobian_) for the stencils' Jacobians.
  void computeFaceStages(const Eigen::VectorXd& x, int order, bool ad, bool stageHessians, bool hessian);
  void computeEdgeStages(int order, bool ad, bool stageHessians);
  /// W and ∂W/∂b of face f's density at b (before the area scale), and W'' when Wbb is given.
  void faceDensity(int f, const double* b, bool ad, double& W, Eigen::Vector3d& w, Eigen::Matrix3d* Wbb) const;
  /// Exact Hessian, no projection: each face's and edge's stage Hessians, contracted once with the total
  /// adjoint of its normal, summed over the stencils that share it (four per face normal, two per mid-edge
  /// normal), into faceCurvature_ and edgeCurvature_ (the stage Hessians are taken here, not stored). The
  /// stencil of face f then assembles its own face's curvature and that of the edges it owns (owner of edge e:
  /// topo.edgeFaces(e, 0)); the sum over stencils is the same Hessian, with each term in one block instead of
  /// one per sharing stencil.
  void contractCurvature(const Eigen::VectorXd& x, bool ad);
  /// upper: fill only the upper vertex blocks of H (r <= c, in stencil order), all that assembly reads; the
  /// others are left unset. Used when no projection needs the whole block.
  /// contracted: contractCurvature has run for this evaluation (exact Hessian, upper blocks).
  double stencil(const Eigen::VectorXd& x, int f, const int* ids, bool wantG, bool wantH, bool ad, bool exact,
                 bool upper, bool contracted, Eigen::Matrix<double, 18, 1>& g,
                 Eigen::Matrix<double, 18, 18>& H) const;
  /// The stencil's gradient J_bᵀ w by adjoints (gradient-only evaluations; w already scaled by the area).
  void gradientByAdjoints(const Eigen::VectorXd& x, int f, const int* ids, const Eigen::Vector3d& e0,
                          const Eigen::Vector3d& e1, const Eigen::Vector3d& w, const std::int8_t* nloc, const int* fn,
                          Eigen::Matrix<double, 18, 1>& g) const;
  void addCurvatureOfB(int f, bool contracted, const Eigen::Vector3d& e0,
                       const Eigen::Vector3d& e1, const Eigen::Vector3d& w, const Eigen::Matrix<double, 3, 12>* M,
                       const Eigen::Matrix<double, 3, 12>* N, const std::int8_t* nloc, const int* fn,
                       const Eigen::Matrix<double, 3, 9>* crossJacobians, bool upper,
                       Eigen::Matrix<double, 18, 18>& H) const;
  Eigen::Vector3d meanNormal(int edge, int order);
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
  std::vector<std::array<std::int8_t, 9>> neighborLocal_;  // per face, per edge i: local index of g's vertex k
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
  std::vector<GhostStage> ghosts_;                         // per edge (boundary edges only)
  std::vector<FaceStage> faces_;
  std::vector<Eigen::Matrix<double, 3, 9>> faceJacobian_;  // ∂n/∂x per face, in its own vertex order (Hessian passes)
  std::vector<EdgeStage> edges_;
  std::vector<StageHessian> faceHessian_;  // ∇²_c n_k per face (sized by the first pass that keeps them)
  std::vector<StageHessian> edgeHessian_;  // ∇²_m n̄_k per edge (the same)
  /// contractCurvature's results: per face, Σ_k h_k ∇²_c n_k (with the ghost rules' curvature) and the cross
  /// product's coupling Q; per edge, Σ_k a_k ∇²_m n̄_k.
  struct FaceCurvature {
    Eigen::Matrix3d c, q;
  };
  std::vector<FaceCurvature> faceCurvature_;
  std::vector<Eigen::Vector3d> edgeMeans_;  // per edge, m of n̄(m), kept by an edge pass for contractCurvature
  std::vector<Eigen::Matrix3d> edgeCurvature_;
  // contractCurvature's adjoints: per face, of each of its edges' mid-edge normals (this stencil's share);
  // per edge, of its mean normal (the total over both stencils).
  std::vector<std::array<Eigen::Vector3d, 3>> slotAdjoint_;
  std::vector<Eigen::Vector3d> meanAdjoint_;
  std::vector<double> elementEnergy_;
};

}  // namespace jetshell
