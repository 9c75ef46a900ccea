// The stress matrix of `jetshell stress` (STABILITY.md): small scenes at the edges of what the solvers take —
// thickness-to-size ratio, Young's modulus, Poisson's ratio, time step, load stepping, sliver triangles, rest
// meshes folded near 180°, crumpled states, unsupported and inverting loads, contact (penalty stiffness, friction,
// fast and spinning solids, two cloths), dynamic relaxation and path following — each run through the same path
// as `jetshell run` and judged:
//   ok              the run completed (converged, or every requested step done)
//   failed_cleanly  the run stopped with a stated reason (not converged, refused input), no NaN anywhere
// Anything else is a defect: NaN in an output file, an exception that is not an input error, a crash, a run over
// its wall-clock budget.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace jetshell {

struct StressCell {
  std::string name;      // unique, e.g. "thickness/h_L=1e-05"
  std::string what;      // one line: what the cell probes
  nlohmann::json scene;  // a scene document (SCENES.md)
  int stepLimit = 0;     // > 0: stop after this many steps (dynamic cells)
  bool quick = false;    // part of the reduced matrix (CTest)
};

/// The full matrix, or the reduced one of a few seconds (quick).
std::vector<StressCell> stressCells(bool quick);

/// Runs one cell in this process: solves it into outputDirectory, scans every output for NaN or infinity and
/// returns {name, outcome, reason, steps, newton_iterations, termination, inverted_faces, warnings}. Never
/// throws for what the scene does; outcome "defect" says what went wrong.
nlohmann::json runStressCell(const StressCell& cell, const std::string& outputDirectory);

/// The output files of a run directory holding a non-finite number ("" when clean): "nan"/"inf" tokens in
/// .vtu, .pvd, .csv and .obj files, null numbers in summary.json.
std::string findNonFinite(const std::string& directory);

}  // namespace jetshell
