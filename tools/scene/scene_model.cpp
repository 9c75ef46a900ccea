#include "tools/scene/scene_model.h"

#include "tools/scene/contact_at_start.h"
#include "tools/scene/contact_coverage.h"
#include "tools/scene/inside_solids.h"
#include "tools/scene/open_seams.h"
#include "tools/scene/sliver_faces.h"

#include "core/input_limits.h"
#include "core/topology.h"
#include "tools/scene/shapes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <map>
#include <sstream>
#include <unordered_set>

namespace jetshell {

Positions worldPositions(const ShellActorParams& actor) {
  const Positions& X = actor.shape->mesh.V;
  Positions W(X.rows(), 3);
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    W.row(v) = actor.worldFromLocalTransform.apply(Eigen::Vector3d(X.row(v))).transpose();
  return W;
}

namespace {

std::vector<char> boundaryVertices(const TriMesh& mesh, const Topology& t) {
  std::vector<char> b(static_cast<std::size_t>(mesh.numVertices()), 0);
  for (int e = 0; e < t.numEdges(); ++e)
    if (t.isBoundaryEdge(e)) b[static_cast<std::size_t>(t.edges(e, 0))] = b[static_cast<std::size_t>(t.edges(e, 1))] = 1;
  return b;
}

/// What selection needs about one actor, in its local numbering.
struct ActorGeometry {
  Positions world;
  std::vector<char> boundary;
  Topology topology;  // local ids
};

/// Per-vertex weights (local ids) of a total force for the chosen distribution.
std::vector<double> loadWeights(const LoadCondition& load, const std::vector<int>& ids, const ActorGeometry& g,
                                const TriMesh& local) {
  using D = LoadCondition::Distribution;
  std::vector<double> w(ids.size(), 1.0);
  if (load.distribution == D::Uniform || load.distribution == D::PerVertex) return w;
  std::map<int, std::size_t> slot;
  for (std::size_t k = 0; k < ids.size(); ++k) slot[ids[k]] = k;
  std::fill(w.begin(), w.end(), 0.0);
  if (load.distribution == D::EdgeLength) {
    // Consistent nodal forces of a uniform line load: each vertex gets half of each adjacent loaded segment.
    for (int e = 0; e < g.topology.numEdges(); ++e) {
      if (!g.topology.isBoundaryEdge(e)) continue;
      const auto a = slot.find(g.topology.edges(e, 0)), b = slot.find(g.topology.edges(e, 1));
      if (a == slot.end() || b == slot.end()) continue;
      const double length = (g.world.row(a->first) - g.world.row(b->first)).norm();
      w[a->second] += 0.5 * length;
      w[b->second] += 0.5 * length;
    }
    double total = 0;
    for (double x : w) total += x;
    if (total == 0.0)
      throw InputError(load.where + "/distribution = \"edgeLength\": no boundary edge joins two selected vertices "
                                    "(select a line of boundary vertices)");
    return w;
  }
  for (int f = 0; f < local.numFaces(); ++f) {  // Area: lumped, a third of each face to each corner
    const Eigen::Vector3d x0 = g.world.row(local.F(f, 0)), x1 = g.world.row(local.F(f, 1)), x2 = g.world.row(local.F(f, 2));
    const double third = (x1 - x0).cross(x2 - x0).norm() / 6.0;
    for (int c = 0; c < 3; ++c) {
      const auto it = slot.find(local.F(f, c));
      if (it != slot.end()) w[it->second] += third;
    }
  }
  return w;
}

/// The selected vertices (local ids) in order along the one open chain of boundary edges that joins them, from
/// the end with the smaller id. InputError naming `where` when they are not such a chain.
std::vector<int> boundaryChain(const std::vector<int>& ids, const Topology& topo, const std::string& where) {
  std::map<int, std::vector<int>> next;  // selected vertex -> its selected neighbours along boundary edges
  for (int v : ids) next[v];
  for (int e = 0; e < topo.numEdges(); ++e) {
    if (!topo.isBoundaryEdge(e)) continue;
    const auto a = next.find(topo.edges(e, 0)), b = next.find(topo.edges(e, 1));
    if (a == next.end() || b == next.end()) continue;
    a->second.push_back(b->first);
    b->second.push_back(a->first);
  }
  const std::string rule = ": a moment load's vertices must form one open chain of boundary edges (an edge of the "
                           "shell, from one end to the other)";
  int start = -1;
  for (const auto& [v, n] : next) {
    if (n.empty())
      throw InputError(where + rule + "; vertex " + std::to_string(v) + " is on no boundary edge to another");
    if (n.size() > 2) throw InputError(where + rule + "; vertex " + std::to_string(v) + " joins three or more");
    if (n.size() == 1 && start < 0) start = v;
  }
  if (start < 0) throw InputError(where + rule + "; these close a loop");
  std::vector<int> chain{start};
  for (int previous = -1, v = start;;) {
    const std::vector<int>& n = next.at(v);
    const int following = n[0] != previous ? n[0] : n.size() > 1 ? n[1] : -1;
    if (following < 0) break;
    previous = v;
    v = following;
    chain.push_back(v);
  }
  if (chain.size() != next.size())
    throw InputError(where + rule + "; they form separate pieces (" + std::to_string(chain.size()) + " of " +
                     std::to_string(next.size()) + " vertices are joined to the first end)");
  return chain;
}

}  // namespace

SceneModel buildSceneModel(const Scene& scene) {
  validate(scene);
  SceneModel model;
  std::vector<ActorGeometry> geometry;
  int numVertices = 0, numFaces = 0;
  for (const ShellActorParams& a : scene.shells) {
    numVertices += a.shape->mesh.numVertices();
    numFaces += a.shape->mesh.numFaces();
  }
  model.world.V.resize(numVertices, 3);
  model.world.F.resize(numFaces, 3);
  int v0 = 0, f0 = 0;
  for (const ShellActorParams& a : scene.shells) {
    const TriMesh& local = a.shape->mesh;
    ActorGeometry g;
    g.world = worldPositions(a);
    g.topology = buildTopology(local);
    g.boundary = boundaryVertices(local, g.topology);
    ActorBlock block;
    block.firstVertex = v0;
    block.numVertices = local.numVertices();
    block.firstFace = f0;
    block.numFaces = local.numFaces();
    block.mesh.V = g.world;
    block.mesh.F = local.F;
    block.topology = g.topology;
    model.world.V.middleRows(v0, local.numVertices()) = g.world;
    model.world.F.middleRows(f0, local.numFaces()) = local.F.array() + v0;
    model.actors.push_back(std::move(block));
    geometry.push_back(std::move(g));
    v0 += local.numVertices();
    f0 += local.numFaces();
  }
  // Meshes read from a file or given as arrays that are cut where they may be meant to be joined (the generators'
  // slits are meant); a shape several actors share is named once.
  std::unordered_set<const TriangularMeshShape*> judged;
  for (std::size_t a = 0; a < scene.shells.size(); ++a) {
    const ShellActorParams& actor = scene.shells[a];
    if (!judged.insert(actor.shape.get()).second || actor.shape->source.rfind("generator", 0) == 0) continue;
    const OpenSeams seams = findOpenSeams(actor.shape->mesh, geometry[a].topology);
    if (seams.vertices == 0) continue;
    const std::array<int, 2>& first = seams.pairs.front();
    const Eigen::IOFormat inRow(Eigen::StreamPrecision, Eigen::DontAlignCols, ", ", ", ");
    std::ostringstream m;
    m << "shell actor '" << actor.name << "': " << (seams.partial ? "at least " : "") << seams.vertices
      << " vertices of its mesh (" << actor.shape->source << ") lie on others with no edge between them (within "
      << seams.tolerance << " m, a thousandth of the mean edge), first vertices " << first[0] << " and " << first[1]
      << " (counted from 0) at (" << geometry[a].world.row(first[0]).format(inRow)
      << "): the mesh is cut there, and its sides move apart (\"weld\": true in the shape joins them; a slit is "
         "meant so)";
    model.warnings.push_back(m.str());
  }
  const double meanEdge = meanEdgeLength(model.world, buildTopology(model.world));
  auto select = [&](int actor, const VertexSelection& s, const std::string& where) {
    const ShellActorParams& a = scene.shells[static_cast<std::size_t>(actor)];
    const ActorGeometry& g = geometry[static_cast<std::size_t>(actor)];
    std::vector<int> ids = selectVertices(s, SelectionContext{&g.world, a.shape.get(), &g.boundary}, where);
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (!s[k].nearest) continue;
      double closest = std::numeric_limits<double>::infinity();
      for (int v : ids) closest = std::min(closest, (g.world.row(v).transpose() - *s[k].nearest).norm());
      if (closest > meanEdge) {
        std::ostringstream m;
        m << where << (s.size() > 1 ? "/" + std::to_string(k) : std::string()) << "/nearest: the vertex picked is "
          << closest << " m from the point (the mean edge is " << meanEdge << " m)";
        model.warnings.push_back(m.str());
      }
    }
    return ids;
  };

  std::int64_t selected = 0;  // by fixed conditions and loads together (each vertex costs a map entry or a force)
  auto count = [&](const std::vector<int>& ids, const std::string& where) {
    selected += static_cast<std::int64_t>(ids.size());
    if (selected > inputLimits().maxSelectedVertices)
      throw InputError(where + ": the scene's fixed conditions and loads select more than " +
                       std::to_string(inputLimits().maxSelectedVertices) + " vertices in all");
  };
  model.appliedForces = Eigen::VectorXd::Zero(3 * numVertices);
  for (const LoadCondition& load : scene.loads) {
    const std::vector<int> ids = select(load.actor, load.select, load.where + "/select");
    count(ids, load.where + "/select");
    const std::vector<double> w =
        loadWeights(load, ids, geometry[static_cast<std::size_t>(load.actor)], scene.shells[static_cast<std::size_t>(load.actor)].shape->mesh);
    double total = 0;
    for (double x : w) total += x;
    const int offset = model.actors[static_cast<std::size_t>(load.actor)].firstVertex;
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const double share = load.distribution == LoadCondition::Distribution::PerVertex ? 1.0 : w[k] / total;
      model.appliedForces.segment<3>(3 * (offset + ids[k])) += share * load.force;
    }
  }

  for (const MomentLoad& m : scene.moments) {
    const std::vector<int> ids = select(m.actor, m.select, m.where + "/select");
    EndMomentLoad e;
    e.chain = boundaryChain(ids, geometry[static_cast<std::size_t>(m.actor)].topology, m.where + "/select");
    for (int& v : e.chain) v += model.actors[static_cast<std::size_t>(m.actor)].firstVertex;
    e.axis = m.axis;
    e.moment = m.moment;
    e.where = m.where;
    model.endMoments.push_back(std::move(e));
  }

  const AnalysisSettings& analysis = scene.analysis;
  const bool statics = analysis.type == AnalysisType::Static;
  const double ramp = analysis.loadRampTime;
  model.loadFactorAtTime = [ramp](double t) { return ramp > 0 ? std::min(1.0, std::max(0.0, t / ramp)) : 1.0; };
  std::map<std::pair<int, int>, PrescribedCoordinate> prescribed;  // later conditions replace earlier ones
  for (const FixedCondition& c : scene.fixed) {
    const std::vector<int> ids = select(c.actor, c.select, c.where + "/select");
    count(ids, c.where + "/select");
    const ActorBlock& block = model.actors[static_cast<std::size_t>(c.actor)];
    const bool moving = c.displacement.norm() > 0 || (!statics && c.velocity.norm() > 0) ||
                        (c.rotation && c.rotation->radians != 0.0);
    const auto loadFactor = model.loadFactorAtTime;
    for (int local : ids) {
      const int v = block.firstVertex + local;
      const Eigen::Vector3d X = model.world.V.row(v);
      // Position of this vertex at s (λ in statics, t in dynamics).
      std::function<Eigen::Vector3d(double)> position;
      if (moving) {
        const FixedCondition cond = c;
        position = [cond, X, statics, loadFactor](double s) {
          const double lambda = statics ? s : loadFactor(s);
          Eigen::Vector3d x = X;
          if (cond.rotation) {
            const Eigen::AngleAxisd R(lambda * cond.rotation->radians, cond.rotation->axis.normalized());
            x = cond.rotation->center + R * (x - cond.rotation->center);
          }
          x += lambda * cond.displacement;
          if (!statics) x += s * cond.velocity;
          return x;
        };
      }
      for (int comp = 0; comp < 3; ++comp) {
        if (!c.components[static_cast<std::size_t>(comp)]) continue;
        PrescribedCoordinate p;
        p.vertex = v;
        p.component = comp;
        p.constant = X[comp];
        if (position) p.value = [position, comp](double s) { return position(s)[comp]; };
        prescribed[{v, comp}] = std::move(p);
      }
    }
    if (c.clampRotation) {
      ActorBlock& b = model.actors[static_cast<std::size_t>(c.actor)];
      if (b.clampedVertices.empty()) b.clampedVertices.assign(static_cast<std::size_t>(b.numVertices), 0);
      for (int local : ids) b.clampedVertices[static_cast<std::size_t>(local)] = 1;
    }
  }
  for (auto& entry : prescribed) model.prescribed.push_back(std::move(entry.second));

  for (const Probe& p : scene.probes) {
    const std::vector<int> ids = select(p.actor, p.select, p.where + "/select");
    if (ids.size() != 1)
      throw InputError(p.where + "/select: picks " + std::to_string(ids.size()) +
                       " vertices; a probe needs exactly one (add \"nearest\": [x, y, z])");
    const int vertex = model.actors[static_cast<std::size_t>(p.actor)].firstVertex + ids[0];
    model.probes.push_back({p.name, p.actor, vertex, model.world.V.row(vertex).transpose()});
  }
  for (std::string& w : contactCoverageWarnings(scene, model.actors)) model.warnings.push_back(std::move(w));
  for (std::string& w : contactAtStartWarnings(scene, model.actors)) model.warnings.push_back(std::move(w));
  for (std::string& w : insideSolidWarnings(scene, model.actors)) model.warnings.push_back(std::move(w));
  for (std::string& w : sliverFaceWarnings(scene, model.actors)) model.warnings.push_back(std::move(w));
  return model;
}

}  // namespace jetshell
