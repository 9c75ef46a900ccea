#include "tools/scene/scene.h"

#include "solvers/newton.h"
#include "tools/scene/checks.h"

#include "core/format.h"
#include "core/input_limits.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <set>

namespace jetshell {

int Scene::addShellActor(ShellActorParams params) {
  const int index = static_cast<int>(shells.size());
  if (params.name.empty()) params.name = "shell" + std::to_string(index);
  const std::string where = "shell actor '" + params.name + "'";
  validate(params, where);
  if (shellNames_.size() != shells.size()) {
    shellNames_.clear();
    for (const ShellActorParams& s : shells) shellNames_.insert(s.name);
  }
  if (shellNames_.count(params.name)) throw InputError(where + ": the name is already used by another shell actor");
  shellNames_.insert(params.name);
  shells.push_back(std::move(params));
  return index;
}

int Scene::addVolumeActor(VolumeActorParams params) {
  const int index = static_cast<int>(volumes.size());
  if (params.name.empty()) params.name = std::string(toString(params.kind)) + std::to_string(index);
  const std::string where = "volume actor '" + params.name + "'";
  validate(params, where);
  if (volumeNames_.size() != volumes.size()) {
    volumeNames_.clear();
    for (const VolumeActorParams& v : volumes) volumeNames_.insert(v.name);
  }
  if (volumeNames_.count(params.name)) throw InputError(where + ": the name is already used by another volume actor");
  volumeNames_.insert(params.name);
  volumes.push_back(std::move(params));
  return index;
}

int Scene::shellIndex(const std::string& name, const std::string& where) const {
  for (std::size_t i = 0; i < shells.size(); ++i)
    if (shells[i].name == name) return static_cast<int>(i);
  std::string known;
  for (const ShellActorParams& s : shells) known += (known.empty() ? "'" : ", '") + s.name + "'";
  throw InputError(where + " = \"" + name + "\": no shell actor has this name" +
                   (known.empty() ? "" : " (known: " + known + ")"));
}

namespace {

void requireActor(const Scene& scene, int actor, const std::string& where) {
  if (actor < 0 || actor >= static_cast<int>(scene.shells.size()))
    throw InputError(where + ".actor = " + std::to_string(actor) + ": no such shell actor (the scene has " +
                     std::to_string(scene.shells.size()) + ")");
}

void validateSelection(const VertexSelection& selection, const std::string& where) {
  if (selection.empty()) throw InputError(where + ": selects nothing (an empty list)");
  for (std::size_t k = 0; k < selection.size(); ++k)
    validate(selection[k], selection.size() == 1 ? where : where + "/" + std::to_string(k));
}

void requireOneOf(const std::string& value, std::initializer_list<const char*> options, const std::string& field) {
  std::string list;
  for (const char* o : options) {
    if (value == o) return;
    list += (list.empty() ? "" : ", ") + std::string(o);
  }
  throw InputError(field + " = \"" + value + "\": must be one of " + list);
}

}  // namespace

void SceneTotals::add(const ShellActorParams& s) {
  ++shells;
  vertices += s.shape ? s.shape->mesh.numVertices() : 0;
  faces += s.shape ? s.shape->mesh.numFaces() : 0;
}

void SceneTotals::add(const VolumeActorParams& v) {
  ++volumes;
  keyframes += static_cast<std::int64_t>(v.keyframes.size());
  if (v.kind == VolumeActorParams::Kind::SdfGrid && sdfFiles.emplace(v.sdfFile, v.sdfSamples).second)
    sdfSamples += v.sdfSamples;
}

SceneTotals sceneTotals(const Scene& scene) {
  SceneTotals t;
  for (const ShellActorParams& s : scene.shells) t.add(s);
  for (const VolumeActorParams& v : scene.volumes) t.add(v);
  return t;
}

void checkSceneTotals(const SceneTotals& t, const std::string& where) {
  const InputLimits& limits = inputLimits();
  check::atMost(t.vertices, limits.maxVertices, where + ": vertices of all shell actors");
  check::atMost(t.faces, limits.maxFaces, where + ": faces of all shell actors");
  check::atMost(t.shells + t.volumes, limits.maxActors, where + ": actors");
  if (t.shells * t.volumes > limits.maxContactPairs)
    throw InputError(where + ": " + std::to_string(t.shells) + " shell actors x " + std::to_string(t.volumes) +
                     " volume actors = " + std::to_string(t.shells * t.volumes) + " contact pairs, each with terms of "
                     "its own: at most " + std::to_string(limits.maxContactPairs) + " (merge shells into one mesh, or "
                     "use fewer volume actors)");
  if (t.volumes * t.vertices > limits.maxVolumeActorVertices)
    throw InputError(where + ": " + std::to_string(t.volumes) + " volume actors over " + std::to_string(t.vertices) +
                     " shell vertices: each volume actor samples every shell vertex, so volume actors x vertices "
                     "must be at most " + std::to_string(limits.maxVolumeActorVertices) + " (use fewer volume actors)");
  check::atMost(t.sdfSamples, limits.maxSdfSamples, where + ": samples of all SDF grids");
  check::atMost(t.keyframes, limits.maxKeyframes, where + ": keyframes of all volume actors");
}

void validate(const Scene& scene) {
  check::finite(scene.gravity, "/gravity");
  check::normAtMost(scene.gravity, inputLimits().maxAcceleration, "/gravity");
  if (scene.shells.empty()) throw InputError("scene: no shell actor (nothing to simulate)");
  std::set<std::string> shellNames, volumeNames;
  for (std::size_t i = 0; i < scene.shells.size(); ++i) {
    const ShellActorParams& s = scene.shells[i];
    validate(s, "shell actor " + std::to_string(i));
    if (!shellNames.insert(s.name).second) throw InputError("shell actor " + std::to_string(i) + ": duplicate name '" + s.name + "'");
  }
  for (std::size_t i = 0; i < scene.volumes.size(); ++i) {
    validate(scene.volumes[i], "volume actor " + std::to_string(i));
    if (!volumeNames.insert(scene.volumes[i].name).second)
      throw InputError("volume actor " + std::to_string(i) + ": duplicate name '" + scene.volumes[i].name + "'");
  }
  const InputLimits& limits = inputLimits();
  check::atMost(static_cast<std::int64_t>(scene.fixed.size()), limits.maxConditions, "scene: fixed conditions");
  check::atMost(static_cast<std::int64_t>(scene.loads.size()), limits.maxConditions, "scene: loads");
  check::atMost(static_cast<std::int64_t>(scene.probes.size()), limits.maxConditions, "scene: probes");
  for (const FixedCondition& c : scene.fixed) {
    requireActor(scene, c.actor, c.where);
    validateSelection(c.select, c.where + "/select");
    if (!c.components[0] && !c.components[1] && !c.components[2])
      throw InputError(c.where + "/components: fixes no component (use some of \"x\", \"y\", \"z\")");
    check::finite(c.displacement, c.where + "/displacement");
    check::finite(c.velocity, c.where + "/velocity");
    check::normAtMost(c.displacement, inputLimits().maxDistance, c.where + "/displacement");
    check::normAtMost(c.velocity, inputLimits().maxDistance, c.where + "/velocity");
    if (c.rotation) {
      check::nonZero(c.rotation->axis, c.where + "/rotation/axis");
      check::finite(c.rotation->center, c.where + "/rotation/center");
      check::finite(c.rotation->radians, c.where + "/rotation/degrees");
    }
  }
  for (const LoadCondition& l : scene.loads) {
    requireActor(scene, l.actor, l.where);
    validateSelection(l.select, l.where + "/select");
    check::finite(l.force, l.where + "/force");
  }
  check::atMost(static_cast<std::int64_t>(scene.moments.size()), inputLimits().maxEndMoments, "scene: moment loads");
  for (const MomentLoad& m : scene.moments) {
    requireActor(scene, m.actor, m.where);
    validateSelection(m.select, m.where + "/select");
    check::finite(m.moment, m.where + "/moment");
    check::nonZero(m.axis, m.where + "/axis");
    if (scene.analysis.type != AnalysisType::Static)
      throw InputError(m.where + "/moment: an end moment needs a static analysis (its rotation is unwrapped from one "
                       "load step to the next)");
  }
  std::set<std::string> probeNames;
  for (const Probe& p : scene.probes) {
    requireActor(scene, p.actor, p.where);
    validateSelection(p.select, p.where + "/select");
    if (p.name.empty()) throw InputError(p.where + "/name: must not be empty");
    if (!probeNames.insert(p.name).second) throw InputError(p.where + "/name = \"" + p.name + "\": duplicate probe name");
  }
  checkSceneTotals(sceneTotals(scene), "scene");
  const AnalysisSettings& a = scene.analysis;
  if (a.type == AnalysisType::Static) check::atLeast(a.loadSteps, 1, "/analysis/loadSteps");
  if (a.type == AnalysisType::Static) check::atMost(a.loadSteps, limits.maxLoadLevels, "/analysis/loadSteps");
  if (a.type == AnalysisType::Static) {
    const PathControlSettings& c = a.pathControl;
    requireOneOf(c.type, {"load", "arcLength", "displacement"}, "/analysis/pathControl/type");
    check::atLeast(c.maxSteps, 1, "/analysis/pathControl/maxSteps");
    check::atMost(c.maxSteps, limits.maxSteps, "/analysis/pathControl/maxSteps");
    check::nonNegative(c.loadScaling, "/analysis/pathControl/loadScaling");
    if (c.type == "displacement") {
      if (!probeNames.count(c.probe))
        throw InputError("/analysis/pathControl/probe = \"" + c.probe + "\": no probe has this name");
      if (c.component < 0 || c.component > 2)
        check::fail("/analysis/pathControl/component", c.component, "must be 0, 1 or 2 (x, y, z)");
      if (!std::isfinite(c.displacement) || c.displacement == 0.0)
        check::fail("/analysis/pathControl/displacement", c.displacement, "must be finite and non-zero");
    }
    // A moving solid's time is the load factor, which arc length and displacement control solve for.
    if (c.type != "load")
      for (const VolumeActorParams& v : scene.volumes)
        if (!rigidPath(v, AnalysisType::Static).isStatic())
          throw InputError("/analysis/pathControl/type = \"" + c.type + "\": the volume actor '" + v.name +
                           "' moves along its keyframes with the load factor, which this control solves for; a "
                           "static path with a moving solid needs \"load\" control");
  }
  if (a.type != AnalysisType::Static) {
    check::positive(a.timeStep, "/analysis/timeStep");
    check::nonNegative(a.loadRampTime, "/analysis/loadRampTime");
  }
  if (a.type == AnalysisType::Dynamic) {
    check::positive(a.duration, "/analysis/duration");
    if (a.duration < a.timeStep) check::fail("/analysis/duration", a.duration, "must be >= timeStep");
    check::stepCount(a.duration, a.timeStep, limits.maxSteps, "/analysis/timeStep");
  }
  // After the step count: a time step too short for the duration is told as too many steps.
  if (a.type != AnalysisType::Static && !(a.timeStep >= limits.minTimeStep))
    check::fail("/analysis/timeStep", a.timeStep,
                "must be at least " + formatNumber("%g", limits.minTimeStep) +
                    " s (its inverse square scales the inertia)");
  if (a.type == AnalysisType::DynamicRelaxation) {
    check::atLeast(a.maxSteps, 1, "/analysis/maxSteps");
    check::atMost(a.maxSteps, limits.maxSteps, "/analysis/maxSteps");
    check::positive(a.tolerance, "/analysis/tolerance");
    check::nonNegative(a.massDamping, "/analysis/massDamping");
    if (!(a.massDamping <= limits.maxDampingCoefficient))
      check::fail("/analysis/massDamping", a.massDamping,
                  "must be at most " + formatNumber("%g", limits.maxDampingCoefficient) + " 1/s");
    double materialDamping = 0.0;
    for (const ShellActorParams& shell : scene.shells)
      materialDamping = std::max(materialDamping, shell.material.massDampingCoefficient);
    if (a.massDamping == 0.0 && materialDamping == 0.0)
      check::fail("/analysis/massDamping", a.massDamping,
                  "must be > 0 when no actor's material has a massDampingCoefficient (relaxation needs damping)");
    if (a.loadRampTime != 0.0) check::fail("/analysis/loadRampTime", a.loadRampTime, "must be 0 for dynamic relaxation");
  }
  const SolverSettings& s = scene.solver;
  if (s.maxIterations) check::atLeast(*s.maxIterations, 1, "/solver/maxIterations");
  if (s.maxIterations) check::atMost(*s.maxIterations, limits.maxIterations, "/solver/maxIterations");
  if (s.residualTolerance) check::nonNegative(*s.residualTolerance, "/solver/residualTolerance");
  if (s.decrementTolerance) check::nonNegative(*s.decrementTolerance, "/solver/decrementTolerance");
  if (s.residualTolerance) check::atMostReal(*s.residualTolerance, kMaxRelativeTolerance, "/solver/residualTolerance");
  if (s.decrementTolerance)
    check::atMostReal(*s.decrementTolerance, kMaxRelativeTolerance, "/solver/decrementTolerance");
  requireOneOf(s.lineSearch, {"default", "none", "armijo", "residual", "wolfe"}, "/solver/lineSearch");
  requireOneOf(s.linearSolver, {"auto", "cholmod", "ldlt", "pcg"}, "/solver/linearSolver");
  requireOneOf(s.preconditioner, {"jacobi", "block_jacobi", "ic"}, "/solver/preconditioner");
  requireOneOf(s.psdProjection, {"auto", "none", "clamp", "abs"}, "/solver/psdProjection");
  requireOneOf(s.derivatives, {"analytic", "autodiff"}, "/solver/derivatives");
  requireOneOf(s.bendingHessian, {"exact", "gaussNewton"}, "/solver/bendingHessian");
  requireOneOf(s.fallbackBendingHessian, {"exact", "gaussNewton"}, "/solver/fallbackBendingHessian");
  requireOneOf(s.frictionHessian, {"exact", "majorizer"}, "/solver/frictionHessian");
  requireOneOf(s.evaluator, {"perFace", "staged"}, "/solver/evaluator");
  check::atLeast(s.threads, 0, "/solver/threads");
  check::atMost(s.threads, limits.maxThreads, "/solver/threads");
  check::atLeast(scene.outputs.frameStride, 1, "/outputs/frameStride");
  check::atMost(scene.outputs.frameStride, limits.maxSteps, "/outputs/frameStride");
}

std::vector<std::string> unsupportedFeatures(const Scene& scene) {
  std::vector<std::string> notes;
  const AnalysisType type = scene.analysis.type;
  if (type == AnalysisType::Dynamic) return notes;
  for (const VolumeActorParams& v : scene.volumes) {
    if (rigidPath(v).isStatic()) continue;
    if (type == AnalysisType::DynamicRelaxation) {
      notes.push_back("volume actor '" + v.name + "' does not move in a " + toString(type) +
                      " analysis: it is held where it is at t = 0");
    } else if (v.keyframes.empty()) {
      notes.push_back("volume actor '" + v.name + "' moves by constant velocities in dynamic analyses only: this "
                      "static analysis holds it where it is at t = 0 (a static path moves a solid along its "
                      "keyframes, their times read as load factors)");
    } else if (v.keyframes.back().time > 1.0) {
      notes.push_back("volume actor '" + v.name + "': a static path reads its keyframes' times as load factors, "
                      "which end at 1, so it goes only as far as its path takes it by t = 1");
    }
  }
  return notes;
}

PathClock pathClock(AnalysisType t) {
  switch (t) {
    case AnalysisType::Static: return PathClock::LoadFactor;
    case AnalysisType::Dynamic: return PathClock::Time;
    case AnalysisType::DynamicRelaxation: return PathClock::Held;
  }
  return PathClock::Held;
}

RigidPath rigidPath(const VolumeActorParams& p, AnalysisType t) { return rigidPath(p).readBy(pathClock(t)); }

const char* toString(AnalysisType t) {
  switch (t) {
    case AnalysisType::Static: return "static";
    case AnalysisType::Dynamic: return "dynamic";
    case AnalysisType::DynamicRelaxation: return "dynamicRelaxation";
  }
  return "?";
}

const char* toString(Integrator i) { return i == Integrator::BackwardEuler ? "backwardEuler" : "bdf2"; }

const char* toString(LoadCondition::Distribution d) {
  switch (d) {
    case LoadCondition::Distribution::Uniform: return "uniform";
    case LoadCondition::Distribution::EdgeLength: return "edgeLength";
    case LoadCondition::Distribution::Area: return "area";
    case LoadCondition::Distribution::PerVertex: return "perVertex";
  }
  return "?";
}

}  // namespace jetshell
