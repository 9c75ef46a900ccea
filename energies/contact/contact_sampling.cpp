#include "energies/contact/contact_sampling.h"

namespace jetshell {

ContactSampling sampleContactPoints(const TriMesh& mesh, const std::vector<double>& faceArea,
                                    ContactQuadrature quadrature) {
  if (static_cast<int>(faceArea.size()) != mesh.numFaces()) throw InputError("contact sampling: one area per face");
  ContactSampling s;
  if (quadrature == ContactQuadrature::Vertices) {
    std::vector<double> vertexArea(static_cast<std::size_t>(mesh.numVertices()), 0.0);
    for (int f = 0; f < mesh.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) vertexArea[mesh.F(f, k)] += faceArea[f] / 3.0;
    s.verticesPerElement = 1;
    s.pointsPerElement = 1;
    s.table.width = 1;
    for (int v = 0; v < mesh.numVertices(); ++v) {
      if (vertexArea[v] <= 0.0) continue;
      s.table.ids.push_back(v);
      s.weights.push_back(1.0);
      s.area.push_back(vertexArea[v]);
    }
    return s;
  }
  s.verticesPerElement = 3;
  s.table.width = 3;
  const bool centroid = quadrature == ContactQuadrature::FaceCentroids;
  s.pointsPerElement = centroid ? 1 : 3;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    for (int k = 0; k < 3; ++k) s.table.ids.push_back(mesh.F(f, k));
    if (centroid) {
      s.weights.insert(s.weights.end(), {1.0 / 3, 1.0 / 3, 1.0 / 3});
      s.area.push_back(faceArea[f]);
    } else {  // the degree-2 rule at (2/3, 1/6, 1/6) and its permutations
      for (int q = 0; q < 3; ++q) {
        for (int k = 0; k < 3; ++k) s.weights.push_back(k == q ? 2.0 / 3 : 1.0 / 6);
        s.area.push_back(faceArea[f] / 3.0);
      }
    }
  }
  return s;
}

}  // namespace jetshell
