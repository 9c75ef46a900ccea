#include "solvers/shell_system.h"

#include "core/vertex_block_term.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

PathClock pathClock(AnalysisKind k) {
  switch (k) {
    case AnalysisKind::Statics: return PathClock::LoadFactor;
    case AnalysisKind::Dynamics: return PathClock::Time;
    case AnalysisKind::DynamicRelaxation: return PathClock::Held;
  }
  return PathClock::Held;
}

std::vector<char> momentLoadedVertices(const ShellProblem& problem) {
  std::vector<char> loaded;
  for (const EndMomentLoad& m : problem.endMoments)
    for (int v : m.chain) {
      if (v < 0 || v >= problem.mesh.numVertices()) continue;  // the system refuses such a chain
      if (loaded.empty()) loaded.assign(static_cast<std::size_t>(problem.mesh.numVertices()), 0);
      loaded[static_cast<std::size_t>(v)] = 1;
    }
  return loaded;
}

std::vector<char> vertexBlock(const std::vector<char>& mask, int first, int count) {
  if (mask.empty()) return {};
  if (first < 0 || count < 0 || static_cast<std::size_t>(first) + static_cast<std::size_t>(count) > mask.size())
    throw InputError("vertex mask of size " + std::to_string(mask.size()) + ": no block of " + std::to_string(count) +
                     " vertices from " + std::to_string(first));
  const std::vector<char> block(mask.begin() + first, mask.begin() + first + count);
  return std::find(block.begin(), block.end(), 1) == block.end() ? std::vector<char>{} : block;
}

namespace {

/// The actors to build: the problem's, or one made of its mesh and material.
std::vector<ShellActorPart> actorsOf(const ShellProblem& p) {
  if (!p.actors.empty()) return p.actors;
  ShellActorPart a;
  a.mesh = p.mesh;
  a.material = p.material;
  a.hasGravity = p.hasGravity;
  a.clampedVertices = p.clampedVertices;
  a.pointCloud = false;  // a plain problem has no shell-shell contact
  return {a};
}

/// An actor's vertices and faces are the stacked mesh's next block: the `covered` vertices and `faces` faces
/// before it belong to the actors before it.
void checkActorBlock(const ShellActorPart& a, const TriMesh& stacked, int covered, int faces) {
  const std::string actor = "actor '" + a.name + "'";
  const int na = a.mesh.numVertices(), nf = a.mesh.numFaces();
  if (a.firstVertex != covered)
    throw InputError(actor + ": firstVertex = " + std::to_string(a.firstVertex) + "; the actors' vertices follow one "
                     "another in the stacked mesh, so this one starts at " + std::to_string(covered));
  if (na > stacked.numVertices() - covered || nf > stacked.numFaces() - faces)
    throw InputError(actor + ": " + std::to_string(na) + " vertices and " + std::to_string(nf) + " faces from vertex " +
                     std::to_string(covered) + " and face " + std::to_string(faces) + " go past the stacked mesh");
  if (a.mesh.V != stacked.V.middleRows(covered, na))
    throw InputError(actor + ": its reference positions are not the stacked mesh's rows " + std::to_string(covered) +
                     " to " + std::to_string(covered + na - 1));
  if ((a.mesh.F.array() + covered).matrix() != stacked.F.middleRows(faces, nf))
    throw InputError(actor + ": its faces, shifted by its first vertex " + std::to_string(covered) +
                     ", are not the stacked mesh's faces " + std::to_string(faces) + " to " +
                     std::to_string(faces + nf - 1));
  if (!a.clampedVertices.empty() && static_cast<int>(a.clampedVertices.size()) != na)
    throw InputError(actor + ": clampedVertices size must equal the actor's vertices (" + std::to_string(na) + ")");
}

bool sameMaterial(const ShellMaterialParams& a, const ShellMaterialParams& b) {
  return a.membraneLambda == b.membraneLambda && a.membraneMu == b.membraneMu && a.bendingAlpha == b.bendingAlpha &&
         a.bendingBeta == b.bendingBeta && a.density == b.density &&
         a.massDampingCoefficient == b.massDampingCoefficient &&
         a.stiffnessDampingCoefficient == b.stiffnessDampingCoefficient;
}

/// The material the solvers read for scalars: the first actor's, with the largest α_R.
ShellMaterialParams leadMaterial(const ShellProblem& p) {
  if (p.actors.empty()) return p.material;
  ShellMaterialParams m = p.actors.front().material;
  for (const ShellActorPart& a : p.actors) {
    m.massDampingCoefficient = std::max(m.massDampingCoefficient, a.material.massDampingCoefficient);
    if (a.material.stiffnessDampingCoefficient != m.stiffnessDampingCoefficient)
      throw InputError("actor '" + a.name + "': stiffnessDampingCoefficient differs from '" + p.actors.front().name +
                       "''s; one β_R for all actors is supported");
  }
  return m;
}

}  // namespace

ShellSystem::ShellSystem(const ShellProblem& p, AnalysisKind kind)
    : kind_(kind),
      mesh_(p.mesh),
      topology_(buildTopology(p.mesh)),
      reference_(computeReference(p.mesh, topology_)),
      material_(leadMaterial(p)),
      objective_(p.mesh.numVertices()) {
  validate(material_, "material");
  const int n = mesh_.numVertices();
  if (const int v = firstVertexWithoutFace(mesh_); v >= 0)
    throw InputError("mesh: vertex " + std::to_string(v) + " belongs to no face (a shell vertex without a face has no "
                     "stiffness and no mass)");
  if (!p.gravity.allFinite()) throw InputError("gravity: must be finite");
  if (p.nodalForces.size() != 0 && p.nodalForces.size() != 3 * n) {
    std::ostringstream s;
    s << "nodalForces: size " << p.nodalForces.size() << ", expected 3 × " << n << " vertices";
    throw InputError(s.str());
  }
  if (p.nodalForces.size() != 0 && !p.nodalForces.allFinite()) throw InputError("nodalForces: must be finite");
  if (!p.clampedVertices.empty() && static_cast<int>(p.clampedVertices.size()) != n)
    throw InputError("clampedVertices: size must equal the number of vertices");

  const std::vector<ShellActorPart> actors = actorsOf(p);
  std::vector<Topology> actorTopology;
  std::vector<ShellReference> actorReference;
  bool uniform = true;
  int faces = 0, covered = 0;
  for (const ShellActorPart& a : actors) {
    const std::string actor = "actor '" + a.name + "'";
    validate(a.material, a.name.empty() ? std::string("material") : actor + ".material");
    checkActorBlock(a, mesh_, covered, faces);
    uniform = uniform && sameMaterial(a.material, actors.front().material);
    covered += a.mesh.numVertices();
    faces += a.mesh.numFaces();
    actorTopology.push_back(p.actors.empty() ? topology_ : buildTopology(a.mesh));
    actorReference.push_back(p.actors.empty() ? reference_ : computeReference(a.mesh, actorTopology.back()));
  }
  if (covered != n || faces != mesh_.numFaces())
    throw InputError("actors: they hold " + std::to_string(covered) + " vertices and " + std::to_string(faces) +
                     " faces; the stacked mesh has " + std::to_string(n) + " and " +
                     std::to_string(mesh_.numFaces()));
  actorMeshes_.reserve(actors.size());
  for (const ShellActorPart& a : actors) actorMeshes_.push_back(a.mesh);

  const bool dynamic = kind != AnalysisKind::Statics;
  vertexMass_ = Eigen::VectorXd::Zero(n);
  membraneWaveRate_ = Eigen::VectorXd::Zero(n);
  edgeOverThickness_ = Eigen::VectorXd::Zero(n);
  for (std::size_t i = 0; i < actors.size(); ++i) {
    const ShellMaterialParams& m = actors[i].material;
    const double edge = meanEdgeLength(actors[i].mesh, actorTopology[i]);
    const double plane = m.membraneLambda + 2.0 * m.membraneMu;  // > 0 (validate)
    const double rate = m.density > 0.0 && edge > 0.0 ? std::sqrt(plane / m.density) / edge
                                                      : std::numeric_limits<double>::infinity();
    const double thickness = std::sqrt(12.0 * (m.bendingAlpha + m.bendingBeta) / plane);
    membraneWaveRate_.segment(actors[i].firstVertex, actors[i].mesh.numVertices()).setConstant(rate);
    edgeOverThickness_.segment(actors[i].firstVertex, actors[i].mesh.numVertices()).setConstant(edge / thickness);
  }
  Eigen::VectorXd gravityMass = Eigen::VectorXd::Zero(n), dampedMass = Eigen::VectorXd::Zero(n);
  for (std::size_t i = 0; i < actors.size(); ++i) {
    const Eigen::VectorXd m = lumpedMass(actors[i].mesh, actorReference[i], actors[i].material.density);
    const int first = actors[i].firstVertex, na = actors[i].mesh.numVertices();
    vertexMass_.segment(first, na) += m;
    if (actors[i].hasGravity) gravityMass.segment(first, na) += m;
    if (material_.massDampingCoefficient > 0.0) {
      const double share = actors[i].material.massDampingCoefficient / material_.massDampingCoefficient;
      dampedMass.segment(first, na) += share * m;
    }
  }
  std::vector<char> clamped;
  for (const ShellActorPart& a : actors) {
    if (a.clampedVertices.empty()) continue;
    if (clamped.empty()) clamped.assign(static_cast<std::size_t>(n), 0);
    for (std::size_t v = 0; v < a.clampedVertices.size(); ++v)
      clamped[static_cast<std::size_t>(a.firstVertex) + v] |= a.clampedVertices[v];
  }

  // Elastic terms: one set over the whole mesh when the actors agree, else one per actor on its own vertices,
  // placed in the objective by a VertexBlockTerm.
  const std::size_t sets = uniform ? 1 : actors.size();
  for (std::size_t i = 0; i < sets; ++i) {
    const ShellMaterialParams& m = actors[i].material;
    const TriMesh& mesh = uniform ? mesh_ : actorMeshes_[i];
    const Topology& topo = uniform ? topology_ : actorTopology[i];
    const ShellReference& ref = uniform ? reference_ : actorReference[i];
    const std::string suffix = uniform ? "" : "/" + actors[i].name;
    const int first = uniform ? 0 : actors[i].firstVertex;
    auto place = [&](const EnergyTermPtr& t) -> EnergyTermPtr {
      return uniform ? t : std::make_shared<VertexBlockTerm>(t, first, mesh.numVertices());
    };
    if (m.membraneLambda != 0.0 || m.membraneMu != 0.0) {
      auto t = std::make_shared<MembraneTerm>(mesh, ref, m.membraneLambda, m.membraneMu);
      if (!uniform) t->setName("membrane" + suffix);
      objective_.addTerm(place(t));
      if (!membrane) membrane = t;
      membraneTerms.push_back(t);
    }
    if (m.bendingAlpha != 0.0 || m.bendingBeta != 0.0) {
      auto t = std::make_shared<BendingTerm>(mesh, topo, ref, m.bendingAlpha, m.bendingBeta);
      const std::vector<char> clampedHere = uniform ? clamped : vertexBlock(clamped, first, mesh.numVertices());
      if (!clampedHere.empty()) t->setClampedBoundary(clampedHere);
      if (!uniform) t->setName("bending" + suffix);
      objective_.addTerm(place(t));
      if (!bending) bending = t;
      bendingTerms.push_back(t);
      bendingBlocks.push_back({&mesh, first});
    }
  }
  const bool gravityActive = p.gravity.squaredNorm() > 0.0 && gravityMass.maxCoeff() > 0.0;
  // Masses are given at the lead material's density (the gravity term's differentiable parameter).
  if (gravityActive) {
    gravity = makeGravityTerm(gravityMass, p.gravity, material_.density > 0.0 ? material_.density : 1.0);
    objective_.addTerm(gravity);
  }
  if (p.nodalForces.size() != 0 && p.nodalForces.cwiseAbs().maxCoeff() > 0.0) {
    nodalForces = makeNodalForceTerm(p.nodalForces);
    objective_.addTerm(nodalForces);
  }
  double momentForce = 0.0;  // the force scale of the end moments (below)
  if (!p.endMoments.empty() && kind != AnalysisKind::Statics)
    throw InputError(p.endMoments.front().where + ": an end moment needs a static analysis (its rotation is "
                     "unwrapped from one load step to the next), not " + toString(kind));
  for (std::size_t k = 0; k < p.endMoments.size(); ++k) {
    const EndMomentLoad& m = p.endMoments[k];
    if (!std::isfinite(m.moment)) throw InputError(m.where + "/moment: must be finite");
    if (!m.axis.allFinite()) throw InputError(m.where + "/axis: must be finite");
    std::shared_ptr<EndMomentTerm> t;
    try {
      const std::string name = k == 0 ? "end_moment" : "end_moment/" + std::to_string(k);
      t = makeEndMomentTerm(mesh_, topology_, m.chain, m.axis, m.moment, name);
    } catch (const InputError& e) {
      throw InputError(m.where + ": " + e.what());
    }
    objective_.addTerm(t);
    endMoments.push_back(t);
    // Newton's tolerances need a force: the couple of nodal forces that carries one segment's share of the
    // moment across one element.
    momentForce = std::max(momentForce, std::abs(m.moment) / static_cast<double>(m.chain.size() - 1));
  }
  const bool massive = vertexMass_.maxCoeff() > 0.0;
  if (dynamic && massive) {
    inertia = makeInertiaTerm(vertexMass_, material_.density > 0.0 ? material_.density : 1.0);
    objective_.addTerm(inertia, TermRole::Transient);
  }
  if (kind == AnalysisKind::Dynamics && material_.massDampingCoefficient > 0.0 && massive) {
    massDamping = makeMassDampingTerm(dampedMass, material_.massDampingCoefficient);
    objective_.addTerm(massDamping, TermRole::Transient);
  } else if (kind == AnalysisKind::DynamicRelaxation && massive) {
    massDamping = makeMassDampingTerm(vertexMass_, material_.massDampingCoefficient > 0.0 ? material_.massDampingCoefficient : 1.0);
    objective_.addTerm(massDamping, TermRole::Transient);
  }
  if (kind == AnalysisKind::Dynamics && material_.stiffnessDampingCoefficient > 0.0) {
    if (!uniform) throw InputError("actors: stiffness damping with different materials per actor is not supported");
    stiffnessDamping = makeStiffnessDampingTerms(mesh_, topology_, reference_, material_);
    if (stiffnessDamping.membrane) {
      objective_.addTerm(stiffnessDamping.membrane, TermRole::Transient);
      membraneTerms.push_back(stiffnessDamping.membrane);
    }
    if (stiffnessDamping.bending) {
      if (!clamped.empty()) stiffnessDamping.bending->setClampedBoundary(clamped);
      objective_.addTerm(stiffnessDamping.bending, TermRole::Transient);
      bendingTerms.push_back(stiffnessDamping.bending);
      bendingBlocks.push_back({&mesh_, 0});
    }
  }

  // Contact: only when there is something to collide with.
  std::vector<ShellContactActor> contactActors;
  for (std::size_t i = 0; i < actors.size(); ++i) {
    ShellContactActor c;
    c.name = actors[i].name.empty() ? "shell" : actors[i].name;
    c.mesh = &actorMeshes_[i];
    c.firstVertex = actors[i].firstVertex;
    c.faceArea = actorReference[i].area;
    c.contact = actors[i].contact;
    c.quadrature = actors[i].contactQuadrature;
    c.pointCloud = actors[i].pointCloud;
    c.pointCloudCollider = actors[i].pointCloudCollider;
    contactActors.push_back(std::move(c));
  }
  // Each volume actor on its path as this kind of analysis reads it: a static path moves it along its keyframes
  // with the load factor (loadFactorHooks in solvers/statics.h sets the contact's time to λ), a relaxation holds it.
  std::vector<VolumeColliderPart> volumes = p.volumes;
  if (kind != AnalysisKind::Dynamics)
    for (VolumeColliderPart& v : volumes)
      if (!v.collider->path().isStatic()) v.collider = v.collider->readBy(pathClock(kind));
  contact = addShellContact(objective_, contactActors, volumes, mesh_.V, dynamic);

  // Not finalized here: callers may still add terms (user energies) before the first evaluation.
  objective_.setPrescribed(p.prescribed);

  PhysicalScales scales;
  const double meanEdge = meanEdgeLength(mesh_, topology_);
  scales.length = meanEdge > 0.0 ? meanEdge : 1.0;  // 1 m for a mesh without edges
  scales.force = momentForce / scales.length;
  for (int v = 0; v < n; ++v) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    if (gravityActive) f += gravityMass[v] * p.gravity;
    if (nodalForces) f += p.nodalForces.segment<3>(3 * v);
    scales.force = std::max(scales.force, f.norm());
  }
  for (const ShellActorPart& a : actors) {
    const ShellMaterialParams& m = a.material;
    scales.stiffness = std::max({scales.stiffness, m.membraneLambda + 2.0 * m.membraneMu,
                                 (m.bendingAlpha + m.bendingBeta) / (scales.length * scales.length)});
  }
  scales.reference = restPositions();
  objective_.setScales(scales);
}

}  // namespace jetshell
