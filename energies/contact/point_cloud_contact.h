// Shell–shell and self-contact between point-cloud colliders: every contact sample (a shell vertex) is a sphere
// of its actor's radius r; two samples closer than r_a + r_b repel with the penalty ramp, and slide on each
// other with regularized Coulomb friction (the actors' contact parameters, combined by geometric mean).
//   pointcloud_penalty   Σ_pairs w_ij k R(D_ij − ‖x_i − x_j‖)                   (Potential)
//   pointcloud_friction  Σ_pairs μ λ_ij f₀(‖P_ij (Δx_i − Δx_j)‖)                 (Transient)
// D_ij = r_a + r_b, w_ij = ½(A_i + A_j) (the samples' rest areas), λ_ij = w_ij k r(D_ij − ‖x_i^n − x_j^n‖) and
// P_ij = I − n nᵀ (n the pair's direction) lagged at the step start, Δx = x − x^n, ε_v = V_f Δt (V_f the
// geometric mean over the point-cloud actors).
// Which pairs interact: samples of different point-cloud actors; samples of one actor with selfContact whose
// rest positions are at least exclusionRatio · 2r apart. (The ratio applies to the diameter 2r: with the
// spec's 1.5 applied to r, every flat-rest neighbour between 1.5r and 2r apart would be in contact at rest
// and the shell would push itself apart.)
// Candidates come from the spatial hash (energies/contact/spatial_hash.h) with the search radius D + skin
// and are rebuilt when a sample has moved more than skin/2 since the last build, relative to the samples' common
// translation (so no pair closer than D is ever missed, and a cloth falling as a whole keeps its list); the terms' stencils then change and the objective rebuilds its pattern
// (EnergyTerm::updateStencils). Friction runs over the same candidates, with zero normal force for the pairs not
// in contact at the step start, so both terms change their pattern together.
#pragma once

#include "core/mesh.h"
#include "core/term.h"
#include "energies/contact/contact_params.h"
#include "energies/contact/spatial_hash.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

/// One point-cloud actor: its sample vertices (stacked ids) with their rest areas.
struct PointCloudActor {
  std::vector<int> vertices;
  std::vector<double> area;  // m², one per vertex
  PointCloudColliderParams collider;
  ContactParams contact;
};

/// Per-pair data the energies read (one entry per element of their stencil table).
struct PointPairData {
  std::vector<double> contactDistance;  // D_ij [m]
  std::vector<double> weight;           // w_ij k [N/m]
  std::vector<double> smoothing;        // δ [m]
  std::vector<double> friction;         // μ
  // Friction only (lagged):
  std::vector<double> frictionForce;    // μ λ_ij [N]
  std::vector<Eigen::Vector3d> normal;  // n
  std::vector<Eigen::Vector3d> startDifference;  // x_i^n − x_j^n
  double slipRegularization = 0.0;      // ε_v [m]
};

class PointCloudState {
 public:
  /// rest: the stacked rest positions (N × 3). skinFraction: skin = fraction × the largest contact distance.
  PointCloudState(std::vector<PointCloudActor> actors, const Positions& rest, double skinFraction = 0.1);

  int numPoints() const { return static_cast<int>(vertex_.size()); }
  /// Rebuilds the candidate pairs when a sample moved more than skin/2 since the last build, relative to the
  /// centre of all samples' displacements (or never built).
  /// Returns true when it rebuilt. Positions the broad phase cannot hash (a coordinate not finite, or beyond 1e15
  /// cells: a line search's trial of a wild step) build nothing and mark the state unhashable until a refresh at
  /// hashable positions; the penalty term's energy there is +inf, so the trial is rejected, not the run.
  bool refresh(const Eigen::VectorXd& x);
  bool unhashable() const { return unhashable_; }
  /// Lags the friction pairs (in contact at x_n) for a step of length h.
  void beginStep(const Eigen::VectorXd& xStart, double h);
  /// Largest α ≤ 1 such that no candidate pair approaches by more than `fraction` of its distance.
  double stepBound(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double fraction) const;
  /// Over every interacting pair: min ‖x_i − x_j‖ / D_ij (1 when no pair is closer than D).
  double minDistanceRatio(const Eigen::VectorXd& x) const;

  const StencilTable& candidates() const { return candidates_; }
  const std::shared_ptr<const PointPairData>& candidateData() const { return candidateData_; }
  const StencilTable& frictionPairs() const { return frictionPairs_; }
  const std::shared_ptr<const PointPairData>& frictionData() const { return frictionData_; }
  std::uint64_t candidateVersion() const { return candidateVersion_; }
  std::uint64_t frictionVersion() const { return frictionVersion_; }
  bool hasFriction() const { return hasFriction_; }
  double broadPhaseSeconds() const { return broadPhaseSeconds_; }
  int rebuilds() const { return rebuilds_; }

 private:
  bool interacts(int a, int b) const;  // point indices
  double contactDistance(int a, int b) const;
  ContactParams pairParams(int a, int b) const;

  std::vector<PointCloudActor> actors_;
  std::vector<int> vertex_, actorOf_;
  std::vector<double> area_;
  Positions rest_;  // per point
  double maxContactDistance_ = 0.0, skin_ = 0.0;
  bool hasFriction_ = false;
  Eigen::VectorXd builtAt_;  // point positions at the last build (3 × points)
  StencilTable candidates_{2, {}};
  std::shared_ptr<const PointPairData> candidateData_;
  StencilTable frictionPairs_{2, {}};
  std::shared_ptr<const PointPairData> frictionData_;
  std::shared_ptr<PointPairData> frictionMutable_;  // the same data, refilled in place while the pairs stay
  std::uint64_t candidateVersion_ = 0, frictionVersion_ = 0;
  double broadPhaseSeconds_ = 0.0;
  int rebuilds_ = 0;
  bool unhashable_ = false;
};

struct PointCloudTerms {
  std::shared_ptr<PointCloudState> state;
  EnergyTermPtr penalty;   // Potential
  EnergyTermPtr friction;  // Transient; null when every μ is 0
};

PointCloudTerms makePointCloudTerms(std::vector<PointCloudActor> actors, const Positions& rest);

/// The pair penalty as a fixed-pair term (every pair of `pairs` with the given data): the energy the dynamic
/// term evaluates, for the registry and the derivative checks.
EnergyTermPtr makePointPairPenaltyTerm(const std::string& name, StencilTable pairs,
                                       std::shared_ptr<const PointPairData> data, int numVertices);
/// The pair friction as a fixed-pair term (lagged data in `data`).
EnergyTermPtr makePointPairFrictionTerm(const std::string& name, StencilTable pairs,
                                        std::shared_ptr<const PointPairData> data, int numVertices);

}  // namespace jetshell
