// The shell energy (membrane + mid-edge bending) as one straight-line element per face, on the project's own
// stages (energies/shell/shell_stages.h): the reference `jetshell bench elements --straight-line` measures the
// stage framework (core/stage_graph_evaluator.h) against. Same stages, same derivative path, same assembly; only
// the chain rule between the stages is written out here for this one graph, with the element's totals stored by
// coordinate (rows: the 15 reduced coordinates u_k = x_k − x_0, padded to 16; columns: a stage output's three
// components) and the face's membrane and bending in one block with one scatter. What the framework could reach
// if it laid out an element so; not a path of the library (no term uses it, energies/ keeps no chain rule).
//
// Inputs: the mesh, its topology and reference state, the moduli (λ, μ membrane; α, β bending), the bending
// term's stencils (per face: its three vertices, then the vertex across edge i, or −1); every boundary edge takes
// the page's free rule (m = n_A), as the bench's terms do. Per evaluation: positions x, the derivative path.
// Output: the energy; the gradient added into *g; the Hessian's upper triangle added through the assembler's
// slot of the bending stencils (the membrane's 3-vertex block lies inside the face's 6-vertex one).
//
// Data flow of one evaluation (each fact computed once, in this order):
//   1 faces:  n_f and ∂n_f/∂(e0, e1)                                    (FaceNormalStage)
//   2 edges:  m_e = ½(n_A + n_B), n̄_e and ∂n̄/∂m                          (KelvinStage)
//   3 faces:  b, the density's energy and ∂W/∂b; the adjoints w_e of n̄_e; the leaves' gradient
//   4 edges:  the adjoints u_f of the face normals, Jᵀ w through the Kelvin inversion and the mean
//   5 faces:  the normals' leaf gradient; with a Hessian, the element: the totals of n̄ (16×3 each), of b, the
//            density's curvature, the second form's (from its declared constant Hessians), the Kelvin
//            curvature of the edges the face owns (first of the edge's faces), the face normal's own, the
//            membrane's; expanded to the base vertex and scattered once.
#pragma once

#include "core/assembly.h"
#include "core/mesh.h"
#include "core/stage.h"
#include "core/stencil.h"
#include "core/topology.h"
#include "energies/shell/reference_state.h"
#include "energies/shell/shell_stages.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace jetshell {

class StraightLineShell {
 public:
  /// Throws std::invalid_argument when the stencils do not match the mesh (a face's first three vertices are its
  /// own), or when the second form's declared Hessians are not what the element assumes (bilinear in the edge
  /// vectors and the mid-edge normals, each block a multiple of the identity).
  StraightLineShell(const TriMesh& mesh, const Topology& topology, const ShellReference& reference, double lambda,
                    double mu, double alpha, double beta, const StencilTable& bendingStencils);

  /// The energy at x; gradient into *g and Hessian into the assembler's `slot` (the bending stencils' slot) when
  /// given. One thread.
  double evaluate(const Eigen::VectorXd& x, DerivativePath path, Eigen::VectorXd* g, HessianAssembler* hessian,
                  int slot);

 private:
  static constexpr int kRows = 16;  // the 15 reduced coordinates, padded
  using Totals = Eigen::Matrix<double, kRows, 3>;
  using Work = Eigen::Matrix<double, kRows, kRows>;
  using Mat3 = Eigen::Matrix3d;
  using Vec3 = Eigen::Vector3d;
  using Jacobian36 = Eigen::Matrix<double, 3, 6>;

  void faces(const double* x, DerivativePath path, int order);
  void edges(DerivativePath path, int order);
  double secondForms(const double* x, DerivativePath path, int order, bool withMembrane, double* g);
  void edgeAdjoints();
  double elements(const double* x, DerivativePath path, double* g, HessianAssembler* hessian, int slot);
  /// The total of n̄ of face f's edge i over the element's working rows, transposed (16×3).
  void meanTotal(int f, int i, Totals& t) const;
  /// Face f's membrane energy; its gradient over (e0, e1) into ge and (h given) its Hessian there.
  double membrane(int f, const Vec3& e0, const Vec3& e1, DerivativePath path, int order,
                  Eigen::Matrix<double, 6, 1>& ge, Eigen::Matrix<double, 6, 6>* h) const;
  /// Adds a gradient over face f's edge vectors (e0, e1) to its three vertices.
  void addLeaves(int f, const double* ge, double* g) const;

  ShellReference ref_;
  Faces F_;
  Topology topo_;
  std::vector<std::array<int, 6>> stencil_;
  // Per face, per edge i, per side (A, then B: none on a boundary edge), per vertex of that side's face: the
  // working row block (stencil slot − 1), −1 for the base vertex.
  std::vector<std::array<std::int8_t, 18>> meanRows_;
  // The second form's leaf–normal curvature: b_k's Hessian block (edge vector a, normal c) = coef[k][a][c] · I.
  std::array<std::array<std::array<double, 3>, 2>, 3> formCoef_{};
  std::array<Eigen::Matrix<double, 6, 6>, 3> metricHessians_;  // the metric's constant Hessians over (e0, e1)

  FaceNormalStage faceStage_;
  KelvinStage kelvinStage_;
  SecondFormStage formStage_;
  BendingDensityStage bendingStage_;
  MetricStage metricStage_;
  MembraneDensityStage membraneStage_;

  // Per face: normal, its Jacobian over (e0, e1), its adjoint. Per edge: mean, n̄, ∂n̄/∂m, adjoint of n̄.
  std::vector<Vec3> normal_, normalAdjoint_;
  std::vector<Jacobian36> normalJacobian_;
  std::vector<Vec3> mean_, midEdge_, midEdgeAdjoint_;
  std::vector<Mat3> kelvinJacobian_;
};

}  // namespace jetshell
