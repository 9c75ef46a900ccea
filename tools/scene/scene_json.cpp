#include "tools/scene/scene_json.h"

#include "core/math_constants.h"
#include "energies/contact/contact_params.h"
#include "energies/contact/sdf_grid.h"
#include "solvers/newton.h"
#include "tools/scene/checks.h"
#include "tools/scene/generated_shapes.h"
#include "tools/scene/json_reader.h"

#include "core/input_file.h"
#include "core/input_limits.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

#include <filesystem>
#include <sstream>

namespace jetshell {
namespace {

using json::Object;
using json::Value;

/// Runs f and prefixes any InputError it throws with `pointer` (generator and mesh errors do not know it).
template <typename F>
auto at(const std::string& pointer, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(pointer + ": " + e.what());
  }
}

double positive(const Object& o, const std::string& key) {
  const double v = o.at(key).number();
  check::positive(v, o.member(key));
  return v;
}

/// A point's position [m] (zero when absent): finite, and at most the bound on distances from the origin.
Eigen::Vector3d position(const Object& o, const std::string& key) {
  const Eigen::Vector3d v = o.vec3(key, Eigen::Vector3d::Zero());
  check::normAtMost(v, inputLimits().maxDistance, o.member(key));
  return v;
}

/// A generator's length [m]: positive, and at most the bound on distances.
double length(const Object& o, const std::string& key) {
  const double v = positive(o, key);
  check::atMostReal(v, inputLimits().maxDistance, o.member(key));
  return v;
}

/// A file's or arrays' "scale": the factor to metres (0.001 for millimetres), in [1e-6, 1e6].
double meshScale(const Object& o) {
  const double s = o.number("scale", 1.0);
  if (!(s >= 1e-6 && s <= 1e6)) check::fail(o.member("scale"), s, "must lie in [1e-06, 1e+06] (the factor to metres)");
  return s;
}

/// A required resolution count: at least `minimum`, at most the vertex limit (the generator bounds the product).
int atLeast(const Object& o, const std::string& key, int minimum) {
  return o.at(key).integer(minimum, static_cast<int>(inputLimits().maxVertices));
}

QuadDiagonals diagonals(const Object& generator) {
  return quadDiagonalsFromString(generator.choice("diagonals", {"alternating", "uniform"}, "uniform"));
}

ShapeHandle readShape(const Value& v, const std::string& baseDirectory) {
  if (!v.isObject()) v.typeError("an object (a shape: {\"obj\": path}, {\"generator\": ...} or {\"vertices\", \"faces\"})");
  const nlohmann::json& j = v.raw();
  if (j.contains("obj")) {
    const Object o = v.object({"obj", "scale", "weld"}, "an OBJ shape");
    std::filesystem::path path = o.at("obj").string();
    if (path.is_relative()) path = std::filesystem::path(baseDirectory) / path;
    const double scale = meshScale(o);
    const ShapeHandle shape =
        at(o.member("obj"), [&] { return CreateTriMeshShape(path.lexically_normal().string(), scale); });
    return o.boolean("weld", false) ? at(o.member("weld"), [&] { return WeldOpenSeams(shape); }) : shape;
  }
  if (j.contains("vertices") || j.contains("faces")) {
    const Object o = v.object({"vertices", "faces", "scale", "weld"}, "a shape given by arrays");
    const double scale = meshScale(o);
    const std::vector<Value> rows = o.at("vertices").array(), faces = o.at("faces").array();
    check::atMost(static_cast<std::int64_t>(rows.size()), inputLimits().maxVertices, o.member("vertices") + " (count)");
    check::atMost(static_cast<std::int64_t>(faces.size()), inputLimits().maxFaces, o.member("faces") + " (count)");
    Positions V(static_cast<Eigen::Index>(rows.size()), 3);
    for (std::size_t k = 0; k < rows.size(); ++k) V.row(static_cast<Eigen::Index>(k)) = rows[k].vec3().transpose();
    Faces F(static_cast<Eigen::Index>(faces.size()), 3);
    for (std::size_t k = 0; k < faces.size(); ++k) {
      const std::vector<Value> corners = faces[k].array();
      if (corners.size() != 3) faces[k].typeError("an array of 3 vertex indices");
      for (int c = 0; c < 3; ++c) F(static_cast<Eigen::Index>(k), c) = corners[static_cast<std::size_t>(c)].integer();
    }
    const ShapeHandle shape = at(v.pointer(), [&] { return CreateTriMeshShape(scale * V, F); });
    return o.boolean("weld", false) ? at(o.member("weld"), [&] { return WeldOpenSeams(shape); }) : shape;
  }
  if (!j.contains("generator"))
    v.error("missing \"obj\", \"generator\" or \"vertices\"/\"faces\" (a shell needs a triangle mesh)");
  const std::string generator =
      Object(v).choice("generator", {"rectangle", "slitAnnulus", "cylinder", "hemisphere", "tshirt"}, "");
  if (generator == "tshirt") {
    const Object o = v.object({"generator", "resolution", "gap"}, "a tshirt generator");
    const int resolution = atLeast(o, "resolution", 1);
    if (resolution > 40) check::fail(o.member("resolution"), resolution, "must be <= 40");
    const double gap = o.number("gap", 0.03);
    check::nonNegative(gap, o.member("gap"));
    return at(v.pointer(), [&] { return makeTShirtShape(resolution, gap); });
  }
  if (generator == "rectangle") {
    const Object o = v.object({"generator", "width", "height", "nx", "ny", "diagonals"}, "a rectangle generator");
    const double w = length(o, "width"), h = length(o, "height");
    const int nx = atLeast(o, "nx", 1), ny = atLeast(o, "ny", 1);
    const QuadDiagonals split = diagonals(o);
    return at(v.pointer(), [&] { return makeRectangleShape(w, h, nx, ny, split); });
  }
  if (generator == "slitAnnulus") {
    const Object o =
        v.object({"generator", "innerRadius", "outerRadius", "rings", "nodesPerRing", "diagonals", "ringSpacing"},
                 "a slitAnnulus generator");
    const double ri = length(o, "innerRadius"), ro = length(o, "outerRadius");
    if (!(ro > ri)) check::fail(o.member("outerRadius"), ro, "must be > innerRadius");
    const int rings = atLeast(o, "rings", 2), nodes = atLeast(o, "nodesPerRing", 4);
    const RingSpacing spacing = ringSpacingFromString(o.choice("ringSpacing", {"uniform", "cosine"}, "uniform"));
    const QuadDiagonals split = diagonals(o);
    return at(v.pointer(), [&] { return makeSlitAnnulusShape(ri, ro, rings, nodes, split, spacing); });
  }
  if (generator == "cylinder") {
    const Object o = v.object({"generator", "radius", "length", "arcDegrees", "nAround", "nAlong", "diagonals"},
                              "a cylinder generator");
    const double r = length(o, "radius"), along = length(o, "length");
    const double arc = o.number("arcDegrees", 360.0);
    if (!(arc > 0 && arc <= 360)) check::fail(o.member("arcDegrees"), arc, "must lie in (0, 360]");
    const int nAround = atLeast(o, "nAround", arc == 360.0 ? 3 : 1), nAlong = atLeast(o, "nAlong", 1);
    const QuadDiagonals split = diagonals(o);
    return at(v.pointer(),
              [&] { return makeCylinderShape(r, along, arc * kRadiansPerDegree, nAround, nAlong, split); });
  }
  const Object o = v.object({"generator", "radius", "rings", "segments", "holeDegrees", "azimuthDegrees", "diagonals"},
                            "a hemisphere generator");
  const double r = length(o, "radius");
  const int rings = atLeast(o, "rings", 1);
  const double hole = o.number("holeDegrees", 0.0), azimuth = o.number("azimuthDegrees", 360.0);
  if (!(hole >= 0 && hole < 90)) check::fail(o.member("holeDegrees"), hole, "must lie in [0, 90)");
  if (!(azimuth > 0 && azimuth <= 360)) check::fail(o.member("azimuthDegrees"), azimuth, "must lie in (0, 360]");
  const int segments = atLeast(o, "segments", azimuth == 360.0 ? 3 : 1);
  const QuadDiagonals split = diagonals(o);
  return at(v.pointer(), [&] {
    return makeHemisphereShape(r, rings, segments, hole * kRadiansPerDegree, azimuth * kRadiansPerDegree, split);
  });
}

Eigen::Quaterniond readRotation(const Value& v) {
  const Object o = v.object({"axis", "degrees"}, "a rotation");
  const Eigen::Vector3d axis = check::unitDirection(o.at("axis").vec3(), o.member("axis"));
  const double degrees = o.at("degrees").number();
  check::finite(degrees, o.member("degrees"));
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * kRadiansPerDegree, axis));
}

RigidTransform readTransform(const Value& v) {
  const Object o = v.object({"translation", "rotation"}, "a rigid transform");
  RigidTransform t;
  t.translation = o.vec3("translation", Eigen::Vector3d::Zero());
  if (const auto r = o.find("rotation")) t.rotation = readRotation(*r);
  return t;
}

ShellMaterialParams readMaterial(const Value& v) {
  static const std::vector<std::string> lame = {"membraneLambda", "membraneMu", "bendingAlpha", "bendingBeta", "density"};
  static const std::vector<std::string> iso = {"youngsModulus", "poissonRatio", "thickness", "volumeDensity"};
  std::vector<std::string> allowed = lame;
  allowed.insert(allowed.end(), iso.begin(), iso.end());
  allowed.insert(allowed.end(), {"massDampingCoefficient", "stiffnessDampingCoefficient"});
  const Object o = v.object(allowed, "a shell material");
  std::string firstLame, firstIso;
  for (const std::string& k : lame)
    if (firstLame.empty() && o.has(k)) firstLame = k;
  for (const std::string& k : iso)
    if (firstIso.empty() && o.has(k)) firstIso = k;
  if (!firstLame.empty() && !firstIso.empty())
    throw InputError(o.member(firstLame) + ": cannot be combined with \"" + firstIso +
                     "\" (give either membraneLambda, membraneMu, bendingAlpha, bendingBeta, density, or "
                     "youngsModulus, poissonRatio, thickness, volumeDensity)");
  ShellMaterialParams m;
  if (!firstIso.empty()) {
    const double E = o.at("youngsModulus").number();
    check::positive(E, o.member("youngsModulus"));
    const double nu = o.at("poissonRatio").number();
    if (!(nu > -1.0 && nu < 0.5)) check::fail(o.member("poissonRatio"), nu, "must lie in (-1, 0.5)");
    const double h = o.at("thickness").number();
    check::positive(h, o.member("thickness"));
    const double rho0 = o.at("volumeDensity").number();
    check::nonNegative(rho0, o.member("volumeDensity"));
    m = ShellMaterialParamsFrom3dIsotropic(E, nu, rho0, h, o.pointer());  // E, ν, h checked above, E·h³ there
  } else {
    m.membraneLambda = o.number("membraneLambda", m.membraneLambda);
    check::finite(m.membraneLambda, o.member("membraneLambda"));
    m.membraneMu = o.number("membraneMu", m.membraneMu);
    check::positive(m.membraneMu, o.member("membraneMu"));
    m.bendingAlpha = o.number("bendingAlpha", m.bendingAlpha);
    check::finite(m.bendingAlpha, o.member("bendingAlpha"));
    m.bendingBeta = o.number("bendingBeta", m.bendingBeta);
    check::positive(m.bendingBeta, o.member("bendingBeta"));
    m.density = o.number("density", m.density);
    check::nonNegative(m.density, o.member("density"));
  }
  m.massDampingCoefficient = o.number("massDampingCoefficient", 0.0);
  check::nonNegative(m.massDampingCoefficient, o.member("massDampingCoefficient"));
  m.stiffnessDampingCoefficient = o.number("stiffnessDampingCoefficient", 0.0);
  check::nonNegative(m.stiffnessDampingCoefficient, o.member("stiffnessDampingCoefficient"));
  at(o.pointer(), [&] { validate(m, "material"); });  // the combined rules (λ + μ > 0, 2α + β > 0)
  return m;
}

ContactParams readContact(const Value& v) {
  const Object o = v.object({"penaltyStiffness", "activationDistance", "smoothingDistance", "huntCrossleyDamping",
                             "frictionCoefficient", "frictionSlipVelocity"},
                            "contact parameters");
  ContactParams c;
  auto read = [&](const char* key, double& field, bool strictlyPositive) {
    field = o.number(key, field);
    if (strictlyPositive) check::positive(field, o.member(key));
    else check::nonNegative(field, o.member(key));
  };
  read("penaltyStiffness", c.penaltyStiffness, false);
  read("activationDistance", c.activationDistance, false);
  read("smoothingDistance", c.smoothingDistance, true);
  read("huntCrossleyDamping", c.huntCrossleyDamping, false);
  read("frictionCoefficient", c.frictionCoefficient, false);
  read("frictionSlipVelocity", c.frictionSlipVelocity, true);
  return c;
}

PointCloudColliderParams readPointCloud(const Value& v) {
  const Object o = v.object({"radius", "selfContact", "selfContactExclusionRatio"}, "point-cloud collider parameters");
  PointCloudColliderParams p;
  p.radius = o.number("radius", p.radius);
  check::positive(p.radius, o.member("radius"));
  if (p.radius < kMinPointCloudRadius)
    check::fail(o.member("radius"), p.radius, "too small (at least 1e-6 m: the broad phase's cells are this wide)");
  p.selfContact = o.boolean("selfContact", p.selfContact);
  p.selfContactExclusionRatio = o.number("selfContactExclusionRatio", p.selfContactExclusionRatio);
  check::nonNegative(p.selfContactExclusionRatio, o.member("selfContactExclusionRatio"));
  return p;
}

VertexSelector readSelector(const Value& v) {
  const Object o = v.object({"all", "indices", "range", "group", "box", "plane", "boundary", "nearest"},
                            "a vertex selector");
  VertexSelector s;
  s.all = o.boolean("all", false);
  if (o.has("indices") && o.has("range"))
    throw InputError(o.member("range") + ": cannot be combined with \"indices\" (use one)");
  if (const auto list = o.find("indices")) {
    s.indices.emplace();
    const std::vector<Value> entries = list->array();
    check::atMost(static_cast<std::int64_t>(entries.size()), inputLimits().maxVertices, list->pointer() + " (count)");
    for (const Value& e : entries) s.indices->push_back(e.integer());
    if (s.indices->empty()) list->error("selects nothing (an empty list)");
  }
  if (const auto r = o.find("range")) {
    const std::vector<Value> parts = r->array();
    if (parts.size() != 2 && parts.size() != 3) r->typeError("[start, stop] or [start, stop, step]");
    // Bounded before anything is filled in: stop <= the vertex limit, and the loop runs in 64 bits.
    const int maxIndex = static_cast<int>(inputLimits().maxVertices);
    const int start = parts[0].integer(0, maxIndex), stop = parts[1].integer(0, maxIndex);
    const int step = parts.size() == 3 ? parts[2].integer(1, std::numeric_limits<int>::max()) : 1;
    if (stop <= start) check::fail(parts[1].pointer(), stop, "must be > start (stop is exclusive)");
    s.indices.emplace();
    for (std::int64_t k = start; k < stop; k += step) s.indices->push_back(static_cast<int>(k));
  }
  if (const auto g = o.find("group")) s.group = g->string();
  if (const auto b = o.find("box")) {
    const Object box = b->object({"min", "max"}, "a box selector");
    s.box = VertexSelector::Box{box.at("min").vec3(), box.at("max").vec3()};
  }
  if (const auto p = o.find("plane")) {
    const Object plane = p->object({"point", "normal", "distance"}, "a plane selector");
    s.plane = VertexSelector::PlaneBand{plane.at("point").vec3(), plane.at("normal").vec3(),
                                        plane.at("distance").number()};
  }
  s.boundaryOnly = o.boolean("boundary", false);
  if (const auto n = o.find("nearest")) s.nearest = n->vec3();
  validate(s, v.pointer());
  return s;
}

VertexSelection readSelection(const Value& v) {
  VertexSelection selection;
  if (v.isArray()) {
    for (const Value& e : v.array()) selection.push_back(readSelector(e));
    if (selection.empty()) v.error("selects nothing (an empty list)");
  } else if (v.isObject()) {
    selection.push_back(readSelector(v));
  } else {
    v.typeError("a selector object or an array of them");
  }
  return selection;
}

void readFixed(const Value& v, int actor, Scene& scene) {
  const Object o = v.object({"select", "components", "displacement", "velocity", "rotation", "clampRotation"},
                            "a fixed condition");
  FixedCondition c;
  c.actor = actor;
  c.where = v.pointer();
  check::atMost(static_cast<std::int64_t>(scene.fixed.size()) + 1, inputLimits().maxConditions,
                c.where + ": fixed conditions in the scene");
  c.select = readSelection(o.at("select"));
  if (const auto comp = o.find("components")) {
    const std::string s = comp->string();
    c.components = {false, false, false};
    for (char ch : s) {
      if (ch < 'x' || ch > 'z') comp->error("\"" + s + "\" must be made of the letters x, y, z");
      c.components[static_cast<std::size_t>(ch - 'x')] = true;
    }
    if (s.empty()) comp->error("fixes no component (use some of \"x\", \"y\", \"z\")");
  }
  c.displacement = o.vec3("displacement", Eigen::Vector3d::Zero());
  c.velocity = o.vec3("velocity", Eigen::Vector3d::Zero());
  if (const auto r = o.find("rotation")) {
    const Object rot = r->object({"axis", "center", "degrees"}, "a prescribed rotation");
    FixedCondition::Rotation R;
    R.axis = rot.at("axis").vec3();
    check::nonZero(R.axis, rot.member("axis"));
    R.center = rot.vec3("center", Eigen::Vector3d::Zero());
    R.radians = rot.at("degrees").number() * kRadiansPerDegree;
    check::finite(R.radians, rot.member("degrees"));
    c.rotation = R;
  }
  c.clampRotation = o.boolean("clampRotation", false);
  scene.fixed.push_back(std::move(c));
}

void readMoment(const Value& v, const Object& o, int actor, Scene& scene) {
  for (const char* key : {"force", "distribution", "name"})
    if (o.has(key))
      throw InputError(o.member(key) + ": a moment load takes \"select\", \"moment\" and \"axis\" only (a force is "
                       "a separate load)");
  MomentLoad m;
  m.actor = actor;
  m.where = v.pointer();
  m.select = readSelection(o.at("select"));
  m.moment = o.at("moment").number();
  check::finite(m.moment, o.member("moment"));
  m.axis = o.at("axis").vec3();
  check::nonZero(m.axis, o.member("axis"));
  check::atMost(static_cast<std::int64_t>(scene.moments.size()) + 1, inputLimits().maxEndMoments,
                m.where + ": moment loads in the scene");
  scene.moments.push_back(std::move(m));
}

void readLoad(const Value& v, int actor, Scene& scene) {
  const Object o = v.object({"name", "select", "force", "distribution", "moment", "axis"}, "a load");
  if (o.has("moment")) return readMoment(v, o, actor, scene);
  if (o.has("axis")) throw InputError(o.member("axis") + ": only a moment load has an axis");
  LoadCondition l;
  l.actor = actor;
  l.where = v.pointer();
  check::atMost(static_cast<std::int64_t>(scene.loads.size()) + 1, inputLimits().maxConditions,
                l.where + ": loads in the scene");
  l.name = o.string("name", "");
  if (o.has("name") && l.name.empty()) throw InputError(o.member("name") + ": must not be empty");
  for (const LoadCondition& q : scene.loads)
    if (!l.name.empty() && q.name == l.name)
      throw InputError(o.member("name") + " = \"" + l.name + "\": duplicate load name");
  l.select = readSelection(o.at("select"));
  l.force = o.at("force").vec3();
  const std::string d = o.choice("distribution", {"uniform", "edgeLength", "area", "perVertex"}, "uniform");
  using D = LoadCondition::Distribution;
  l.distribution = d == "uniform" ? D::Uniform : d == "edgeLength" ? D::EdgeLength : d == "area" ? D::Area : D::PerVertex;
  scene.loads.push_back(std::move(l));
}

void readProbe(const Value& v, int actor, Scene& scene) {
  const Object o = v.object({"name", "select"}, "a probe");
  Probe p;
  p.actor = actor;
  p.where = v.pointer();
  check::atMost(static_cast<std::int64_t>(scene.probes.size()) + 1, inputLimits().maxConditions,
                p.where + ": probes in the scene");
  p.name = o.at("name").string();
  if (p.name.empty()) throw InputError(o.member("name") + ": must not be empty");
  for (const Probe& q : scene.probes)
    if (q.name == p.name) throw InputError(o.member("name") + " = \"" + p.name + "\": duplicate probe name");
  p.select = readSelection(o.at("select"));
  scene.probes.push_back(std::move(p));
}

template <typename F>
void forEach(const Object& o, const std::string& key, F&& f) {
  if (const auto list = o.find(key))
    for (const Value& e : list->array()) f(e);
}

void readShell(const Value& v, Scene& scene, const std::string& baseDirectory) {
  const Object o = v.object({"type", "name", "layer", "shape", "worldFromLocalTransform", "material", "colliderType",
                             "contact", "pointCloudCollider", "hasGravity", "contactElementType", "fixed", "loads",
                             "probes"},
                            "a shell actor");
  ShellActorParams p;
  p.name = o.string("name", "");
  p.layer = o.string("layer", "");
  p.shape = readShape(o.at("shape"), baseDirectory);
  if (const auto t = o.find("worldFromLocalTransform")) p.worldFromLocalTransform = readTransform(*t);
  if (const auto m = o.find("material")) p.material = readMaterial(*m);
  p.colliderType = o.choice("colliderType", {"PointCloud", "None"}, "PointCloud") == "None" ? ColliderType::None
                                                                                          : ColliderType::PointCloud;
  if (const auto c = o.find("contact")) p.contact = readContact(*c);
  if (const auto c = o.find("pointCloudCollider")) p.pointCloudCollider = readPointCloud(*c);
  p.hasGravity = o.boolean("hasGravity", true);
  const std::string element =
      o.choice("contactElementType", {"Default", "Vertices", "FaceCentroids", "FaceThreePoint"}, "Default");
  using B = ActorBoundaryElementType;
  p.contactElementType = element == "Vertices" ? B::Vertices
                         : element == "FaceCentroids" ? B::FaceCentroids
                         : element == "FaceThreePoint" ? B::FaceThreePoint
                                                       : B::Default;
  const int actor = at(v.pointer(), [&] { return scene.addShellActor(std::move(p)); });
  forEach(o, "fixed", [&](const Value& e) { readFixed(e, actor, scene); });
  forEach(o, "loads", [&](const Value& e) { readLoad(e, actor, scene); });
  forEach(o, "probes", [&](const Value& e) { readProbe(e, actor, scene); });
}

/// A volume actor's keyframes: [{"time": t, "translation": [x, y, z], "rotation": {"axis", "degrees"}}, ...],
/// times increasing from after 0, each pose the placement moved and turned (energies/contact/rigid_path.h). At most
/// `room` of them (what the scene's bound leaves).
std::vector<RigidKeyframe> readKeyframes(const Value& v, std::int64_t room) {
  if (!v.isArray()) v.typeError("an array of keyframes");
  if (static_cast<std::int64_t>(v.raw().size()) > room)
    v.error(std::to_string(v.raw().size()) + " keyframes: too many (at most " + std::to_string(room) +
            " for all volume actors of a scene together)");
  if (v.raw().empty()) v.error("no keyframe (leave \"keyframes\" out for a static actor)");
  std::vector<RigidKeyframe> keys;
  for (const Value& e : v.array()) {
    const Object o = e.object({"time", "translation", "rotation"}, "a keyframe");
    RigidKeyframe k;
    k.time = o.at("time").number();
    const double previous = keys.empty() ? 0.0 : keys.back().time;
    if (!std::isfinite(k.time) || !(k.time >= previous + inputLimits().minTimeStep))
      check::fail(o.member("time"), k.time,
                  keys.empty() ? "must be finite and at least 1e-9 s (the actor is at its placement at t = 0)"
                               : "must be finite and at least 1e-9 s after the previous keyframe's time");
    k.translation = o.vec3("translation", Eigen::Vector3d::Zero());
    check::normAtMost(k.translation, inputLimits().maxDistance, o.member("translation"));
    if (const auto r = o.find("rotation")) k.turn = readRotation(*r);
    keys.push_back(k);
  }
  return keys;
}

/// The SDF grid files read so far, by resolved path: the first actor that named each (index in scene.volumes).
/// A file named by several actors is read once, and they share its shape, as the run holds it once.
using SdfFilesRead = std::map<std::string, std::size_t>;

/// totals: the scene's so far.
void readVolume(const Value& v, const std::string& type, Scene& scene, const std::string& baseDirectory,
                const SceneTotals& totals, SdfFilesRead& sdfFiles) {
  VolumeActorParams p;
  std::vector<std::string> keys = {"type", "name", "layer", "contact", "velocity", "angularVelocity", "keyframes"};
  if (type == "plane") keys.insert(keys.end(), {"point", "normal"});
  if (type == "box") keys.insert(keys.end(), {"center", "halfExtents", "edgeRadius", "rotation"});
  if (type == "sphere") keys.insert(keys.end(), {"center", "radius"});
  if (type == "capsule") keys.insert(keys.end(), {"center", "radius", "halfLength", "rotation"});
  if (type == "sdfGrid") keys.insert(keys.end(), {"file", "center", "rotation"});
  const Object o = v.object(keys, "a " + type + " actor");
  p.name = o.string("name", "");
  p.layer = o.string("layer", "");
  if (const auto c = o.find("contact")) p.contact = readContact(*c);
  if (type == "plane") {
    p.kind = VolumeActorParams::Kind::Plane;
    const Eigen::Vector3d normal = check::unitDirection(o.vec3("normal", Eigen::Vector3d::UnitZ()), o.member("normal"));
    p.worldFromLocalTransform.rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal);
    p.worldFromLocalTransform.translation = position(o, "point");
  } else if (type == "box") {
    p.kind = VolumeActorParams::Kind::Box;
    p.worldFromLocalTransform.translation = position(o, "center");
    if (const auto r = o.find("rotation")) p.worldFromLocalTransform.rotation = readRotation(*r);
    p.halfExtents = o.at("halfExtents").vec3();
    for (int c = 0; c < 3; ++c) {
      const std::string field = o.member("halfExtents") + "/" + std::to_string(c);
      check::positive(p.halfExtents[c], field);
      check::atMostReal(p.halfExtents[c], inputLimits().maxDistance, field);
    }
    p.edgeRadius = o.number("edgeRadius", 0.0);
    checkEdgeRadius(p.edgeRadius, p.halfExtents, o.member("edgeRadius"));
  } else if (type == "sphere") {
    p.kind = VolumeActorParams::Kind::Sphere;
    p.worldFromLocalTransform.translation = position(o, "center");
    p.radius = length(o, "radius");
  } else if (type == "capsule") {
    p.kind = VolumeActorParams::Kind::Capsule;
    p.worldFromLocalTransform.translation = position(o, "center");
    if (const auto r = o.find("rotation")) p.worldFromLocalTransform.rotation = readRotation(*r);
    p.radius = length(o, "radius");
    p.halfLength = o.number("halfLength", 0.0);
    check::nonNegative(p.halfLength, o.member("halfLength"));
    check::atMostReal(p.halfLength, inputLimits().maxDistance, o.member("halfLength"));
  } else {
    p.kind = VolumeActorParams::Kind::SdfGrid;
    p.worldFromLocalTransform.translation = position(o, "center");
    if (const auto r = o.find("rotation")) p.worldFromLocalTransform.rotation = readRotation(*r);
    const std::string file = o.string("file", "");
    if (file.empty()) throw InputError(o.member("file") + ": missing (the SDF grid file)");
    p.sdfFile = (std::filesystem::path(baseDirectory) / file).lexically_normal().string();
    const auto read = sdfFiles.find(p.sdfFile);
    if (read != sdfFiles.end()) {
      const VolumeActorParams& first = scene.volumes[read->second];
      p.sdfSamples = first.sdfSamples;
      p.sdfShape = first.sdfShape;
      p.sdfBox = first.sdfBox;
      p.sdfThinnestHalfWidth = first.sdfThinnestHalfWidth;
    } else {
      at(o.member("file"), [&] {  // named errors now
        SdfGrid grid = readSdfGrid(p.sdfFile);
        p.sdfSamples = static_cast<std::int64_t>(grid.values.size());
        p.sdfBox = sdfGridBox(grid);
        p.sdfThinnestHalfWidth = sdfGridThinnestHalfWidth(grid);
        p.sdfShape = makeSdfGridShape(std::move(grid));
      });
      sdfFiles.emplace(p.sdfFile, scene.volumes.size());
    }
  }
  p.velocity = o.vec3("velocity", Eigen::Vector3d::Zero());
  check::normAtMost(p.velocity, inputLimits().maxDistance, o.member("velocity"));
  p.angularVelocity = o.vec3("angularVelocity", Eigen::Vector3d::Zero());
  check::normAtMost(p.angularVelocity, inputLimits().maxAngularVelocity, o.member("angularVelocity"));
  if (const auto k = o.find("keyframes")) {
    if (o.has("velocity") || o.has("angularVelocity"))
      throw InputError(o.member("keyframes") + ": cannot be combined with \"velocity\" or \"angularVelocity\" (a "
                       "keyframed actor moves through its keyframes alone)");
    p.keyframes = readKeyframes(*k, inputLimits().maxKeyframes - totals.keyframes);
  }
  at(v.pointer(), [&] { scene.addVolumeActor(std::move(p)); });
}

PathControlSettings readPathControl(const Value& v, int maxSteps) {
  if (!v.isObject()) v.typeError("an object (the path control)");
  PathControlSettings c;
  c.type = Object(v).choice("type", {"load", "arcLength", "displacement"}, "load");
  if (c.type == "load") {
    v.object({"type"}, "a load path control");
    return c;
  }
  if (c.type == "arcLength") {
    const Object o = v.object({"type", "maxSteps", "loadScaling"}, "an arcLength path control");
    c.maxSteps = o.integer("maxSteps", c.maxSteps, 1, maxSteps);
    c.loadScaling = o.number("loadScaling", c.loadScaling);
    check::nonNegative(c.loadScaling, o.member("loadScaling"));
    return c;
  }
  const Object o = v.object({"type", "maxSteps", "probe", "component", "displacement"}, "a displacement path control");
  c.maxSteps = o.integer("maxSteps", c.maxSteps, 1, maxSteps);
  c.probe = o.string("probe", "");
  if (c.probe.empty()) throw InputError(o.member("probe") + ": missing (required: the name of the probe to drive)");
  const std::string component = o.choice("component", {"x", "y", "z"}, "z");
  c.component = component[0] - 'x';
  if (!o.has("displacement")) throw InputError(o.member("displacement") + ": missing (required)");
  c.displacement = o.number("displacement", 0.0);
  if (!std::isfinite(c.displacement) || c.displacement == 0.0)
    check::fail(o.member("displacement"), c.displacement, "must be finite and non-zero");
  return c;
}

AnalysisSettings readAnalysis(const Value& v) {
  if (!v.isObject()) v.typeError("an object (the analysis)");
  const std::string type = Object(v).choice("type", {"static", "dynamic", "dynamicRelaxation"}, "");
  if (type.empty()) throw InputError(v.pointer() + "/type: missing (required: static, dynamic or dynamicRelaxation)");
  AnalysisSettings a;
  const int maxSteps = static_cast<int>(inputLimits().maxSteps);
  if (type == "static") {
    const Object o = v.object({"type", "loadSteps", "pathControl", "branchSwitching"}, "a static analysis");
    a.type = AnalysisType::Static;
    a.loadSteps = o.integer("loadSteps", a.loadSteps, 1, static_cast<int>(inputLimits().maxLoadLevels));
    a.branchSwitching = o.boolean("branchSwitching", a.branchSwitching);
    if (const auto p = o.find("pathControl")) a.pathControl = readPathControl(*p, maxSteps);
    return a;
  }
  const bool dynamic = type == "dynamic";
  const Object o = dynamic ? v.object({"type", "timeStep", "duration", "integrator", "loadRampTime"}, "a dynamic analysis")
                           : v.object({"type", "timeStep", "maxSteps", "tolerance", "massDamping"},
                                      "a dynamicRelaxation analysis");
  a.type = dynamic ? AnalysisType::Dynamic : AnalysisType::DynamicRelaxation;
  a.timeStep = positive(o, "timeStep");
  if (dynamic) {
    a.loadRampTime = o.number("loadRampTime", 0.0);
    check::nonNegative(a.loadRampTime, o.member("loadRampTime"));
    a.duration = positive(o, "duration");
    if (a.duration < a.timeStep) check::fail(o.member("duration"), a.duration, "must be >= timeStep");
    check::stepCount(a.duration, a.timeStep, maxSteps, o.member("timeStep"));
    a.integrator = o.choice("integrator", {"backwardEuler", "bdf2"}, "backwardEuler") == "bdf2" ? Integrator::BDF2
                                                                                            : Integrator::BackwardEuler;
  } else {
    a.maxSteps = o.integer("maxSteps", a.maxSteps, 1, maxSteps);
    a.tolerance = o.number("tolerance", a.tolerance);
    check::positive(a.tolerance, o.member("tolerance"));
    check::atMostReal(a.tolerance, kMaxRelativeTolerance, o.member("tolerance"));
    a.massDamping = o.number("massDamping", a.massDamping);
    check::nonNegative(a.massDamping, o.member("massDamping"));
  }
  return a;
}

SolverSettings readSolver(const Value& v) {
  const Object o = v.object({"maxIterations", "residualTolerance", "decrementTolerance", "lineSearch", "linearSolver",
                             "preconditioner", "psdProjection", "derivatives", "bendingHessian", "fallbackBendingHessian",
                             "frictionHessian", "evaluator", "threads", "acceptIterationCap"},
                            "solver settings");
  SolverSettings s;
  if (const auto m = o.find("maxIterations")) {
    s.maxIterations = m->integer(1, static_cast<int>(inputLimits().maxIterations));
  }
  if (const auto t = o.find("residualTolerance")) {
    s.residualTolerance = t->number();
    check::nonNegative(*s.residualTolerance, t->pointer());
    check::atMostReal(*s.residualTolerance, kMaxRelativeTolerance, t->pointer());
  }
  if (const auto t = o.find("decrementTolerance")) {
    s.decrementTolerance = t->number();
    check::nonNegative(*s.decrementTolerance, t->pointer());
    check::atMostReal(*s.decrementTolerance, kMaxRelativeTolerance, t->pointer());
  }
  s.lineSearch = o.choice("lineSearch", {"default", "none", "armijo", "residual", "wolfe"}, s.lineSearch);
  s.linearSolver = o.choice("linearSolver", {"auto", "cholmod", "ldlt", "pcg"}, s.linearSolver);
  s.preconditioner = o.choice("preconditioner", {"jacobi", "block_jacobi", "ic"}, s.preconditioner);
  s.psdProjection = o.choice("psdProjection", {"auto", "none", "clamp", "abs"}, s.psdProjection);
  s.derivatives = o.choice("derivatives", {"analytic", "autodiff"}, s.derivatives);
  s.bendingHessian = o.choice("bendingHessian", {"exact", "gaussNewton"}, s.bendingHessian);
  s.fallbackBendingHessian =
      o.choice("fallbackBendingHessian", {"exact", "gaussNewton"}, s.fallbackBendingHessian);
  s.frictionHessian = o.choice("frictionHessian", {"exact", "majorizer"}, s.frictionHessian);
  // "handChained": perFace's name before the bending term lost its hand-chained evaluator (older scenes).
  s.evaluator = o.choice("evaluator", {"perFace", "staged", "handChained"}, s.evaluator);
  if (s.evaluator == "handChained") s.evaluator = "perFace";
  s.acceptIterationCap = o.boolean("acceptIterationCap", s.acceptIterationCap);
  s.threads = o.integer("threads", s.threads, 0, inputLimits().maxThreads);
  return s;
}

OutputSettings readOutputs(const Value& v) {
  const Object o = v.object({"vtu", "obj", "frameStride", "probesCsv", "png", "plots"}, "output settings");
  OutputSettings out;
  out.vtu = o.boolean("vtu", out.vtu);
  out.obj = o.boolean("obj", out.obj);
  out.frameStride = o.integer("frameStride", out.frameStride, 1, static_cast<int>(inputLimits().maxSteps));
  out.probesCsv = o.boolean("probesCsv", out.probesCsv);
  out.png = o.boolean("png", out.png);
  out.plots = o.boolean("plots", out.plots);
  return out;
}

EdgeRuleSettings readEdgeRules(const Value& v) {
  const Object o = v.object({"clamp", "free", "symmetryPlanes"}, "the edge rules");
  EdgeRuleSettings r;
  r.clamp = o.choice("clamp", {"mirrored_clamp", "reference_clamp"}, r.clamp);
  r.free = o.choice("free", {"second_order_free", "page_free"}, r.free);
  if (const auto planes = o.find("symmetryPlanes")) {
    const std::vector<Value> list = planes->array();
    if (list.size() > 16) throw InputError(planes->pointer() + ": at most 16 symmetry planes");
    for (const Value& e : list) {
      const Object p = e.object({"point", "normal"}, "a symmetry plane");
      EdgeRuleSettings::SymmetryPlane plane;
      plane.point = p.vec3("point", plane.point);
      plane.normal = check::unitDirection(p.vec3("normal", plane.normal), e.pointer() + "/normal");
      r.symmetryPlanes.push_back(plane);
    }
  }
  return r;
}

}  // namespace

Scene sceneFromJson(const nlohmann::json& document, const std::string& baseDirectory) {
  const Value root(document, "");
  const Object o = root.object({"description", "gravity", "actors", "analysis", "solver", "outputs", "edgeRules"}, "a scene");
  Scene scene;
  scene.description = o.string("description", "");
  scene.gravity = o.vec3("gravity", scene.gravity);
  const std::vector<Value> actors = o.at("actors").array();
  // The totals are checked after each actor, so that no shape is generated or read past a scene-wide bound (a
  // 1 KB scene of many large generated shells would otherwise fill the memory before validate() below).
  SceneTotals totals;
  SdfFilesRead sdfFiles;
  for (const Value& a : actors) {
    if (!a.isObject()) a.typeError("an object (an actor)");
    const std::string type =
        Object(a).choice("type", {"shell", "plane", "box", "sphere", "capsule", "sdfGrid"}, "");
    if (type.empty())
      throw InputError(a.pointer() + "/type: missing (required: shell, plane, box, sphere, capsule or sdfGrid)");
    if (type == "shell") {
      readShell(a, scene, baseDirectory);
      totals.add(scene.shells.back());
    } else {
      readVolume(a, type, scene, baseDirectory, totals, sdfFiles);
      totals.add(scene.volumes.back());
    }
    checkSceneTotals(totals, a.pointer());
  }
  if (scene.shells.empty()) throw InputError("/actors: no shell actor (nothing to simulate)");
  scene.analysis = readAnalysis(o.at("analysis"));
  if (const auto s = o.find("solver")) scene.solver = readSolver(*s);
  if (const auto out = o.find("outputs")) scene.outputs = readOutputs(*out);
  if (const auto r = o.find("edgeRules")) scene.edgeRules = readEdgeRules(*r);
  validate(scene);
  return scene;
}

Scene loadSceneFile(const std::string& path) {
  return sceneFromText(readInputFile(path, inputLimits().maxJsonBytes, "scene file"), path);
}

Scene sceneFromText(const std::string& text, const std::string& path) {
  const nlohmann::json document = json::parse(text, path);
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  return sceneFromJson(document, base.empty() ? "." : base.string());
}

}  // namespace jetshell
