// Mesh plumbing of the hinge-bending example (energies/examples/hinge_bending.h): stencils, per-hinge constants
// and the nested-Jet reference, which composes the very same stage functions into one 12-dof element.
#include "energies/examples/hinge_bending.h"

#include "energies/element_energy_term.h"

#include <cmath>

namespace jetshell {
namespace {

/// Per interior edge: the stencil (a, b, c, d), the two faces and their vertices in stencil numbering.
struct HingeLayout {
  StencilTable table{4, {}};
  std::vector<std::array<int, 2>> faces;
  std::vector<std::array<std::array<int, 3>, 2>> corners;
};

HingeLayout hingeLayout(const TriMesh& mesh, const Topology& topology) {
  HingeLayout h;
  for (int e = 0; e < topology.numEdges(); ++e) {
    const int fa = topology.edgeFaces(e, 0), fb = topology.edgeFaces(e, 1);
    if (fb < 0) continue;
    // (a, b) in face A's order, c its third vertex; face B holds (b, a) and d.
    int a = -1, b = -1, c = -1;
    for (int k = 0; k < 3; ++k) {
      const int p = mesh.F(fa, k), q = mesh.F(fa, (k + 1) % 3);
      if ((p == topology.edges(e, 0) && q == topology.edges(e, 1)) ||
          (p == topology.edges(e, 1) && q == topology.edges(e, 0))) {
        a = p;
        b = q;
        c = mesh.F(fa, (k + 2) % 3);
      }
    }
    int d = -1;
    for (int k = 0; k < 3; ++k)
      if (mesh.F(fb, k) != a && mesh.F(fb, k) != b) d = mesh.F(fb, k);
    const int ids[4] = {a, b, c, d};
    h.table.ids.insert(h.table.ids.end(), ids, ids + 4);
    h.faces.push_back({fa, fb});
    std::array<std::array<int, 3>, 2> corner{};
    for (int s = 0; s < 2; ++s)
      for (int k = 0; k < 3; ++k) {
        const int v = mesh.F(s == 0 ? fa : fb, k);
        for (int l = 0; l < 4; ++l)
          if (ids[l] == v) corner[s][k] = l;
      }
    h.corners.push_back(corner);
  }
  return h;
}

/// The hinge energy of the stencil positions x (12 values) as one function: the stages composed.
template <typename T>
T composedHingeEnergy(const T* x, const HingeEnergyDensity& density, const std::array<std::array<int, 3>, 2>& corner,
                      int hinge) {
  T z[9];
  for (int s = 0; s < 2; ++s) {
    const V3<T> p0 = load3(x + 3 * corner[s][0]);
    const V3<T> e0 = load3(x + 3 * corner[s][1]) - p0, e1 = load3(x + 3 * corner[s][2]) - p0;
    const T edges[6] = {e0[0], e0[1], e0[2], e1[0], e1[1], e1[2]};
    HingeFaceNormal()(edges, z + 3 * s, 0);
  }
  for (int c = 0; c < 3; ++c) z[6 + c] = x[3 + c] - x[c];
  T t[1], energy[1];
  HingeTanHalf()(z, t, hinge);
  density(t, energy, hinge);
  return energy[0];
}

HingeEnergyDensity restDensity(const TriMesh& mesh, const HingeLayout& h, double stiffness) {
  HingeEnergyDensity density;
  const int n = h.table.size();
  density.weight.resize(static_cast<std::size_t>(n));
  density.restTan.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    const int* ids = h.table.element(i);
    double x[12];
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) x[3 * k + c] = mesh.V(ids[k], c);
    auto area = [&](int f) {
      const Eigen::Vector3d p0 = mesh.V.row(mesh.F(f, 0));
      return 0.5 * (Eigen::Vector3d(mesh.V.row(mesh.F(f, 1))) - p0).cross(Eigen::Vector3d(mesh.V.row(mesh.F(f, 2))) - p0).norm();
    };
    const double length2 = (mesh.V.row(ids[1]) - mesh.V.row(ids[0])).squaredNorm();
    density.weight[i] = stiffness * 3.0 * length2 / (area(h.faces[i][0]) + area(h.faces[i][1]));
    // tan(θ̄/2) from the same function: with unit weight, E(r) = 4(t − r)², so t = (E(0) − E(1))/8 + 1/2.
    const HingeEnergyDensity probe0{{1.0}, {0.0}}, probe1{{1.0}, {1.0}};
    density.restTan[i] = (composedHingeEnergy(x, probe0, h.corners[i], 0) - composedHingeEnergy(x, probe1, h.corners[i], 0)) / 8.0 + 0.5;
  }
  return density;
}

struct HingeNestedEnergy {
  static constexpr int kVertices = 4;
  HingeEnergyDensity density;
  std::vector<std::array<std::array<int, 3>, 2>> corners;
  template <typename T>
  T operator()(const T* x, int hinge) const {
    return composedHingeEnergy(x, density, corners[hinge], hinge);
  }
};

}  // namespace

EnergyTermPtr makeHingeBendingTerm(const TriMesh& mesh, const Topology& topology, double stiffness) {
  HingeLayout h = hingeLayout(mesh, topology);
  HingeBendingEnergy energy{StageCache<HingeFaceNormal>({}, mesh.numFaces()), restDensity(mesh, h, stiffness),
                            std::move(h.faces), std::move(h.corners)};
  return std::make_shared<StagedEnergyTerm<HingeBendingEnergy>>("hinge_bending", std::move(h.table),
                                                                mesh.numVertices(), std::move(energy));
}

EnergyTermPtr makeHingeBendingNestedJet(const TriMesh& mesh, const Topology& topology, double stiffness) {
  HingeLayout h = hingeLayout(mesh, topology);
  HingeNestedEnergy energy{restDensity(mesh, h, stiffness), std::move(h.corners)};
  return std::make_shared<ElementEnergyTerm<HingeNestedEnergy>>("hinge_bending_nested_jet", std::move(h.table),
                                                                mesh.numVertices(), std::move(energy));
}

}  // namespace jetshell
