// Runs a scene: builds the solver's shell system from the scene model, solves the analysis (load stepping,
// implicit dynamics or dynamic relaxation), logs one line per step and writes the outputs (tools/output).
#pragma once

#include "tools/output/run_output.h"
#include "solvers/dynamics.h"
#include "solvers/newton.h"
#include "solvers/shell_system.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <iosfwd>
#include <string>

namespace jetshell {

struct RunOptions {
  std::string outputDirectory;
  std::string scenePath;     // recorded in summary.json
  int stepLimit = 0;         // > 0: stop after this many steps (quick checks and tests)
  bool progressBar = false;  // draw a progress bar (on a terminal)
  bool pictures = true;      // final.png and probes.png (when the scene's outputs ask for them)
  std::ostream* log = nullptr;  // log lines; null: silent
  /// Dynamics: write outputDirectory/checkpoint.cbor every this many steps (0: never; when resuming, 0 keeps the
  /// interrupted run's cadence). tools/output/checkpoint.h
  int checkpointEvery = 0;
  /// Dynamics: continue from outputDirectory's checkpoint; with the interrupted run's cadence the run ends bit for
  /// bit as an uninterrupted one.
  bool resume = false;
  /// Identifies the scene in checkpoints (a resume with another scene is refused); e.g. fingerprint(file text).
  std::string sceneFingerprint;
};

struct RunResult {
  RunSummary summary;
  bool interrupted = false;
  bool stepLimitReached = false;
  std::vector<std::string> lastFrame;  // the last frame's .vtu files (one per shell actor when several), or none
  std::string finalPng;    // or "" when not drawn
  std::string probesPng;   // or ""
  std::string contactForcesPng;  // or ""
  std::vector<std::string> notes;     // unsupported features, steps moved on unconverged, picture problems
  std::vector<std::string> warnings;  // doubts about the result (inverted faces); also in summary.json
};

/// Newton options from a scene's solver settings (defaultIterations when the scene sets none). psdProjection
/// "auto": none on static paths (`statics`; the projected Hessian makes Newton linear near large-rotation
/// equilibria: 2x the iterations, and stalls; VALIDATION.md), clamp otherwise.
NewtonOptions newtonOptionsFor(const SolverSettings& settings, int defaultIterations, bool statics = false);

/// Time-stepping options from a dynamic scene: its integrator, time step, Newton settings and iteration-cap
/// outcome, as `jetshell run` uses them (and `jetshell fit` and `bench contact` with it).
DynamicsOptions dynamicsOptionsFor(const Scene& scene);

/// Runs the scene. Throws InputError for scenes the solver cannot take yet (see SCENES.md: shell actors with
/// different materials or gravity flags), for static problems with an unbalanced rigid-body mode
/// (tools/scene/support_check.h), and for unwritable outputs. Ctrl-C (after installInterruptHandler())
/// stops after the current step, with its frame written.
RunResult runScene(const Scene& scene, const RunOptions& options);

}  // namespace jetshell
