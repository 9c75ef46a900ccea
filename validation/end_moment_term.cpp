#include "validation/end_moment_term.h"

#include "core/topology.h"
#include "validation/line_load.h"

#include <algorithm>
#include <string>

namespace jetshell::validation {
namespace {

/// Sets the element's unwrapping origin to the normal n (projected on the plane normal to the axis).
/// Returns false when n is (nearly) parallel to the axis.
bool setOrigin(EndMomentEnergy::Element& el, const double axis[3], Eigen::Vector3d n, double angle) {
  const Eigen::Vector3d a(axis[0], axis[1], axis[2]);
  n -= n.dot(a) * a;
  if (!(n.norm() > 1e-8)) return false;
  n.normalize();
  const Eigen::Vector3d side = a.cross(n);
  for (int c = 0; c < 3; ++c) {
    el.side[c] = side[c];
    el.origin[c] = n[c];
  }
  el.originAngle = angle;
  return true;
}

Eigen::Vector3d faceNormal(const Eigen::VectorXd& x, const int* ids) {
  const Eigen::Vector3d p0 = x.segment<3>(3 * ids[0]);
  return (x.segment<3>(3 * ids[1]) - p0).cross(x.segment<3>(3 * ids[2]) - p0);
}

}  // namespace

EndMomentTerm::EndMomentTerm(int numVertices, StencilTable table, std::shared_ptr<EndMomentEnergy::State> state)
    : ElementEnergyTerm<EndMomentEnergy>("end_moment", table, numVertices, EndMomentEnergy{std::move(state)},
                                         /*zeroAtRest=*/false, /*rigidInvariant=*/false),
      faces_(table.ids) {}

void EndMomentTerm::advance(const Eigen::VectorXd& x) {
  EndMomentEnergy::State& s = *functor().state;
  for (std::size_t e = 0; e < s.elements.size(); ++e) {
    const int* ids = faces_.data() + 3 * e;
    double xe[9];
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) xe[3 * k + c] = x[3 * ids[k] + c];
    const double angle = functor().rotation(xe, static_cast<int>(e));
    // A face normal along the axis has no rotation about it: keep the old origin (a tolerated, rare case).
    setOrigin(s.elements[e], s.axis, faceNormal(x, ids), angle);
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
                                                 const Eigen::Vector3d& axis, double moment) {
  if (!(axis.norm() > 0.0)) throw InputError("end moment: the axis must be nonzero");
  const double length = chainLength(mesh, chain);
  const Topology topo = buildTopology(mesh);
  auto state = std::make_shared<EndMomentEnergy::State>();
  const Eigen::Vector3d a = axis.normalized();
  for (int c = 0; c < 3; ++c) state->axis[c] = a[c];
  StencilTable table;
  table.width = 3;
  for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
    const int u = std::min(chain[k], chain[k + 1]), v = std::max(chain[k], chain[k + 1]);
    int face = -1;
    for (int e = 0; e < topo.numEdges(); ++e) {
      if (topo.edges(e, 0) == u && topo.edges(e, 1) == v) {
        if (topo.isBoundaryEdge(e)) face = topo.edgeFaces(e, 0);
        break;
      }
    }
    if (face < 0)
      throw InputError("end moment: chain segment " + std::to_string(k) + " (" + std::to_string(chain[k]) + ", " +
                       std::to_string(chain[k + 1]) + ") is not a boundary edge");
    for (int c = 0; c < 3; ++c) table.ids.push_back(mesh.F(face, c));
    EndMomentEnergy::Element el{};
    el.moment = moment * (mesh.V.row(chain[k + 1]) - mesh.V.row(chain[k])).norm() / length;
    if (!setOrigin(el, state->axis, faceNormal(flatten(mesh.V), table.ids.data() + 3 * k), 0.0))
      throw InputError("end moment: the axis is parallel to the normal of face " + std::to_string(face));
    state->elements.push_back(el);
  }
  return std::make_shared<EndMomentTerm>(mesh.numVertices(), std::move(table), std::move(state));
}

}  // namespace jetshell::validation
