#include "solvers/shell_contact.h"

#include "energies/contact/surface_sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetshell {
namespace {

/// The most sub-times a step's surface sweep samples (ShellContact::solidSweep).
constexpr double kMaxSweepSubTimes = 4096.0;

}  // namespace

std::vector<std::string> ShellContact::termNames() const {
  std::vector<std::string> names;
  for (const VolumeContactTerms& v : volume)
    for (const EnergyTermPtr& t : {v.penalty, v.damping, v.friction})
      if (t) names.push_back(t->name());
  for (const EnergyTermPtr& t : {pointCloud.penalty, pointCloud.friction})
    if (t) names.push_back(t->name());
  return names;
}

std::vector<std::string> ShellContact::solidNames() const {
  std::vector<std::string> names;
  for (const VolumeContactTerms& v : volume)
    if (std::find(names.begin(), names.end(), v.state->collider->name()) == names.end())
      names.push_back(v.state->collider->name());
  return names;
}

bool ShellContact::guardsBroken(const Eigen::VectorXd& x, double depthFraction, double pairFraction) const {
  for (const VolumeContactTerms& v : volume)
    if (v.state->minDistance(x) < -depthFraction * v.state->params.activationDistance) return true;
  return pointCloud.state && pointCloud.state->minDistanceRatio(x) < pairFraction;
}

std::vector<std::pair<std::string, Eigen::Vector3d>> ShellContact::solidForces(const Eigen::VectorXd& x,
                                                                               double t) const {
  std::vector<std::pair<std::string, Eigen::Vector3d>> forces;
  for (const VolumeContactTerms& v : volume) {
    const std::string& name = v.state->collider->name();
    auto it = std::find_if(forces.begin(), forces.end(), [&](const auto& f) { return f.first == name; });
    if (it == forces.end()) it = forces.insert(forces.end(), {name, Eigen::Vector3d::Zero()});
    it->second += v.state->forceOnSolid(x, t);
    if (!(v.state->timeStep > 0.0)) continue;  // the transient terms are zero until a step begins
    for (const EnergyTermPtr& term : {v.damping, v.friction}) {
      if (!term) continue;
      Eigen::VectorXd gradient = Eigen::VectorXd::Zero(x.size());
      EvalRequest request;
      request.gradient = &gradient;
      term->evaluate(x, request, EvalOptions{});
      for (Eigen::Index i = 0; i < x.size() / 3; ++i) it->second += gradient.segment<3>(3 * i);
    }
  }
  return forces;
}

ShellContact::SolidSweep ShellContact::solidSweep(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double t,
                                                  double h, double maxParts) const {
  SolidSweep sweep;
  const double maxSubTimes = std::min(4.0 * maxParts, kMaxSweepSubTimes);
  for (const VolumeContactTerms& term : volume) {
    const double thinnest = term.state->collider->shape().thinnestHalfWidth();
    if (!std::isfinite(thinnest)) continue;  // the half-space has no far side to jump to
    const double travel = term.state->solidTravel(x, v, t, h), allowed = stepFraction * thinnest;
    // The fewer of the two bounds: the surface's parts are a power of two, so where they are fewer than the
    // material's ratio they are also fewer than the power of two that ratio asks for.
    double parts = travel / allowed;
    bool bySurface = false;
    if (parts > 1.0) {
      const double surface = surfaceSweepParts(*term.state, x, v, t, h, allowed, maxSubTimes);
      bySurface = surface < parts;
      parts = std::min(parts, surface);
    }
    // The solid that needs the most parts; else the first whose material's move asked for some.
    if (parts > sweep.parts || (sweep.solid.empty() && travel > allowed))
      sweep = {std::max(parts, 1.0), term.state->collider->name(), travel, allowed, bySurface};
  }
  return sweep;
}

ShellContact addShellContact(Objective& objective, const std::vector<ShellContactActor>& actors,
                             const std::vector<VolumeColliderPart>& volumes, const Positions& rest, bool dynamic,
                             double stepFraction) {
  ShellContact c;
  c.stepFraction = stepFraction;
  const int n = static_cast<int>(rest.rows());
  for (const ShellContactActor& a : actors) {
    if (!a.mesh) throw InputError("contact: actor '" + a.name + "' has no mesh");
    if (a.firstVertex < 0 || a.mesh->numVertices() > n - a.firstVertex)
      throw InputError("contact: actor '" + a.name + "': its vertices from " + std::to_string(a.firstVertex) +
                       " go past the " + std::to_string(n) + " stacked ones");
    for (const VolumeColliderPart& v : volumes) {
      const std::string suffix = "/" + a.name + "/" + v.collider->name();
      VolumeContactTerms t =
          makeVolumeContactTerms(sampleContactPoints(*a.mesh, a.faceArea, a.quadrature), a.mesh->numVertices(),
                                 v.collider, combine(a.contact, v.contact), suffix, a.firstVertex);
      objective.addTerm(t.penalty, TermRole::Potential);
      if (dynamic && t.damping) objective.addTerm(t.damping, TermRole::Transient);
      if (dynamic && t.friction) objective.addTerm(t.friction, TermRole::Transient);
      if (!dynamic) t.damping = t.friction = nullptr;
      c.volume.push_back(t);
    }
  }
  int clouds = 0;
  bool self = false;
  for (const ShellContactActor& a : actors)
    if (a.pointCloud) {
      ++clouds;
      self = self || a.pointCloudCollider.selfContact;
    }
  if (clouds >= 2 || self) {
    std::vector<PointCloudActor> cloud;
    for (const ShellContactActor& a : actors) {
      if (!a.pointCloud) continue;
      // Samples at the actor's vertices (stacked ids), with their lumped rest areas.
      const int na = a.mesh->numVertices();
      std::vector<double> area(static_cast<std::size_t>(na), 0.0);
      for (int f = 0; f < a.mesh->numFaces(); ++f)
        for (int k = 0; k < 3; ++k) area[a.mesh->F(f, k)] += a.faceArea[f] / 3.0;
      PointCloudActor p;
      p.collider = a.pointCloudCollider;
      p.contact = a.contact;
      for (int v = 0; v < na; ++v)
        if (area[static_cast<std::size_t>(v)] > 0.0) {
          p.vertices.push_back(a.firstVertex + v);
          p.area.push_back(area[static_cast<std::size_t>(v)]);
        }
      cloud.push_back(std::move(p));
    }
    c.pointCloud = makePointCloudTerms(std::move(cloud), rest);
    objective.addTerm(c.pointCloud.penalty, TermRole::Potential);
    if (dynamic && c.pointCloud.friction) objective.addTerm(c.pointCloud.friction, TermRole::Transient);
    if (!dynamic) c.pointCloud.friction = nullptr;
  }
  if (c.empty()) return c;
  double narrowest = std::numeric_limits<double>::infinity();
  for (const ShellContactActor& a : actors) narrowest = std::min(narrowest, a.contact.smoothingDistance);
  for (const VolumeColliderPart& v : volumes) narrowest = std::min(narrowest, v.contact.smoothingDistance);
  c.narrowestRamp = narrowest;
  const std::vector<VolumeContactTerms> volume = c.volume;
  const std::shared_ptr<PointCloudState> cloud = c.pointCloud.state;
  if (dynamic) {
    objective.addStepStartHook([volume, cloud](const Eigen::VectorXd& x, double t, double h) {
      for (const VolumeContactTerms& v : volume) v.state->beginStep(x, t, h);
      if (cloud) cloud->beginStep(x, h);
    });
  }
  // Layers can be tunnelled through, and so can a solid thinner than a step's move: past its middle, the penalty
  // pushes a sample out of the far side (measured: a cloth falling at 6 m/s through a ball of radius 3 cm at
  // 60 Hz). A solid's bound allows at least a fraction of its thinnest half-width, so only thin solids hold the
  // shell back, and the half-space never does (it is not registered).
  for (const VolumeContactTerms& v : volume) {
    if (!std::isfinite(v.state->collider->shape().thinnestHalfWidth())) continue;
    const std::shared_ptr<VolumeContactState> state = v.state;
    objective.addStepBound([state, stepFraction](const Eigen::VectorXd& x, const Eigen::VectorXd& d) {
      return state->stepBound(x, d, stepFraction);
    });
  }
  if (cloud)
    objective.addStepBound([cloud, stepFraction](const Eigen::VectorXd& x, const Eigen::VectorXd& d) {
      return cloud->stepBound(x, d, stepFraction);
    });
  return c;
}

}  // namespace jetshell
