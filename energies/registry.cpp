#include "energies/registry.h"

#include "energies/contact/contact_registry.h"
#include "energies/end_moment_term.h"
#include "energies/examples/hinge_bending.h"
#include "energies/examples/seam_spring.h"
#include "energies/kinetic_terms.h"
#include "energies/shell/shell_terms.h"

#include <cmath>

namespace jetshell {
namespace {

EvalOptions gaussNewton() {
  EvalOptions o;
  o.hessianModel = HessianModel::GaussNewton;
  return o;
}

/// The endpoints of the first boundary edge.
std::vector<char> firstBoundaryEdgeMask(const TermSetup& s) {
  std::vector<char> mask(static_cast<std::size_t>(s.mesh.numVertices()), 0);
  for (int e = 0; e < s.topology.numEdges(); ++e) {
    if (!s.topology.isBoundaryEdge(e)) continue;
    mask[s.topology.edges(e, 0)] = mask[s.topology.edges(e, 1)] = 1;
    break;
  }
  return mask;
}

/// Bending, named `name`.
std::shared_ptr<BendingTerm> makeNamedBending(const TermSetup& s, const char* name) {
  auto term = std::make_shared<BendingTerm>(s.mesh, s.topology, s.reference, s.material.bendingAlpha,
                                            s.material.bendingBeta);
  term->setName(name);
  return term;
}

/// Membrane (on the stage framework when staged), named `name`.
std::shared_ptr<MembraneTerm> makeNamedMembrane(const TermSetup& s, const char* name, bool staged = false) {
  auto term = std::make_shared<MembraneTerm>(s.mesh, s.reference, s.material.membraneLambda, s.material.membraneMu);
  term->setStaged(staged);
  term->setName(name);
  return term;
}

/// Bending with every boundary edge moment-free (second_order_free): faces with one and with two minimized edges.
EnergyTermPtr makeSecondOrderFreeBending(const TermSetup& s, const char* name) {
  auto term = makeNamedBending(s, name);
  term->setEdgeRule(std::vector<char>(static_cast<std::size_t>(s.mesh.numVertices()), 1), EdgeRule::SecondOrderFree);
  return term;
}

/// Bending with the first boundary edge under `rule` (energies/shell/edge_rules.h), the others free.
EnergyTermPtr makeRuledBending(const TermSetup& s, EdgeRule rule, const char* name) {
  auto term = makeNamedBending(s, name);
  term->setEdgeRule(firstBoundaryEdgeMask(s), rule);
  return term;
}

/// Bending with the first boundary edge on a symmetry plane through it, whose normal is tilted by 0.2 rad out of
/// the face's plane towards its reference normal (so the rule's rest origin differs from the page's).
EnergyTermPtr makeSymmetryPlaneBending(const TermSetup& s, const char* name) {
  auto term = makeNamedBending(s, name);
  for (int e = 0; e < s.topology.numEdges(); ++e) {
    if (!s.topology.isBoundaryEdge(e)) continue;
    const int f = s.topology.edgeFaces(e, 0);
    const Eigen::Vector3d x0 = s.mesh.V.row(s.mesh.F(f, 0));
    const Eigen::Vector3d r = (Eigen::Vector3d(s.mesh.V.row(s.mesh.F(f, 1))) - x0)
                                  .cross(Eigen::Vector3d(s.mesh.V.row(s.mesh.F(f, 2))) - x0)
                                  .normalized();
    const int a = s.topology.edges(e, 0), b = s.topology.edges(e, 1);
    const Eigen::Vector3d t = (s.mesh.V.row(b) - s.mesh.V.row(a)).transpose().normalized();
    term->setEdgeRule(firstBoundaryEdgeMask(s), EdgeRule::SymmetryPlane,
                      std::cos(0.2) * t.cross(r) + std::sin(0.2) * r);
    break;
  }
  return term;
}

/// A fixed, smooth displacement of the rest positions (centres and origins of the transient terms).
Eigen::VectorXd displacedRest(const TriMesh& mesh, double amplitude) {
  Eigen::VectorXd x = flatten(mesh.V);
  for (int i = 0; i < x.size(); ++i) x[i] += amplitude * std::cos(0.3 + 1.1 * i);
  return x;
}

/// The stiffness-damping terms with their origin moved to a displaced configuration (β_R = 0.05 s, Δt = 0.01 s).
StiffnessDampingTerms dampingTerms(const TermSetup& s, bool staged = false) {
  ShellMaterialParams m = s.material;
  m.stiffnessDampingCoefficient = 0.05;
  StiffnessDampingTerms t = makeStiffnessDampingTerms(s.mesh, s.topology, s.reference, m);
  if (staged) {
    t.membrane->setStaged(true);
    t.membrane->setName("membrane_staged_damping");
  }
  const Eigen::VectorXd origin = displacedRest(s.mesh, 0.02);
  t.membrane->setStrainOrigin(origin, 0.05 / 0.01);
  t.bending->setCurvatureOrigin(origin, 0.05 / 0.01);
  return t;
}

/// The end moment on the first boundary edge, about its own direction.
EnergyTermPtr makeSampleEndMoment(const TermSetup& s) {
  for (int e = 0; e < s.topology.numEdges(); ++e) {
    if (!s.topology.isBoundaryEdge(e)) continue;
    const int a = s.topology.edges(e, 0), b = s.topology.edges(e, 1);
    const Eigen::Vector3d axis = s.mesh.V.row(b) - s.mesh.V.row(a);
    auto term = makeEndMomentTerm(s.mesh, {a, b}, axis, 1.3);
    term->setLoadFactor(0.8);
    return term;
  }
  throw InputError("end moment: the mesh has no boundary edge");
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
      {"bending", "StVK bending, Kelvin-inverted mid-edge normals, exact Hessian (stage graph, AD + analytic)",
       [](S s) {
         return makeBendingTerm(s.mesh, s.topology, s.reference, s.material.bendingAlpha, s.material.bendingBeta);
       }},
      {"bending_gauss_newton", "bending with the Gauss-Newton Hessian J_b^T W'' J_b (a model: checked PSD)",
       [](S s) {
         return makeBendingTerm(s.mesh, s.topology, s.reference, s.material.bendingAlpha, s.material.bendingBeta);
       },
       gaussNewton(), false},
      {"bending_clamped", "bending with one boundary edge under the reference_clamp rule (ghost normal = r)",
       [](S s) { return makeRuledBending(s, EdgeRule::ReferenceClamp, "bending_clamped"); }},
      {"bending_mirrored_clamp", "bending with one boundary edge under the mirrored_clamp rule (2(n.r)r - n)",
       [](S s) { return makeRuledBending(s, EdgeRule::MirroredClamp, "bending_mirrored_clamp"); }},
      {"bending_clamped_gauss_newton", "clamped bending with the Gauss-Newton Hessian (a model: checked PSD)",
       [](S s) { return makeRuledBending(s, EdgeRule::MirroredClamp, "bending_clamped_gauss_newton"); },
       gaussNewton(), false},
      {"bending_second_order_free",
       "bending with every boundary edge second_order_free (its mid-edge normal minimized out: no moment)",
       [](S s) { return makeSecondOrderFreeBending(s, "bending_second_order_free"); }},
      {"bending_second_order_free_gauss_newton",
       "second_order_free bending with the Gauss-Newton Hessian (a model: checked PSD)",
       [](S s) { return makeSecondOrderFreeBending(s, "bending_second_order_free_gauss_newton"); }, gaussNewton(),
       false},
      {"bending_symmetry_plane", "bending with one boundary edge under the symmetry_plane rule (n - 2(n.p)p)",
       [](S s) { return makeSymmetryPlaneBending(s, "bending_symmetry_plane"); }},
      {"bending_symmetry_plane_gauss_newton",
       "symmetry_plane bending with the Gauss-Newton Hessian (a model: checked PSD)",
       [](S s) { return makeSymmetryPlaneBending(s, "bending_symmetry_plane_gauss_newton"); }, gaussNewton(), false},
      {"bending_nested_jet", "bending as one 18-dof nested-Jet element (the naive reference)",
       [](S s) {
         return makeBendingTermNestedJet(s.mesh, s.topology, s.reference, s.material.bendingAlpha,
                                         s.material.bendingBeta);
       }},
      {"gravity", "gravity on the lumped mass",
       [](S s) {
         return makeGravityTerm(lumpedMass(s.mesh, s.reference, s.material.density), Eigen::Vector3d(0, 0, -9.81),
                                s.material.density);
       }},
      {"nodal_forces", "external nodal forces",
       [](S s) { return EnergyTermPtr(makeNodalForceTerm(sampleForces(s.mesh.numVertices()))); }},
      {"inertia", "lumped inertia 1/2 c sum m |x - x~|^2 (c = 1/dt^2, dt = 0.1 s)",
       [](S s) {
         auto t = makeInertiaTerm(lumpedMass(s.mesh, s.reference, s.material.density), s.material.density);
         t->setCentre(displacedRest(s.mesh, 0.05), 100.0);
         return EnergyTermPtr(t);
       }},
      {"mass_damping", "mass damping 1/2 c sum m |x - x_prev|^2 (c = alpha_R/dt, alpha_R = 0.5/s, dt = 0.1 s)",
       [](S s) {
         auto t = makeMassDampingTerm(lumpedMass(s.mesh, s.reference, s.material.density), 0.5);
         t->setCentre(displacedRest(s.mesh, 0.03), 5.0);
         return EnergyTermPtr(t);
       }},
      {"membrane_damping", "membrane stiffness damping (origin x_prev, scale beta_R/dt)",
       [](S s) { return EnergyTermPtr(dampingTerms(s).membrane); }},
      {"bending_damping", "bending stiffness damping (origin x_prev, scale beta_R/dt)",
       [](S s) { return EnergyTermPtr(dampingTerms(s).bending); }},
      // The membrane on its stage graph (MembraneTerm::setStaged), also with the moved origin of stiffness damping
      // (the bending term above is always one: every edge rule, both Hessians).
      {"membrane_staged", "membrane on the stage framework (metric, density)",
       [](S s) { return EnergyTermPtr(makeNamedMembrane(s, "membrane_staged", true)); }},
      {"membrane_staged_damping", "staged membrane stiffness damping (origin x_prev, scale beta_R/dt)",
       [](S s) { return EnergyTermPtr(dampingTerms(s, true).membrane); }},
      {"end_moment", "end moment -lambda M theta on a boundary edge (no hand derivatives)", makeSampleEndMoment},
      // Example of a term written without hand derivatives, registered in one line (energies/examples/).
      {"seam_spring", "edge springs", [](S s) { return makeSeamSpringTerm(s.mesh, edgePairs(s.topology), 10.0); }},
      // A term on stages (core/stage_graph.h), no derivatives written: energies/examples/hinge_bending.h.
      {"hinge_bending", "discrete-shells hinge bending, tan-based, on stages (face normal cached per face)",
       [](S s) { return makeHingeBendingTerm(s.mesh, s.topology, 0.7); }, {}, true, true},
      {"hinge_bending_gauss_newton", "hinge bending with the Gauss-Newton Hessian (a model: checked PSD)",
       [](S s) { return makeHingeBendingTerm(s.mesh, s.topology, 0.7); }, gaussNewton(), false, true},
      {"hinge_bending_nested_jet", "hinge bending as one 12-dof nested-Jet element (the naive reference)",
       [](S s) { return makeHingeBendingNestedJet(s.mesh, s.topology, 0.7); }, {}, true, true},
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
