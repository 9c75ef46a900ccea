// What a dynamic run's checkpoint holds (tools/output/checkpoint.h writes and reads the file), as typed data, and
// the one place that knows its fields. `run --resume` continues from a checkpoint read back through
// runCheckpointFromJson, which checks every field against the scene it is resumed with: each vector's length and
// finiteness, each count's range, the probe rows against the probes, and the last frame's files
// (inside the output directory's frames/). A checkpoint edited by hand or damaged is refused with the field's
// name; nothing of it reaches the solver or the outputs unchecked.
//
// Data flow: DynamicsSolver::snapshot() + RunOutput::state() + SafeguardReport::state() + the run's counters
// -> RunCheckpoint -> toJson -> CBOR file; and back: CBOR file -> parseCheckpoint -> runCheckpointFromJson ->
// DynamicsSolver::restore, RunOutput::restore, SafeguardReport::restore.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "tools/output/plot_rows.h"

namespace jetshell {

/// The run a checkpoint must belong to: it is refused when it was written for another one.
struct CheckpointScene {
  std::string fingerprint;  // of the scene file's text (checkpoint.h: fingerprint)
  int vertices = 0;
  double timeStep = 0.0;  // s
  double duration = 0.0;  // s
  int probes = 0;
  int contactSolids = 0;                // volume actors whose contact force probes.csv records (RunOutput)
  int frameFiles = 1;                   // .vtu files a frame (one per shell actor when several: RunOutput)
  int maxSteps = 0;                     // InputLimits::maxSteps
  std::vector<std::string> cutReasons;  // the reasons a step can be cut for (SafeguardReport::cutReasons)
};

/// DynamicsSolver::Snapshot's fields.
struct SolverCheckpoint {
  Eigen::VectorXd x, v, xPrev, vPrev;  // 3N each; the previous step's only when historyValid (else empty)
  double t = 0.0, historyStep = 0.0;
  int steps = 0;
  bool historyValid = false;
};

/// SafeguardReport's counts.
struct SafeguardCounts {
  std::map<std::string, int> cuts;  // failed solves that cut their step, by termination reason
  int nonFiniteTrials = 0, regularizedSolves = 0, regularizations = 0, projectionFallbacks = 0;
  int directFallbacks = 0, acceptedAtCap = 0, solvedAgain = 0;
  double largestShift = 0.0;
};

/// RunOutput's state: what it needs to continue the output files exactly. probes.csv holds every row already; the
/// checkpoint holds the last one and the plots' (tools/output/plot_rows.h), so its size does not grow with the run.
struct OutputCheckpoint {
  int frames = 0, lastFrameStep = -1;
  std::vector<std::string> lastFrame;  // relative to the output directory: frames/NAME.vtu
  std::optional<ProbeRow> lastRow;     // the last recorded row; none before the first
  PlotRows plotRows;
  std::optional<std::uint64_t> pvdBytes, probesBytes;  // the files' sizes, when they were open
  std::uint64_t lastRowOffset = 0;  // where the last row starts in probes.csv (when it is open)
};

struct RunCheckpoint {
  SolverCheckpoint solver;
  int checkpointEvery = 0;  // the run's --checkpoint-every, which a run resumed from here keeps unless told otherwise
  int newtonIterations = 0, cuts = 0, stepsAtIterationCap = 0;
  double worstResidualOverTolerance = 0.0;
  SafeguardCounts safeguards;
  OutputCheckpoint output;
};

/// The checkpoint as a JSON document (checkpoint.h writes it as CBOR, doubles exact, with the version key).
nlohmann::json toJson(const RunCheckpoint& checkpoint, const CheckpointScene& scene);

/// Reads it back, checking every field against `scene`. Throws InputError naming `file` and the field.
RunCheckpoint runCheckpointFromJson(const nlohmann::json& j, const CheckpointScene& scene, const std::string& file);

/// A checkpoint file's bytes as a JSON document: CBOR nested no deeper than scene files, carrying this build's
/// checkpoint version. Throws InputError naming `file` otherwise.
nlohmann::json parseCheckpoint(const std::string& bytes, const std::string& file);

/// The version key written into every checkpoint.
constexpr const char* kCheckpointVersionKey = "jetshell_checkpoint";
// 3: each plot row with its bucket's range, packed, and the run's checkpoint cadence; 2: the probe rows in
// probes.csv only; 1: all rows, twice.
constexpr int kCheckpointVersion = 3;

}  // namespace jetshell
