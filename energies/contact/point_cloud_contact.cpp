#include "energies/contact/point_cloud_contact.h"

#include "energies/contact/contact_ramp.h"
#include "energies/element_energy_term.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace jetshell {
namespace {

struct PointPairPenaltyEnergy {
  static constexpr int kVertices = 2;
  static constexpr bool kTranslationInvariant = true;  // a function of x_1 − x_0
  std::shared_ptr<const PointPairData> data;
  template <typename T>
  T operator()(const T* x, int e) const {
    const double D = data->contactDistance[e];
    const T d2 = squaredNorm(load3(x + 3) - load3(x));
    const double v2 = valueOf(d2);
    if (v2 >= D * D) return constant<T>(0.0);
    const double delta = data->smoothing[e];
    if (v2 < 1e-24 * D * D) return constant<T>(data->weight[e] * contactRamp(D, delta));  // no direction
    using std::sqrt;
    return data->weight[e] * contactRamp(D - sqrt(d2), delta);
  }
};

struct PointPairFrictionEnergy {
  static constexpr int kVertices = 2;
  static constexpr bool kTranslationInvariant = true;  // a function of x_0 − x_1
  explicit PointPairFrictionEnergy(std::shared_ptr<const PointPairData> d) : data(std::move(d)) {}
  std::shared_ptr<const PointPairData> data;
  EvalOptions options;  // options.frictionHessian (energies/element_energy_term.h)
  template <typename T>
  T operator()(const T* x, int e) const {
    if (data->frictionForce[e] == 0.0) return constant<T>(0.0);  // not in contact at the step start
    const Eigen::Vector3d& s = data->startDifference[e];
    V3<T> u;
    for (int k = 0; k < 3; ++k) u[k] = x[k] - x[3 + k] - s[k];
    return data->frictionForce[e] * frictionPrimitive(tangentialSlipSquared(u, data->normal[e]),
                                                      data->slipRegularization, options.frictionHessian);
  }
};

/// A term over a pair list that changes as the configuration moves: an ElementEnergyTerm rebuilt on each new
/// list; its version tells the objective to rebuild the Hessian pattern.
template <typename Functor>
class DynamicPairTerm : public EnergyTerm {
 public:
  DynamicPairTerm(std::string name, int numVertices, std::shared_ptr<PointCloudState> state, bool friction)
      : name_(std::move(name)), numVertices_(numVertices), state_(std::move(state)), friction_(friction) {}
  std::string name() const override { return name_; }
  StencilTable stencils() const override { return inner_ ? inner_->stencils() : StencilTable{2, {}}; }
  bool zeroAtRest() const override { return false; }
  bool rigidInvariant() const override { return !friction_; }
  std::uint64_t stencilVersion() const override { return version_; }
  bool stencilsFollowConfiguration() const override { return true; }
  void updateStencils(const Eigen::VectorXd& x) override {
    if (!friction_) state_->refresh(x);
    if (!friction_ && state_->unhashable() && inner_) return;  // keep the last list (its energy is +inf there)
    const std::uint64_t v = friction_ ? state_->frictionVersion() : state_->candidateVersion();
    if (inner_ && v == seen_) return;
    seen_ = v;
    const StencilTable& table = friction_ ? state_->frictionPairs() : state_->candidates();
    const auto& data = friction_ ? state_->frictionData() : state_->candidateData();
    inner_ = std::make_unique<ElementEnergyTerm<Functor>>(name_, table, numVertices_, Functor{data}, false, !friction_);
    ++version_;
  }
  double evaluate(const Eigen::VectorXd& x, const EvalRequest& request, const EvalOptions& options) override {
    // Without a Hessian the pair list may follow x (the pattern is not involved); with one, the caller has
    // brought the stencils up to date (Objective::evaluate does).
    if (request.hessian == nullptr || !inner_) updateStencils(x);
    // Positions the broad phase cannot hash (a wild line-search trial): no pair list, an infinite energy.
    if (!friction_ && state_->unhashable()) return std::numeric_limits<double>::infinity();
    return inner_->evaluate(x, request, options);
  }

 private:
  std::string name_;
  int numVertices_;
  std::shared_ptr<PointCloudState> state_;
  bool friction_;
  std::unique_ptr<ElementEnergyTerm<Functor>> inner_;
  std::uint64_t seen_ = 0, version_ = 0;
};

}  // namespace

PointCloudState::PointCloudState(std::vector<PointCloudActor> actors, const Positions& rest, double skinFraction)
    : actors_(std::move(actors)) {
  for (std::size_t a = 0; a < actors_.size(); ++a) {
    const PointCloudActor& A = actors_[a];
    if (A.area.size() != A.vertices.size()) throw InputError("point cloud: one area per vertex");
    if (!(A.collider.radius > 0.0)) throw InputError("point cloud: radius must be > 0");
    if (!(A.contact.smoothingDistance > 0.0)) throw InputError("point cloud: smoothingDistance must be > 0");
    for (std::size_t i = 0; i < A.vertices.size(); ++i) {
      if (A.vertices[i] < 0 || A.vertices[i] >= rest.rows()) throw InputError("point cloud: vertex out of range");
      vertex_.push_back(A.vertices[i]);
      actorOf_.push_back(static_cast<int>(a));
      area_.push_back(A.area[i]);
    }
    maxContactDistance_ = std::max(maxContactDistance_, 2.0 * A.collider.radius);
    hasFriction_ = hasFriction_ || A.contact.frictionCoefficient > 0.0;
  }
  rest_.resize(numPoints(), 3);
  for (int i = 0; i < numPoints(); ++i) rest_.row(i) = rest.row(vertex_[i]);
  skin_ = skinFraction * maxContactDistance_;
  candidateData_ = std::make_shared<PointPairData>();
  frictionData_ = std::make_shared<PointPairData>();
}

bool PointCloudState::interacts(int a, int b) const {
  const int A = actorOf_[a], B = actorOf_[b];
  if (A != B) return true;
  const PointCloudActor& act = actors_[A];
  if (!act.collider.selfContact) return false;
  const double exclusion = act.collider.selfContactExclusionRatio * 2.0 * act.collider.radius;
  return (rest_.row(a) - rest_.row(b)).squaredNorm() >= exclusion * exclusion;
}

double PointCloudState::contactDistance(int a, int b) const {
  return actors_[actorOf_[a]].collider.radius + actors_[actorOf_[b]].collider.radius;
}

ContactParams PointCloudState::pairParams(int a, int b) const {
  return combine(actors_[actorOf_[a]].contact, actors_[actorOf_[b]].contact);
}

bool PointCloudState::refresh(const Eigen::VectorXd& x) {
  const int n = numPoints();
  const double radius = maxContactDistance_ + skin_;
  unhashable_ = false;
  if (builtAt_.size() == 3 * n) {
    // Pair distances change only by the samples' relative motion: measure each displacement from the centre t
    // of their bounding box. |d_i − d_j| <= |d_i − t| + |d_j − t| <= skin, so no pair that was farther than
    // D + skin at the build is closer than D now. A shirt falling as a whole keeps its list.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d d = x.segment<3>(3 * vertex_[i]) - builtAt_.segment<3>(3 * i);
      lo = lo.cwiseMin(d);
      hi = hi.cwiseMax(d);
    }
    const Eigen::Vector3d t = 0.5 * (lo + hi);
    double moved2 = 0.0;
    bool finite = true;  // a NaN displacement is a move (std::max would pass it over), so it rebuilds, and fails
    for (int i = 0; i < n; ++i) {
      const double m = (x.segment<3>(3 * vertex_[i]) - builtAt_.segment<3>(3 * i) - t).squaredNorm();
      finite = finite && std::isfinite(m);
      moved2 = std::max(moved2, m);
    }
    if (finite && moved2 <= 0.25 * skin_ * skin_) return false;
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> points;
  points.reserve(3 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) points.push_back(x[3 * vertex_[i] + c]);
    // Only a rebuild hashes the points (within the skin the last list stands), so only a rebuild checks them.
    if (!hashablePoint(points.data() + 3 * i, radius)) {
      unhashable_ = true;
      return false;
    }
  }
  builtAt_ = Eigen::Map<const Eigen::VectorXd>(points.data(), 3 * n);
  const std::vector<PointPair> pairs =
      findClosePairs(points, radius, [&](int a, int b) { return interacts(a, b); });
  auto data = std::make_shared<PointPairData>();
  StencilTable table{2, {}};
  table.ids.reserve(2 * pairs.size());
  for (const PointPair& p : pairs) {
    table.ids.push_back(vertex_[p[0]]);
    table.ids.push_back(vertex_[p[1]]);
    const ContactParams c = pairParams(p[0], p[1]);
    data->contactDistance.push_back(contactDistance(p[0], p[1]));
    data->weight.push_back(0.5 * (area_[p[0]] + area_[p[1]]) * c.penaltyStiffness);
    data->smoothing.push_back(c.smoothingDistance);
    data->friction.push_back(c.frictionCoefficient);
  }
  candidates_ = std::move(table);
  candidateData_ = std::move(data);
  ++candidateVersion_;
  ++rebuilds_;
  broadPhaseSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}

void PointCloudState::beginStep(const Eigen::VectorXd& xStart, double h) {
  refresh(xStart);
  if (!hasFriction_) return;
  // Friction runs over the candidate pairs (zero normal force for those not in contact at the step start), so
  // its stencils change only when the candidates do: one pattern rebuild for both terms, not one per step.
  auto data = std::make_shared<PointPairData>();
  const PointPairData& cand = *candidateData_;
  for (int e = 0; e < candidates_.size(); ++e) {
    const int i = candidates_.ids[2 * e], j = candidates_.ids[2 * e + 1];
    const Eigen::Vector3d diff = xStart.segment<3>(3 * i) - xStart.segment<3>(3 * j);
    const double dist = diff.norm();
    const double p = cand.contactDistance[e] - dist;
    const bool touching = p > 0.0 && dist > 0.0;
    data->frictionForce.push_back(touching ? cand.friction[e] * cand.weight[e] * contactRampForce(p, cand.smoothing[e])
                                           : 0.0);
    data->normal.push_back(touching ? Eigen::Vector3d(diff / dist) : Eigen::Vector3d::UnitZ());
    data->startDifference.push_back(diff);
  }
  // V_f: the geometric mean over the point-cloud actors (one regularization for the whole term).
  double vf = 1.0;
  for (const PointCloudActor& a : actors_) vf *= std::pow(a.contact.frictionSlipVelocity, 1.0 / actors_.size());
  data->slipRegularization = vf * h;
  if (frictionMutable_ && frictionVersion_ == candidateVersion_) {
    *frictionMutable_ = std::move(*data);  // same pairs: new lagged values, same pattern
    return;
  }
  frictionPairs_ = candidates_;
  frictionMutable_ = data;
  frictionData_ = std::move(data);
  frictionVersion_ = candidateVersion_;
}

double PointCloudState::stepBound(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double fraction) const {
  double alpha = 1.0;
  for (int e = 0; e < candidates_.size(); ++e) {
    const int i = candidates_.ids[2 * e], j = candidates_.ids[2 * e + 1];
    const Eigen::Vector3d diff = x.segment<3>(3 * i) - x.segment<3>(3 * j);
    const double dist = diff.norm();
    if (dist <= 0.0) continue;
    const double approach = -diff.dot(d.segment<3>(3 * i) - d.segment<3>(3 * j)) / dist;
    if (approach > 0.0) alpha = std::min(alpha, fraction * dist / approach);
  }
  return alpha;
}

double PointCloudState::minDistanceRatio(const Eigen::VectorXd& x) const {
  const int n = numPoints();
  std::vector<double> points(3 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) points[3 * static_cast<std::size_t>(i) + c] = x[3 * vertex_[i] + c];
  double ratio = 1.0;
  for (const PointPair& p : findClosePairs(points, maxContactDistance_, [&](int a, int b) { return interacts(a, b); })) {
    const double dist = (x.segment<3>(3 * vertex_[p[0]]) - x.segment<3>(3 * vertex_[p[1]])).norm();
    ratio = std::min(ratio, dist / contactDistance(p[0], p[1]));
  }
  return ratio;
}

PointCloudTerms makePointCloudTerms(std::vector<PointCloudActor> actors, const Positions& rest) {
  PointCloudTerms t;
  t.state = std::make_shared<PointCloudState>(std::move(actors), rest);
  const int n = static_cast<int>(rest.rows());
  t.penalty = std::make_shared<DynamicPairTerm<PointPairPenaltyEnergy>>("pointcloud_penalty", n, t.state, false);
  if (t.state->hasFriction())
    t.friction = std::make_shared<DynamicPairTerm<PointPairFrictionEnergy>>("pointcloud_friction", n, t.state, true);
  return t;
}

EnergyTermPtr makePointPairPenaltyTerm(const std::string& name, StencilTable pairs,
                                       std::shared_ptr<const PointPairData> data, int numVertices) {
  return std::make_shared<ElementEnergyTerm<PointPairPenaltyEnergy>>(name, std::move(pairs), numVertices,
                                                                     PointPairPenaltyEnergy{std::move(data)}, false, true);
}

EnergyTermPtr makePointPairFrictionTerm(const std::string& name, StencilTable pairs,
                                        std::shared_ptr<const PointPairData> data, int numVertices) {
  return std::make_shared<ElementEnergyTerm<PointPairFrictionEnergy>>(name, std::move(pairs), numVertices,
                                                                      PointPairFrictionEnergy{std::move(data)}, false,
                                                                      false);
}

}  // namespace jetshell
