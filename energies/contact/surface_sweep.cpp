#include "energies/contact/surface_sweep.h"

#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace jetshell {
namespace {

/// The fewest parts (a power of two dividing F = d.size() − 1) over each of which the spread of d plus `slack`
/// stays within `allowed`; F itself when none fewer does.
int partsFor(const std::vector<double>& d, double slack, double allowed) {
  const int fine = static_cast<int>(d.size()) - 1;
  for (int parts = 1; parts < fine; parts *= 2) {
    const int length = fine / parts;
    bool fits = true;
    for (int k = 0; k < parts && fits; ++k) {
      const auto [lo, hi] = std::minmax_element(d.begin() + k * length, d.begin() + (k + 1) * length + 1);
      fits = *hi - *lo + slack <= allowed;
    }
    if (fits) return parts;
  }
  return fine;
}

}  // namespace

double surfaceSweepParts(const VolumeContactState& state, const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                         double tStart, double h, double allowed, double maxSubTimes) {
  if (!(allowed > 0.0) || !std::isfinite(allowed))
    throw InputError("surface sweep: the allowed change must be positive and finite");
  const VolumeCollider& collider = *state.collider;
  const RigidPath& path = collider.path();
  if (path.isStatic() || !(h > 0.0)) return 1.0;
  // The surface's speed bound near p over the step: the fastest translation of its pieces, plus their fastest
  // turn that moves the surface (solidTravel's ω') times p's farthest distance from the moving centre.
  const Eigen::Vector3d centre = path.originAt(tStart);
  double speed = 0.0, turn = 0.0, centreTravel = 0.0;
  for (const RigidPath::Piece& piece : path.piecesOver(tStart, h)) {
    speed = std::max(speed, piece.velocity.norm());
    turn = std::max(turn, collider.surfaceTurning(piece).norm());
    centreTravel += piece.duration * piece.velocity.norm();
  }
  struct Reached {
    Eigen::Vector3d p;
    double bound;  // L_p h: the most d(p, ·) can change over the step
  };
  std::vector<Reached> reached;
  double largest = 0.0;
  const int Q = state.sampling.pointsPerElement;
  for (int e = 0; e < state.sampling.numElements(); ++e)
    for (int q = 0; q < Q; ++q) {
      const Eigen::Vector3d p = state.point(x, e, q);
      const double bound = h * (speed + turn * ((p - centre).norm() + centreTravel));
      if (!(bound > 0.0)) continue;
      const double reach = bound + h * state.point(v, e, q).norm() + state.params.activationDistance;
      if (collider.query(p, tStart).distance > reach) continue;
      reached.push_back({p, bound});
      largest = std::max(largest, bound);
    }
  if (reached.empty()) return 1.0;
  // F sub-intervals, each letting d change by at most allowed / 4 anywhere.
  const double needed = 4.0 * largest / allowed;
  if (!(needed <= maxSubTimes)) return std::numeric_limits<double>::infinity();
  int fine = 1;
  while (fine < needed) fine *= 2;
  const int n = static_cast<int>(reached.size());
  int parts = 1;
#pragma omp parallel for schedule(static) reduction(max : parts) if (static_cast<long>(n) * fine >= 65536)
  for (int i = 0; i < n; ++i) {
    std::vector<double> d(static_cast<std::size_t>(fine) + 1);
    for (int j = 0; j <= fine; ++j) d[j] = collider.query(reached[i].p, tStart + h * j / fine).distance;
    parts = std::max(parts, partsFor(d, reached[i].bound / fine, allowed));
  }
  return parts;
}

}  // namespace jetshell
