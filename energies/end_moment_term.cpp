#include "energies/end_moment_term.h"

#include "core/topology.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <utility>

namespace jetshell {
namespace {

Eigen::Vector3d unitFaceNormal(const Eigen::VectorXd& x, const int* ids) {
  const Eigen::Vector3d p0 = x.segment<3>(3 * ids[0]);
  return (x.segment<3>(3 * ids[1]) - p0).cross(x.segment<3>(3 * ids[2]) - p0).normalized();
}

/// Stores the unwrapping origin of element el of the face `ids` at positions x.
void setOrigin(EndMomentEnergy::Element& el, const Eigen::VectorXd& x, const int* ids, double angle) {
  const Eigen::Vector3d n = unitFaceNormal(x, ids);
  const Eigen::Vector3d a = (x.segment<3>(3 * ids[el.to]) - x.segment<3>(3 * ids[el.from])).normalized();
  for (int c = 0; c < 3; ++c) {
    el.origin[c] = n[c];
    el.originAxis[c] = a[c];
  }
  el.originAngle = angle;
}

}  // namespace

EndMomentTerm::EndMomentTerm(int numVertices, const StencilTable& table, std::shared_ptr<EndMomentEnergy::State> state,
                             std::string name)
    : ElementEnergyTerm<EndMomentEnergy>(std::move(name), table, numVertices, EndMomentEnergy{std::move(state)},
                                         /*zeroAtRest=*/false, /*rigidInvariant=*/false),
      faces_(table.ids) {}

void EndMomentTerm::advance(const Eigen::VectorXd& x) {
  EndMomentEnergy::State& s = *functor().state;
  for (std::size_t e = 0; e < s.elements.size(); ++e) {
    const int* ids = faces_.data() + 3 * e;
    double xe[9];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) xe[3 * k + c] = x[3 * ids[k] + c];
    setOrigin(s.elements[e], x, ids, functor().rotation(xe, static_cast<int>(e)));
  }
}

double EndMomentTerm::meanRotation(const Eigen::VectorXd& x) const {
  const EndMomentEnergy::State& s = *functor().state;
  double weighted = 0.0, total = 0.0;
  for (std::size_t e = 0; e < s.elements.size(); ++e) {
    const int* ids = faces_.data() + 3 * e;
    double xe[9];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) xe[3 * k + c] = x[3 * ids[k] + c];
    weighted += s.elements[e].moment * functor().rotation(xe, static_cast<int>(e));
    total += s.elements[e].moment;
  }
  return total != 0.0 ? weighted / total : 0.0;
}

std::shared_ptr<EndMomentTerm> makeEndMomentTerm(const TriMesh& mesh, const std::vector<int>& chain,
                                                 const Eigen::Vector3d& axis, double moment, std::string name) {
  return makeEndMomentTerm(mesh, buildTopology(mesh), chain, axis, moment, std::move(name));
}

std::shared_ptr<EndMomentTerm> makeEndMomentTerm(const TriMesh& mesh, const Topology& topo,
                                                 const std::vector<int>& chain, const Eigen::Vector3d& axis,
                                                 double moment, std::string name) {
  if (!(axis.norm() > 0.0)) throw InputError("end moment: the axis must be nonzero");
  if (chain.size() < 2) throw InputError("end moment: the chain needs at least two vertices");
  double length = 0.0;
  for (std::size_t k = 0; k < chain.size(); ++k) {
    if (chain[k] < 0 || chain[k] >= mesh.numVertices())
      throw InputError("end moment: chain vertex " + std::to_string(k) + " = " + std::to_string(chain[k]) +
                       " is out of range [0, " + std::to_string(mesh.numVertices()) + ")");
    if (k > 0) length += (mesh.V.row(chain[k]) - mesh.V.row(chain[k - 1])).norm();
  }
  auto state = std::make_shared<EndMomentEnergy::State>();
  StencilTable table;
  table.width = 3;
  // The face along each chain segment, found in one pass over the edges.
  std::map<std::pair<int, int>, int> segmentFace;
  for (std::size_t k = 0; k + 1 < chain.size(); ++k)
    segmentFace[{std::min(chain[k], chain[k + 1]), std::max(chain[k], chain[k + 1])}] = -1;
  for (int e = 0; e < topo.numEdges(); ++e) {
    if (!topo.isBoundaryEdge(e)) continue;
    const auto it = segmentFace.find({topo.edges(e, 0), topo.edges(e, 1)});
    if (it != segmentFace.end()) it->second = topo.edgeFaces(e, 0);
  }
  for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
    const int face = segmentFace.at({std::min(chain[k], chain[k + 1]), std::max(chain[k], chain[k + 1])});
    if (face < 0)
      throw InputError("end moment: chain segment " + std::to_string(k) + " (" + std::to_string(chain[k]) + ", " +
                       std::to_string(chain[k + 1]) + ") is not a boundary edge");
    for (int c = 0; c < 3; ++c) table.ids.push_back(mesh.F(face, c));
    const Eigen::Vector3d segment = mesh.V.row(chain[k + 1]) - mesh.V.row(chain[k]);
    const double along = axis.normalized().dot(segment.normalized());
    if (std::abs(along) < 1e-8)
      throw InputError("end moment: chain segment " + std::to_string(k) + " is perpendicular to the axis");
    EndMomentEnergy::Element el{};
    el.moment = moment * segment.norm() / length;
    for (int c = 0; c < 3; ++c) {
      if (mesh.F(face, c) == (along > 0 ? chain[k] : chain[k + 1])) el.from = c;
      if (mesh.F(face, c) == (along > 0 ? chain[k + 1] : chain[k])) el.to = c;
    }
    setOrigin(el, flatten(mesh.V), table.ids.data() + 3 * k, 0.0);
    state->elements.push_back(el);
  }
  return std::make_shared<EndMomentTerm>(mesh.numVertices(), std::move(table), std::move(state), std::move(name));
}

}  // namespace jetshell
