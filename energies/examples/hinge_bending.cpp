// Mesh plumbing of the hinge-bending example (energies/examples/hinge_bending.h): per-hinge constants
// and the nested-Jet reference: the same energy written independently as one 12-dof element in plain math, so
// the staged term and the reference check each other.
#include "energies/examples/hinge_bending.h"

#include "core/hinge_stencil.h"
#include "core/stage_graph_term.h"
#include "energies/element_energy_term.h"

#include <cmath>

namespace jetshell {
namespace {

/// The same hinge energy as one 12-dof element, written independently of the stages as plain math: the form a
/// user writes for a small stencil (README compares its length with TinyAD's and Ceres' equivalents).
struct HingeElementEnergy {
  static constexpr int kVertices = 4;
  std::vector<std::array<std::array<int, 3>, 2>> corners;  // per hinge and face: its vertices in stencil numbering
  std::vector<double> weight, restTan;                     // per hinge: k·3ℓ̄²/(Ā_A + Ā_B), tan(θ̄/2)
  template <typename T> T tanHalf(const T* x, int h) const {
    Eigen::Matrix<T, 3, 1> n[2];
    for (int s = 0; s < 2; ++s) {
      const auto p = [&](int k) { return vec3(x + 3 * corners[h][s][k]); };
      n[s] = (p(1) - p(0)).cross(p(2) - p(0)).normalized();
    }
    const Eigen::Matrix<T, 3, 1> e = vec3(x + 3) - vec3(x);
    return n[0].cross(n[1]).dot(e) / (e.norm() * (1.0 + n[0].dot(n[1])));
  }
  template <typename T> T operator()(const T* x, int h) const {
    const T d = 2.0 * (tanHalf(x, h) - restTan[h]);
    return weight[h] * d * d;
  }
};

/// The element energy with its per-hinge constants from the rest positions (the mesh's).
HingeElementEnergy restElementEnergy(const TriMesh& mesh, const HingeStencils& h, double stiffness) {
  HingeElementEnergy energy{h.corners, {}, {}};
  for (int i = 0; i < h.table.size(); ++i) {
    const int* ids = h.table.element(i);
    double x[12];
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) x[3 * k + c] = mesh.V(ids[k], c);
    auto area = [&](int f) {
      const Eigen::Vector3d p0 = mesh.V.row(mesh.F(f, 0));
      return 0.5 * (Eigen::Vector3d(mesh.V.row(mesh.F(f, 1))) - p0).cross(Eigen::Vector3d(mesh.V.row(mesh.F(f, 2))) - p0).norm();
    };
    const double length2 = (mesh.V.row(ids[1]) - mesh.V.row(ids[0])).squaredNorm();
    energy.weight.push_back(stiffness * 3.0 * length2 / (area(h.faces[i][0]) + area(h.faces[i][1])));
    energy.restTan.push_back(energy.tanHalf(static_cast<const double*>(x), i));
  }
  return energy;
}

}  // namespace

EnergyTermPtr makeHingeBendingTerm(const TriMesh& mesh, const Topology& topology, double stiffness) {
  const HingeStencils h = hingeStencils(mesh, topology);
  HingeElementEnergy rest = restElementEnergy(mesh, h, stiffness);
  HingeGraph graph(mesh.numVertices());
  graph.resize<0>(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f)
    graph.setInputs<0>(f, {difference(mesh.F(f, 0), mesh.F(f, 1)), difference(mesh.F(f, 0), mesh.F(f, 2))});
  graph.setElements(h.table);
  for (int i = 0; i < h.table.size(); ++i) {
    const int* v = h.table.element(i);
    graph.setInputs<1>(i, {node(h.faces[i][0]), node(h.faces[i][1]), difference(v[0], v[1])});
    graph.setInputs<2>(i, {node(i)});
  }
  graph.stage<2>() = HingeEnergyDensity{std::move(rest.weight), std::move(rest.restTan)};
  graph.finalize();
  return std::make_shared<StageGraphTerm<HingeGraph>>("hinge_bending", std::move(graph));
}

EnergyTermPtr makeHingeBendingNestedJet(const TriMesh& mesh, const Topology& topology, double stiffness) {
  const HingeStencils h = hingeStencils(mesh, topology);
  return std::make_shared<ElementEnergyTerm<HingeElementEnergy>>("hinge_bending_nested_jet", h.table, mesh.numVertices(),
                                                                 restElementEnergy(mesh, h, stiffness));
}

}  // namespace jetshell
