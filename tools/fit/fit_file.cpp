#include "tools/fit/fit_file.h"

#include "core/format.h"
#include "core/input_file.h"
#include "core/input_limits.h"

#include "core/mesh_io.h"
#include "tools/scene/checks.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/scene_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace jetshell {
namespace {

using json::Object;
using json::Value;

constexpr std::uintmax_t kMaxFileBytes = 64u << 20;

std::string readText(const std::string& path, const std::string& what) {
  // Regular files only (a FIFO or /dev/zero is an input error, not a hang), bounded in size.
  return readInputFile(path, static_cast<std::int64_t>(kMaxFileBytes), what);
}

std::string resolve(const std::string& base, const std::string& path) {
  std::filesystem::path p = path;
  if (p.is_relative()) p = std::filesystem::path(base) / p;
  return p.lexically_normal().string();
}

/// Scene errors from an inline scene name pointers from its root: put them under /scene.
Scene inlineScene(const Value& v, const std::string& base) {
  try {
    return sceneFromJson(v.raw(), base);
  } catch (const InputError& e) {
    const std::string m = e.what();
    throw InputError(m.rfind('/', 0) == 0 ? "/scene" + m : "/scene: " + m);
  }
}

/// The raw JSON of shell actor `index` (shell actors counted in file order), or null.
const nlohmann::json* shellActorJson(const nlohmann::json& scene, int index) {
  if (!scene.contains("actors") || !scene["actors"].is_array()) return nullptr;
  int k = 0;
  for (const nlohmann::json& a : scene["actors"]) {
    if (!a.is_object() || !a.contains("type") || a["type"] != "shell") continue;
    if (k++ == index) return &a;
  }
  return nullptr;
}

MaterialBase materialBase(const Scene& scene, const nlohmann::json& sceneJson, int actor) {
  MaterialBase b;
  b.shell = scene.shells[static_cast<std::size_t>(actor)].material;
  const nlohmann::json* a = shellActorJson(sceneJson, actor);
  if (a && a->contains("material") && (*a)["material"].is_object() && (*a)["material"].contains("youngsModulus")) {
    const nlohmann::json& m = (*a)["material"];
    b.isotropic = true;
    b.youngsModulus = m["youngsModulus"].get<double>();
    b.poissonRatio = m["poissonRatio"].get<double>();
    b.thickness = m["thickness"].get<double>();
    b.volumeDensity = m["volumeDensity"].get<double>();
  }
  return b;
}

int componentIndex(const std::string& c, const std::string& where) {
  if (c == "x") return 0;
  if (c == "y") return 1;
  if (c == "z") return 2;
  throw InputError(where + " = \"" + c + "\": must be \"x\", \"y\" or \"z\"");
}

double loadFactor(const Value& v) {
  const double l = v.number();
  if (!(std::isfinite(l) && l >= 0.0 && l <= 100.0)) check::fail(v.pointer(), l, "must lie in [0, 100]");
  return l;
}

/// A dynamic observation's time: a step time k·timeStep with 1 ≤ k ≤ the run's steps; returned snapped.
double stepTime(const Value& v, const Scene& scene) {
  const double t = v.number();
  const double h = scene.analysis.timeStep;
  if (!std::isfinite(t)) check::fail(v.pointer(), t, "must be finite");
  const double k = std::round(t / h);
  const double steps = std::ceil(scene.analysis.duration / h - 1e-9);
  if (std::abs(t / h - k) > 1e-6) {
    std::ostringstream m;
    m << v.pointer() << " = " << t << ": not a step time (the scene's timeStep is " << h << " s: the nearest are "
      << std::floor(t / h) * h << " and " << (std::floor(t / h) + 1.0) * h << ")";
    throw InputError(m.str());
  }
  if (k < 1.0) check::fail(v.pointer(), t, "must be a step time after the start (>= timeStep)");
  if (k > steps) {
    std::ostringstream m;
    m << v.pointer() << " = " << t << ": beyond the end of the run (the scene's duration is " << scene.analysis.duration
      << " s)";
    throw InputError(m.str());
  }
  return k * h;
}

/// The level of a probe or shape observation: "loadFactor" in a static scene, "time" in a dynamic one.
double observationLevel(const Object& o, const Scene& scene) {
  if (scene.analysis.type == AnalysisType::Dynamic) return stepTime(o.at("time"), scene);
  return loadFactor(o.at("loadFactor"));
}

double weight(const Object& o) {
  const double w = o.number("weight", 1.0);
  check::nonNegative(w, o.member("weight"));
  if (!(w <= kMaxObservationWeight))
    check::fail(o.member("weight"), w, "must be at most " + formatNumber("%g", kMaxObservationWeight));
  return w;
}

const Probe& findProbe(const Scene& scene, const Value& v) {
  const std::string name = v.string();
  std::vector<std::string> names;
  for (const Probe& p : scene.probes) {
    if (p.name == name) return p;
    names.push_back(p.name);
  }
  const std::string hint = json::closest(name, names);
  throw InputError(v.pointer() + " = \"" + name + "\": the scene has no such probe" +
                   (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
}

ObservationSpec readProbeObservation(const Object& o, const Scene& scene) {
  ObservationSpec s;
  s.kind = ObservationSpec::Kind::Probe;
  s.probe = findProbe(scene, o.at("probe")).name;
  s.levels = {observationLevel(o, scene)};
  s.weight = weight(o);
  const Value d = o.at("displacement");
  if (d.isArray()) {
    if (o.has("component"))
      throw InputError(o.member("component") + ": only with a number as displacement (an array gives all three)");
    s.components = {0, 1, 2};
    s.displacements = {d.vec3()};
    check::normAtMost(s.displacements[0], inputLimits().maxDistance, d.pointer());
  } else {
    const double u = d.number();
    check::finite(u, d.pointer());
    if (!(std::abs(u) <= inputLimits().maxDistance))
      check::fail(d.pointer(), u, "must be at most " + formatNumber("%g", inputLimits().maxDistance) + " m in size");
    const int c = componentIndex(o.at("component").string(), o.member("component"));
    s.components = {c};
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    v[c] = u;
    s.displacements = {v};
  }
  return s;
}

ObservationSpec readShapeObservation(const Object& o, const Scene& scene, const std::string& base) {
  ObservationSpec s;
  s.kind = ObservationSpec::Kind::Shape;
  const Value actor = o.at("actor");
  s.actor = actor.string();
  const int a = scene.shellIndex(s.actor, actor.pointer());
  s.levels = {observationLevel(o, scene)};
  s.weight = weight(o);
  const std::string path = resolve(base, o.at("obj").string());
  TriMesh target;
  try {
    target = readObj(path);
  } catch (const InputError& e) {
    throw InputError(o.member("obj") + ": " + e.what());
  }
  const int n = scene.shells[static_cast<std::size_t>(a)].shape->mesh.numVertices();
  if (target.numVertices() != n)
    throw InputError(o.member("obj") + ": " + path + " has " + std::to_string(target.numVertices()) +
                     " vertices; actor '" + s.actor + "' has " + std::to_string(n) +
                     " (a target shape lists the actor's vertices in its order, in world coordinates)");
  s.targetPositions = target.V;
  return s;
}

ObservationSpec readCurveObservation(const Object& o, const Scene& scene, const std::string& base) {
  ObservationSpec s;
  s.kind = ObservationSpec::Kind::Curve;
  s.probe = findProbe(scene, o.at("probe")).name;
  const int c = componentIndex(o.at("component").string(), o.member("component"));
  s.components = {c};
  s.weight = weight(o);
  const double scale = o.number("displacementScale", 1.0);
  check::finite(scale, o.member("displacementScale"));
  const int loadColumn = o.integer("loadColumn", 0), valueColumn = o.integer("displacementColumn", 1);
  if (loadColumn < 0 || loadColumn > 63) check::fail(o.member("loadColumn"), loadColumn, "must lie in [0, 63]");
  if (valueColumn < 0 || valueColumn > 63 || valueColumn == loadColumn)
    check::fail(o.member("displacementColumn"), valueColumn, "must lie in [0, 63] and differ from loadColumn");
  const std::string path = resolve(base, o.at("csv").string());
  readCurveRows(readText(path, "CSV curve"), path, loadColumn, valueColumn, c, scale, s);
  if (s.levels.empty()) throw InputError(o.member("csv") + ": " + path + " holds no data row");
  return s;
}

}  // namespace

void readCurveRows(const std::string& text, const std::string& path, int loadColumn, int valueColumn, int component,
                   double scale, ObservationSpec& s) {
  if (component < 0 || component > 2 || loadColumn < 0 || loadColumn > 63 || valueColumn < 0 || valueColumn > 63 ||
      loadColumn == valueColumn)
    throw InputError(path + ": the curve's columns must be distinct and in [0, 63], its component 0, 1 or 2");
  const int c = component;
  const int columns = std::max(loadColumn, valueColumn) + 1;
  std::istringstream in(text);
  std::string line;
  int lineNumber = 0;
  bool firstContent = true;  // the first line that is neither blank nor a comment may be a header
  while (std::getline(in, line)) {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    const bool mayBeHeader = firstContent;
    firstContent = false;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::vector<double> row;
    double value = 0.0;
    while (static_cast<int>(row.size()) < columns && fields >> value) row.push_back(value);
    const std::string where = path + ":" + std::to_string(lineNumber);
    if (static_cast<int>(row.size()) < columns) {
      if (mayBeHeader && row.empty()) continue;  // a header line
      throw InputError(where + ": expected at least " + std::to_string(columns) +
                       " numbers (load factor in column " + std::to_string(loadColumn) + ", displacement in column " +
                       std::to_string(valueColumn) + ", counted from 0)");
    }
    const double lambda = row[static_cast<std::size_t>(loadColumn)], u = row[static_cast<std::size_t>(valueColumn)];
    if (!(std::isfinite(lambda) && lambda >= 0.0 && lambda <= 100.0))
      throw InputError(where + ": load factor " + std::to_string(lambda) + " must lie in [0, 100]");
    if (!std::isfinite(u)) throw InputError(where + ": displacement not finite");
    if (!s.levels.empty() && !(lambda > s.levels.back()))
      throw InputError(where + ": load factors must increase");
    if (static_cast<int>(s.levels.size()) >= kMaxCurvePoints)
      throw InputError(where + ": more than " + std::to_string(kMaxCurvePoints) + " points");
    s.levels.push_back(lambda);
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[c] = scale * u;
    if (!(std::abs(d[c]) <= inputLimits().maxDistance))
      throw InputError(where + ": displacement x displacementScale = " + std::to_string(d[c]) +
                       " m, too large (at most " + formatNumber("%g", inputLimits().maxDistance) + " m in size)");
    s.displacements.push_back(d);
  }
}

FitFile fitFromJson(const nlohmann::json& document, const std::string& base, const std::string& name) {
  const Value root(document, "");
  const Object o = root.object({"description", "scene", "parameters", "observations", "algorithm", "maxEvaluations",
                                "parameterTolerance", "misfitTolerance", "plots"},
                               "a fit file");
  FitFile f;
  f.path = name;
  f.description = o.string("description", "");
  const Value sceneValue = o.at("scene");
  nlohmann::json sceneJson;
  if (sceneValue.raw().is_string()) {
    const std::string path = resolve(base, sceneValue.string());
    const std::string text = readText(path, "scene file");
    sceneJson = json::parse(text, path);
    // The scene is built from the text just read (a second read could see another file: the material base below
    // reads this JSON, which the scene reader has then checked).
    const std::filesystem::path sceneBase = std::filesystem::path(path).parent_path();
    try {
      f.scene = sceneFromJson(sceneJson, sceneBase.empty() ? "." : sceneBase.string());
    } catch (const InputError& e) {
      throw InputError(sceneValue.pointer() + ": " + e.what());
    }
  } else if (sceneValue.isObject()) {
    sceneJson = sceneValue.raw();
    f.scene = inlineScene(sceneValue, base);
  } else {
    sceneValue.typeError("a scene file path or an inline scene object");
  }
  if (f.scene.analysis.type == AnalysisType::DynamicRelaxation)
    throw InputError("/scene: the analysis is " + std::string(toString(f.scene.analysis.type)) +
                     "; fitting supports static analyses (observations at load factors) and dynamic ones "
                     "(observations at times; see FITTING.md)");
  const bool dynamic = f.scene.analysis.type == AnalysisType::Dynamic;

  // Parameters.
  const std::vector<Value> params = o.at("parameters").array();
  if (params.empty()) throw InputError(o.member("parameters") + ": empty (nothing to fit)");
  if (params.size() > static_cast<std::size_t>(kMaxFitParameters))
    throw InputError(o.member("parameters") + ": " + std::to_string(params.size()) + " entries; at most " +
                     std::to_string(kMaxFitParameters));
  int actorIndex = -1;
  for (const Value& p : params) {
    const Object po = p.object({"actor", "name", "load", "initial", "lower", "upper", "logScale"}, "a fit parameter");
    FitParameterSpec s;
    s.where = p.pointer();
    const Value actor = po.at("actor");
    s.actor = actor.string();
    const int a = f.scene.shellIndex(s.actor, actor.pointer());
    if (actorIndex >= 0 && a != actorIndex)
      throw InputError(actor.pointer() + " = \"" + s.actor +
                       "\": every parameter must belong to the same actor (the solver takes one material per scene)");
    if (actorIndex < 0) {
      actorIndex = a;
      f.material = materialBase(f.scene, sceneJson, a);
    }
    s.name = po.at("name").string();
    const std::vector<std::string> names = fittableMaterialNames(f.material);
    if (std::find(names.begin(), names.end(), s.name) == names.end()) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      const std::string hint = json::closest(s.name, names);
      throw InputError(po.member("name") + " = \"" + s.name + "\": not a fittable parameter of actor '" + s.actor +
                       "' (its material is given " + (f.material.isotropic ? "as E, nu, thickness, volumeDensity" : "by shell parameters") +
                       "; fittable: " + list + ")" + (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
    }
    if (po.has("load")) {
      if (s.name != "loadScale")
        throw InputError(po.member("load") + ": only with \"name\": \"loadScale\" (the scale of one named load)");
      const Value load = po.at("load");
      s.load = load.string();
      std::vector<std::string> loadNames;
      for (const LoadCondition& l : f.scene.loads)
        if (!l.name.empty()) loadNames.push_back(l.name);
      if (std::find(loadNames.begin(), loadNames.end(), s.load) == loadNames.end()) {
        const std::string hint = json::closest(s.load, loadNames);
        throw InputError(load.pointer() + " = \"" + s.load + "\": the scene has no load of that name (loads are " +
                         "named by their \"name\" key)" + (hint.empty() ? "" : " (did you mean \"" + hint + "\"?)"));
      }
    }
    for (const FitParameterSpec& q : f.parameters)
      if (q.name == s.name && q.load == s.load)
        throw InputError(po.member("name") + " = \"" + s.name + "\": fitted twice" +
                         (s.load.empty() ? "" : " (load \"" + s.load + "\")"));
    FitVariable& v = s.variable;
    v.label = s.actor + "." + s.name + (s.load.empty() ? "" : "/" + s.load);
    v.initial = po.number("initial", materialBaseValue(f.material, s.name));
    check::finite(v.initial, po.member("initial"));
    v.lower = po.at("lower").number();
    check::finite(v.lower, po.member("lower"));
    v.upper = po.at("upper").number();
    check::finite(v.upper, po.member("upper"));
    if (!(v.lower < v.upper)) check::fail(po.member("upper"), v.upper, "must be > lower");
    if (v.initial < v.lower || v.initial > v.upper) check::fail(po.member("initial"), v.initial, "must lie within [lower, upper]");
    v.logScale = po.boolean("logScale", false);
    if (v.logScale && !(v.lower > 0.0)) check::fail(po.member("lower"), v.lower, "must be > 0 with logScale");
    if (s.name == "poissonRatio" && !(v.lower > -1.0 && v.upper < 0.5))
      throw InputError(s.where + ": poissonRatio bounds must lie inside (-1, 0.5)");
    if (s.name != "poissonRatio" && s.name != "membraneLambda" && !(v.lower >= 0.0))
      check::fail(po.member("lower"), v.lower, "must be >= 0 for this parameter");
    f.parameters.push_back(std::move(s));
  }

  // Observations.
  const std::vector<Value> obs = o.at("observations").array();
  if (obs.empty()) throw InputError(o.member("observations") + ": empty (nothing to fit to)");
  if (obs.size() > static_cast<std::size_t>(kMaxFitObservations))
    throw InputError(o.member("observations") + ": more than " + std::to_string(kMaxFitObservations) + " entries");
  std::set<double> levels;
  for (const Value& v : obs) {
    if (!v.isObject()) v.typeError("an object (an observation)");
    if (!dynamic && v.raw().contains("time"))
      throw InputError(v.pointer() + "/time: observations at times need a dynamic scene (this one is static: "
                                     "observe at a \"loadFactor\")");
    if (dynamic && v.raw().contains("loadFactor"))
      throw InputError(v.pointer() + "/loadFactor: the scene is dynamic: observe at a \"time\" (a step time)");
    const std::string type = Object(v).choice("type", {"probe", "shape", "curve"}, "");
    if (type.empty()) throw InputError(v.pointer() + "/type: missing (required: probe, shape or curve)");
    if (dynamic && type == "curve")
      throw InputError(v.pointer() + "/type: curve observations (load–displacement tables) need a static scene");
    const std::string level = dynamic ? "time" : "loadFactor";
    ObservationSpec s;
    if (type == "probe") {
      s = readProbeObservation(v.object({"type", "probe", level, "displacement", "component", "weight"}, "a probe observation"), f.scene);
    } else if (type == "shape") {
      s = readShapeObservation(v.object({"type", "actor", level, "obj", "weight"}, "a shape observation"), f.scene, base);
    } else {
      s = readCurveObservation(v.object({"type", "probe", "component", "csv", "loadColumn", "displacementColumn", "displacementScale", "weight"}, "a curve observation"), f.scene, base);
    }
    s.where = v.pointer();
    levels.insert(s.levels.begin(), s.levels.end());
    if (static_cast<int>(levels.size()) > kMaxFitLevels)
      throw InputError(v.pointer() + ": more than " + std::to_string(kMaxFitLevels) + " distinct " +
                       (dynamic ? "times" : "load levels") + " in all");
    f.observations.push_back(std::move(s));
  }
  bool anyWeight = false;
  for (const ObservationSpec& s : f.observations) anyWeight = anyWeight || s.weight > 0.0;
  if (!f.observations.empty() && !anyWeight)
    throw InputError(o.member("observations") + ": every observation has weight 0: nothing to fit");

  f.options.algorithm = fitAlgorithmFromString(
      o.choice("algorithm", {"bobyqa", "nelder-mead", "lbfgs", "mma", "levenberg-marquardt"}, "levenberg-marquardt"));
  f.options.maxEvaluations = o.integer("maxEvaluations", f.options.maxEvaluations);
  if (f.options.maxEvaluations < 1 || f.options.maxEvaluations > 10000)
    check::fail(o.member("maxEvaluations"), f.options.maxEvaluations, "must lie in [1, 10000]");
  f.options.parameterTolerance = o.number("parameterTolerance", f.options.parameterTolerance);
  if (!(f.options.parameterTolerance >= 1e-15 && f.options.parameterTolerance <= 1.0))
    check::fail(o.member("parameterTolerance"), f.options.parameterTolerance, "must lie in [1e-15, 1]");
  f.options.misfitTolerance = o.number("misfitTolerance", f.options.misfitTolerance);
  if (!(f.options.misfitTolerance >= 0.0 && f.options.misfitTolerance <= 1.0))
    check::fail(o.member("misfitTolerance"), f.options.misfitTolerance, "must lie in [0, 1]");
  f.plots = o.boolean("plots", true);
  return f;
}

FitFile loadFitFile(const std::string& path) {
  const std::string text = readText(path, "fit file");
  const nlohmann::json document = json::parse(text, path);
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  return fitFromJson(document, base.empty() ? "." : base.string(), path);
}

}  // namespace jetshell
