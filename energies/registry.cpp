#include "energies/registry.h"

#include "energies/contact/contact_registry.h"
#include "energies/examples/seam_spring.h"
#include "energies/shell/shell_terms.h"

#include <cmath>

namespace jetshell {
namespace {

EvalOptions gaussNewton() {
  EvalOptions o;
  o.bendingHessian = BendingHessian::GaussNewton;
  return o;
}

/// Bending with the first boundary edge clamped (its missing neighbour's normal is the reference normal).
EnergyTermPtr makeClampedBending(const TermSetup& s) {
  auto term = std::make_shared<BendingTerm>(s.mesh, s.topology, s.reference, s.material.bendingAlpha,
                                            s.material.bendingBeta);
  std::vector<char> mask(static_cast<std::size_t>(s.mesh.numVertices()), 0);
  for (int e = 0; e < s.topology.numEdges(); ++e) {
    if (!s.topology.isBoundaryEdge(e)) continue;
    mask[s.topology.edges(e, 0)] = mask[s.topology.edges(e, 1)] = 1;
    break;
  }
  term->setClampedBoundary(mask);
  term->setName("bending_clamped");
  return term;
}

/// A fixed, non-uniform nodal load.
Eigen::VectorXd sampleForces(int numVertices) {
  Eigen::VectorXd f(3 * numVertices);
  for (int i = 0; i < f.size(); ++i) f[i] = std::sin(1.0 + 0.7 * i);
  return f;
}

std::vector<std::array<int, 2>> edgePairs(const Topology& t) {
  std::vector<std::array<int, 2>> pairs;
  for (int e = 0; e < t.numEdges(); ++e) pairs.push_back({t.edges(e, 0), t.edges(e, 1)});
  return pairs;
}

std::vector<RegisteredTerm> buildRegistry() {
  using S = const TermSetup&;
  return {
      {"membrane", "StVK membrane (staged AD + analytic)",
       [](S s) { return makeMembraneTerm(s.mesh, s.reference, s.material.membraneLambda, s.material.membraneMu); }},
      {"bending", "StVK bending, Kelvin-inverted mid-edge normals, exact Hessian (staged AD + analytic)",
       [](S s) {
         return makeBendingTerm(s.mesh, s.topology, s.reference, s.material.bendingAlpha, s.material.bendingBeta);
       }},
      {"bending_gauss_newton", "bending with the Gauss-Newton Hessian J_b^T W'' J_b (a model: checked PSD)",
       [](S s) {
         return makeBendingTerm(s.mesh, s.topology, s.reference, s.material.bendingAlpha, s.material.bendingBeta);
       },
       gaussNewton(), false},
      {"bending_clamped", "bending with one clamped boundary edge", makeClampedBending},
      {"bending_nested_jet", "bending as one 18-dof nested-Jet element (the naive reference)",
       [](S s) {
         return makeBendingTermNestedJet(s.mesh, s.topology, s.reference, s.material.bendingAlpha,
                                         s.material.bendingBeta);
       }},
      {"gravity", "gravity on the lumped mass",
       [](S s) {
         return makeGravityTerm(lumpedMass(s.mesh, s.reference, s.material.density), Eigen::Vector3d(0, 0, -9.81));
       }},
      {"nodal_forces", "external nodal forces",
       [](S s) { return EnergyTermPtr(makeNodalForceTerm(sampleForces(s.mesh.numVertices()))); }},
      // Example of a term written without hand derivatives, registered in one line (energies/examples/).
      {"seam_spring", "edge springs", [](S s) { return makeSeamSpringTerm(s.mesh, edgePairs(s.topology), 10.0); }},
  };
}

}  // namespace

const std::vector<RegisteredTerm>& termRegistry() {
  static const std::vector<RegisteredTerm> registry = [] {
    std::vector<RegisteredTerm> r = buildRegistry();
    for (RegisteredTerm& t : contactRegistryEntries()) r.push_back(std::move(t));
    return r;
  }();
  return registry;
}

const RegisteredTerm* findRegisteredTerm(const std::string& name) {
  for (const RegisteredTerm& t : termRegistry())
    if (t.name == name) return &t;
  return nullptr;
}

std::vector<std::string> registeredTermNames() {
  std::vector<std::string> names;
  for (const RegisteredTerm& t : termRegistry()) names.push_back(t.name);
  return names;
}

}  // namespace jetshell
