#include "validation/mirrored_clamp_term.h"

namespace jetshell::validation {

std::shared_ptr<MirroredClampTerm> makeMirroredClampTerm(const TriMesh& mesh, const Topology& topo,
                                                         const ShellReference& ref, double alpha, double beta,
                                                         const std::vector<char>& clampedVertices) {
  auto elements = std::make_shared<std::vector<MirroredClampEnergy::Element>>();
  StencilTable table;
  table.width = 6;
  auto marked = [&](int v) { return v < static_cast<int>(clampedVertices.size()) && clampedVertices[v]; };
  for (int f = 0; f < mesh.numFaces(); ++f) {
    MirroredClampEnergy::Element el{};
    bool any = false;
    for (int i = 0; i < 3; ++i) {
      el.boundary[i] = topo.faceNeighbors(f, i) < 0;
      el.clamped[i] = el.boundary[i] && marked(mesh.F(f, (i + 1) % 3)) && marked(mesh.F(f, (i + 2) % 3));
      any = any || el.clamped[i];
    }
    if (!any) continue;
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
    for (int k = 0; k < 6; ++k) table.ids.push_back(topo.bendingStencil(f, k));
    elements->push_back(el);
  }
  if (elements->empty()) return nullptr;
  return std::make_shared<MirroredClampTerm>("mirrored_clamp", std::move(table), mesh.numVertices(),
                                             MirroredClampEnergy{elements, alpha, beta}, /*zeroAtRest=*/true,
                                             /*rigidInvariant=*/false);
}

}  // namespace jetshell::validation
