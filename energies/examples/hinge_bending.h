// Example: a term on stages with no derivatives written: discrete-shells hinge bending (Grinspun et al. 2003)
// with the tan-based angle function of Tamstorf and Grinspun 2013,
//   E = Σ_hinges k · 3ℓ̄²/(Ā_A + Ā_B) · (2 tan(θ/2) − 2 tan(θ̄/2))²,
// θ the signed dihedral angle across an interior edge, tan(θ/2) = ((n_A × n_B)·ê) / (1 + n_A·n_B).
// Three stages, written once for any scalar type: the unit normal of a face (6 → 3, one node per face shared
// by the face's three hinges), tan(θ/2) (9 → 1) and the energy (1 → 1), each written as plain Eigen math with
// plain double constants (core/jet_arithmetic.h makes that work for every Jet type), and the graph that
// connects them (core/stage_graph.h). The framework differentiates each stage with Jets of its own size and
// chains them; the stages, the graph and hingeGraph() in hinge_bending.cpp are the whole user-side code.
// makeHingeBendingNestedJet builds the same energy as one 12-dof nested-Jet element (the naive reference for
// `jetshell bench elements --term hinge` and the checks).
#pragma once

#include "core/mesh.h"
#include "core/stage_graph.h"
#include "core/term.h"
#include "core/topology.h"

#include <Eigen/Geometry>

#include <array>
#include <vector>

namespace jetshell {

// ---- the user's term: stages and how they connect -------------------------------------------------------
/// Unit normal of a face from its edge vectors e0 = x1 − x0, e1 = x2 − x0 (the face's own vertex order).
struct HingeFaceNormal {
  static constexpr int kInputs = 6, kOutputs = 3;
  template <typename T> void operator()(const T* z, T* n, int /*face*/) const {
    vec3(n) = vec3(z).cross(vec3(z + 3)).normalized();
  }
};
struct HingeTanHalf {  // tan(θ/2) of the hinge from the two face normals and the edge vector
  static constexpr int kInputs = 9, kOutputs = 1;
  template <typename T> void operator()(const T* z, T* t, int /*hinge*/) const {
    const auto nA = vec3(z), nB = vec3(z + 3), e = vec3(z + 6);
    t[0] = nA.cross(nB).dot(e) / (e.norm() * (1.0 + nA.dot(nB)));
  }
};
/// The energy: a square of tan(θ/2), so the Gauss–Newton model (this stage's curvature only) is PSD.
struct HingeEnergyDensity {
  static constexpr int kInputs = 1, kOutputs = 1;
  std::vector<double> weight, restTan;  // per hinge: k·3ℓ̄²/(Ā_A + Ā_B), tan(θ̄/2)
  template <typename T> void operator()(const T* t, T* energy, int hinge) const {
    const T d = 2.0 * (t[0] - restTan[hinge]);
    energy[0] = weight[hinge] * d * d;
  }
};
/// The graph: a normal per face; per hinge (the edge (0, 1), the opposite vertices of face A (2) and B (3))
/// tan(θ/2) from the two faces' normals and the edge, then the energy.
using HingeGraph = StageGraph<4, Shared<HingeFaceNormal, 3, Difference, Difference>,
                              Local<HingeTanHalf, From<0>, From<0>, Difference>, Local<HingeEnergyDensity, From<1>>>;
// ----------------------------------------------------------------------------------------------------------

/// Hinge bending with stiffness k on every interior edge of the mesh, rest angles from the mesh's positions.
EnergyTermPtr makeHingeBendingTerm(const TriMesh& mesh, const Topology& topology, double stiffness);

/// The same energy as one 12-dof element differentiated with nested Jets (the naive reference).
EnergyTermPtr makeHingeBendingNestedJet(const TriMesh& mesh, const Topology& topology, double stiffness);

}  // namespace jetshell
