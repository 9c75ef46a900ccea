// The fit file (FITTING.md): a static scene (by path or inline), the material parameters to fit with bounds
// and scales, the observations (probe displacements at load levels, target shapes from OBJ files, a CSV
// load–displacement curve), the algorithm and its tolerances. Read strictly, like scenes: unknown keys,
// wrong types and out-of-range values are one-line errors naming the JSON pointer (file:line for CSV rows), and
// every count is bounded.
#pragma once

#include "tools/fit/fit_options.h"
#include "tools/fit/material_base.h"
#include "tools/scene/scene.h"

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace jetshell {

/// Bounds on the fit file's counts.
constexpr int kMaxFitObservations = 1000;   // entries of "observations"
constexpr double kMaxObservationWeight = 1e12;  // an observation's weight (its square scales the misfit)
constexpr int kMaxCurvePoints = 10000;      // rows of one CSV curve
constexpr int kMaxFitLevels = 200;          // distinct load levels over all observations

struct FitParameterSpec {
  std::string actor;  // shell actor name
  std::string name;   // youngsModulus, ... (tools/fit/material_mapping.h)
  std::string load;   // loadScale only: the named load it scales (empty: all the scene's applied loads)
  FitVariable variable;
  std::string where;  // JSON pointer
};

/// One observation as read; coordinates are resolved against the scene model later (tools/fit/fit_setup.h).
struct ObservationSpec {
  enum class Kind { Probe, Shape, Curve };
  Kind kind = Kind::Probe;
  std::string where;
  double weight = 1.0;
  // Probe and Curve:
  std::string probe;
  std::vector<int> components;  // 0, 1, 2
  // Probe: one level and the displacement of each listed component (same order as `components`).
  // Curve: one level and one displacement per point (a single component).
  std::vector<double> levels;
  std::vector<Eigen::Vector3d> displacements;
  // Shape:
  std::string actor;
  Eigen::MatrixXd targetPositions;  // N_actor × 3 (world coordinates)
};

struct FitFile {
  std::string path;
  std::string description;
  Scene scene;
  MaterialBase material;  // the fitted actor's material as the scene gives it
  std::vector<FitParameterSpec> parameters;
  std::vector<ObservationSpec> observations;
  FitOptions options;
  bool plots = true;
};

/// The rows of a curve observation's CSV text (`path` names it in messages, file:line): blank lines, lines
/// starting with '#' and the first other line when it starts with no number (a header) are skipped; each other
/// row gives a load factor in [0, 100] (column loadColumn, increasing) and a displacement (column valueColumn,
/// times scale, at most inputLimits().maxDistance in size) along `component`. Appended to s.levels and
/// s.displacements, at most kMaxCurvePoints. InputError naming file:line otherwise.
void readCurveRows(const std::string& text, const std::string& path, int loadColumn, int valueColumn, int component,
                   double scale, ObservationSpec& s);

/// Reads a fit file; relative paths (scene, OBJ, CSV) are relative to its directory.
FitFile loadFitFile(const std::string& path);
/// The same from parsed JSON.
FitFile fitFromJson(const nlohmann::json& document, const std::string& baseDirectory, const std::string& name);

}  // namespace jetshell
