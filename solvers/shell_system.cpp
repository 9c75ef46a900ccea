#include "solvers/shell_system.h"

#include <cmath>
#include <sstream>

namespace jetshell {

const char* toString(AnalysisKind k) {
  switch (k) {
    case AnalysisKind::Statics: return "statics";
    case AnalysisKind::Dynamics: return "dynamics";
    case AnalysisKind::DynamicRelaxation: return "dynamic_relaxation";
  }
  return "?";
}

namespace {

double meanEdgeLength(const TriMesh& mesh, const Topology& topo) {
  double sum = 0.0;
  for (int e = 0; e < topo.numEdges(); ++e)
    sum += (mesh.V.row(topo.edges(e, 0)) - mesh.V.row(topo.edges(e, 1))).norm();
  return topo.numEdges() > 0 ? sum / topo.numEdges() : 1.0;
}

}  // namespace

ShellSystem::ShellSystem(const ShellProblem& p, AnalysisKind kind)
    : kind_(kind),
      mesh_(p.mesh),
      topology_(buildTopology(p.mesh)),
      reference_(computeReference(p.mesh, topology_)),
      material_(p.material),
      objective_(p.mesh.numVertices()) {
  validate(material_, "material");
  const int n = mesh_.numVertices();
  if (!p.gravity.allFinite()) throw InputError("gravity: must be finite");
  if (p.nodalForces.size() != 0 && p.nodalForces.size() != 3 * n) {
    std::ostringstream s;
    s << "nodalForces: size " << p.nodalForces.size() << ", expected 3 × " << n << " vertices";
    throw InputError(s.str());
  }
  if (p.nodalForces.size() != 0 && !p.nodalForces.allFinite()) throw InputError("nodalForces: must be finite");
  if (!p.clampedVertices.empty() && static_cast<int>(p.clampedVertices.size()) != n)
    throw InputError("clampedVertices: size must equal the number of vertices");

  vertexMass_ = lumpedMass(mesh_, reference_, material_.density);
  const ShellMaterialParams& m = material_;
  const bool dynamic = kind != AnalysisKind::Statics;

  if (m.membraneLambda != 0.0 || m.membraneMu != 0.0) {
    membrane = std::make_shared<MembraneTerm>(mesh_, reference_, m.membraneLambda, m.membraneMu);
    objective_.addTerm(membrane);
  }
  if (m.bendingAlpha != 0.0 || m.bendingBeta != 0.0) {
    bending = std::make_shared<BendingTerm>(mesh_, topology_, reference_, m.bendingAlpha, m.bendingBeta);
    if (!p.clampedVertices.empty()) bending->setClampedBoundary(p.clampedVertices);
    objective_.addTerm(bending);
  }
  const bool gravityActive = p.hasGravity && p.gravity.squaredNorm() > 0.0 && m.density > 0.0;
  if (gravityActive) objective_.addTerm(makeGravityTerm(vertexMass_, p.gravity, m.density));
  if (p.nodalForces.size() != 0 && p.nodalForces.cwiseAbs().maxCoeff() > 0.0) {
    nodalForces = makeNodalForceTerm(p.nodalForces);
    objective_.addTerm(nodalForces);
  }
  if (dynamic && m.density > 0.0) {
    inertia = makeInertiaTerm(vertexMass_, m.density);
    objective_.addTerm(inertia, TermRole::Transient);
  }
  if ((kind == AnalysisKind::Dynamics && m.massDampingCoefficient > 0.0 && m.density > 0.0) ||
      (kind == AnalysisKind::DynamicRelaxation && m.density > 0.0)) {
    massDamping = makeMassDampingTerm(vertexMass_, m.massDampingCoefficient > 0.0 ? m.massDampingCoefficient : 1.0);
    objective_.addTerm(massDamping, TermRole::Transient);
  }
  if (kind == AnalysisKind::Dynamics && m.stiffnessDampingCoefficient > 0.0) {
    stiffnessDamping = makeStiffnessDampingTerms(mesh_, topology_, reference_, m);
    if (stiffnessDamping.membrane) objective_.addTerm(stiffnessDamping.membrane, TermRole::Transient);
    if (stiffnessDamping.bending) {
      if (!p.clampedVertices.empty()) stiffnessDamping.bending->setClampedBoundary(p.clampedVertices);
      objective_.addTerm(stiffnessDamping.bending, TermRole::Transient);
    }
  }
  // Not finalized here: callers may still add terms (contact, user energies) before the first evaluation.
  objective_.setPrescribed(p.prescribed);

  PhysicalScales scales;
  scales.length = meanEdgeLength(mesh_, topology_);
  for (int v = 0; v < n; ++v) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    if (gravityActive) f += vertexMass_[v] * p.gravity;
    if (nodalForces) f += p.nodalForces.segment<3>(3 * v);
    scales.force = std::max(scales.force, f.norm());
  }
  scales.stiffness = std::max(m.membraneLambda + 2.0 * m.membraneMu,
                              (m.bendingAlpha + m.bendingBeta) / (scales.length * scales.length));
  scales.reference = restPositions();
  objective_.setScales(scales);
}

}  // namespace jetshell
