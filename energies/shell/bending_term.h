// Bending term Σ_f scale · area_f · W_b(κ_f), κ = B_origin − b, on the four-triangle stencil with Kelvin-inverted
// mid-edge normals, differentiated in stages (see bending_term.cpp for the data flow).
#pragma once

#include "core/mesh.h"
#include "energies/shell/reference_state.h"
#include "core/term.h"
#include "core/topology.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
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
  bool rigidInvariant() const override { return clamped_.empty(); }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override;

  /// Clamps the boundary edges whose two endpoints are both marked in vertexMask (size N): the missing
  /// neighbour's normal becomes the face's reference normal instead of the face's current normal, so the
  /// mid-edge normal resists rotation about the edge (a mesh-independent clamp). Returns the number of
  /// clamped edges. An empty mask unclamps.
  int setClampedBoundary(const std::vector<char>& vertexMask);

  /// Moves the curvature origin to b(xOrigin) and scales the energy: with scale = β_R/Δt and xOrigin = x_prev
  /// this is the stiffness-damping potential Δt·β_R·W_b(κ̇), κ̇ = (κ(x) − κ(x_prev))/Δt.
  void setCurvatureOrigin(const Eigen::VectorXd& xOrigin, double scale);
  void setName(std::string name) { name_ = std::move(name); }

 private:
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
  using StageHessian = std::array<Eigen::Matrix3d, 3>;  // ∇² of each output component

  void computeFaceStages(const Eigen::VectorXd& x, int order, bool ad);
  void computeEdgeStages(int order, bool ad);
  double stencil(const Eigen::VectorXd& x, int f, const int* ids, bool wantG, bool wantH, bool ad, bool exact,
                 Eigen::Matrix<double, 18, 1>& g, Eigen::Matrix<double, 18, 18>& H) const;
  void addCurvatureOfB(int f, const Eigen::Vector3d& e0,
                       const Eigen::Vector3d& e1, const Eigen::Vector3d& w, const Eigen::Matrix<double, 3, 12>* M,
                       const Eigen::Matrix<double, 3, 12>* N, const std::int8_t* nloc, const int* fn,
                       const Eigen::Matrix<double, 3, 9>* crossJacobians, Eigen::Matrix<double, 18, 18>& H) const;
  bool isClamped(int edge) const { return !clamped_.empty() && clamped_[edge]; }

  std::string name_ = "bending";
  Faces F_;
  Topology topo_;
  ShellReference ref_;  // secondFundamentalForm = curvature origin
  double alpha_, beta_;
  double scale_ = 1.0;
  bool originMoved_ = false;
  StencilTable table_;
  ElementSchedule schedule_;
  std::vector<std::array<std::int8_t, 9>> neighborLocal_;  // per face, per edge i: local index of g's vertex k
  std::vector<char> clamped_;                              // per edge; empty = none
  std::vector<Eigen::Vector3d> referenceNormal_;           // per face, for clamped edges
  std::vector<FaceStage> faces_;
  std::vector<EdgeStage> edges_;
  std::vector<StageHessian> faceHessian_;  // ∇²_c n_k per face
  std::vector<StageHessian> edgeHessian_;  // ∇²_m n̄_k per edge
  std::vector<double> elementEnergy_;
};

}  // namespace jetshell
