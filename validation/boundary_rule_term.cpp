#include "validation/boundary_rule_term.h"

#include "core/term.h"

#include <cmath>

namespace jetshell::validation {

const char* toString(BoundaryRule r) {
  switch (r) {
    case BoundaryRule::PageFree: return "page_free";
    case BoundaryRule::ReferenceClamp: return "reference_clamp";
    case BoundaryRule::MirroredClamp: return "mirrored_clamp";
    case BoundaryRule::SecondOrderFree: return "second_order_free";
    case BoundaryRule::SymmetryPlane: return "symmetry_plane";
  }
  return "?";
}

BoundaryRule toBoundaryRule(EdgeRule r) {
  switch (r) {
    case EdgeRule::ReferenceClamp: return BoundaryRule::ReferenceClamp;
    case EdgeRule::MirroredClamp: return BoundaryRule::MirroredClamp;
    default: return BoundaryRule::PageFree;
  }
}

BoundaryRule parseBoundaryRule(const std::string& name) {
  for (BoundaryRule r : {BoundaryRule::PageFree, BoundaryRule::ReferenceClamp, BoundaryRule::MirroredClamp,
                     BoundaryRule::SecondOrderFree, BoundaryRule::SymmetryPlane})
    if (name == toString(r)) return r;
  throw InputError("unknown edge rule '" + name +
                   "' (page_free, reference_clamp, mirrored_clamp, second_order_free, symmetry_plane)");
}

std::shared_ptr<BoundaryRuleTerm> makeBoundaryRuleTerm(const TriMesh& mesh, const Topology& topo,
                                                       const ShellReference& ref, double alpha, double beta,
                                                       const std::vector<char>& clampedVertices,
                                                       const BoundaryRules& rules) {
  auto elements = std::make_shared<std::vector<BoundaryRuleEnergy::Element>>();
  StencilTable table;
  table.width = BoundaryRuleEnergy::kVertices;
  auto marked = [&](int v) { return v < static_cast<int>(clampedVertices.size()) && clampedVertices[v]; };
  const double size = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  auto onPlane = [&](int v, const BoundaryRules::Plane& p) {
    return std::abs((Eigen::Vector3d(mesh.V.row(v).transpose()) - p.point).dot(p.normal.normalized())) <=
           rules.planeTolerance * size;
  };
  for (int f = 0; f < mesh.numFaces(); ++f) {
    BoundaryRuleEnergy::Element el{};
    bool any = false;
    for (int i = 0; i < 3; ++i) {
      el.boundary[i] = topo.faceNeighbors(f, i) < 0;
      el.rule[i] = el.builtIn[i] = BoundaryRule::PageFree;
      if (!el.boundary[i]) continue;
      const int a = mesh.F(f, (i + 1) % 3), b = mesh.F(f, (i + 2) % 3);
      const bool clamped = marked(a) && marked(b);
      el.builtIn[i] = clamped ? rules.builtInClampRule : BoundaryRule::PageFree;
      const bool loaded = a < static_cast<int>(rules.momentLoadedVertices.size()) &&
                          b < static_cast<int>(rules.momentLoadedVertices.size()) && rules.momentLoadedVertices[a] &&
                          rules.momentLoadedVertices[b];
      el.rule[i] = clamped ? rules.clampRule : loaded ? BoundaryRule::PageFree : rules.freeRule;
      for (const BoundaryRules::Plane& p : rules.symmetryPlanes) {
        if (clamped || !onPlane(a, p) || !onPlane(b, p)) continue;
        el.rule[i] = BoundaryRule::SymmetryPlane;
        const Eigen::Vector3d u = p.normal.normalized();
        for (int k = 0; k < 3; ++k) el.plane[i][k] = u[k];
        break;
      }
      any = any || el.rule[i] != el.builtIn[i];
    }
    if (!any) continue;
    el.minimizedOnly = true;
    for (int i = 0; i < 3; ++i)
      if (el.boundary[i] && !((el.rule[i] == BoundaryRule::SecondOrderFree || el.rule[i] == BoundaryRule::PageFree) &&
                              el.builtIn[i] == BoundaryRule::PageFree))
        el.minimizedOnly = false;
    el.area = ref.area[f];
    for (int k = 0; k < 3; ++k) {
      el.B[k] = ref.secondFundamentalForm[f][k];
      el.Ainv[k] = ref.inverseMetric[f][k];
    }
    const Eigen::Vector3d x0 = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d r = (Eigen::Vector3d(mesh.V.row(mesh.F(f, 1))) - x0)
                                  .cross(Eigen::Vector3d(mesh.V.row(mesh.F(f, 2))) - x0)
                                  .normalized();
    for (int k = 0; k < 3; ++k) el.reference[k] = r[k];
    // The face's vertices, then the interior edges' opposite vertices (bendingStencil 3 + i), packed.
    int ids[BoundaryRuleEnergy::kVertices] = {topo.bendingStencil(f, 0), topo.bendingStencil(f, 1),
                                              topo.bendingStencil(f, 2), -1, -1};
    int used = 0;
    for (int i = 0; i < 3; ++i) {
      el.slot[i] = -1;
      if (el.boundary[i]) continue;
      el.slot[i] = used;
      ids[3 + used++] = topo.bendingStencil(f, 3 + i);
    }
    double X[3 * BoundaryRuleEnergy::kVertices] = {};
    for (int k = 0; k < BoundaryRuleEnergy::kVertices; ++k) {
      const int v = ids[k];
      table.ids.push_back(v);
      for (int c = 0; c < 3 && v >= 0; ++c) X[3 * k + c] = mesh.V(v, c);
    }
    double bBuiltIn[3], db[3][3];
    BoundaryRuleEnergy::forms(X, el, el.Brule, bBuiltIn, db);
    elements->push_back(el);
  }
  if (elements->empty()) return nullptr;
  return std::make_shared<BoundaryRuleTerm>("boundary_rules", std::move(table), mesh.numVertices(),
                                            BoundaryRuleEnergy{elements, {{alpha, beta}}}, /*zeroAtRest=*/true,
                                            /*rigidInvariant=*/false);
}

}  // namespace jetshell::validation
