// Everything a run writes into its output directory, each file atomically (frames.pvd and probes.csv grow by
// appends that leave them complete: tools/output/append_file.h):
//   frames/frame_NNNNN.vtu + frames.pvd   VTK XML frames and their time series (ParaView); with several shell
//                                         actors one file per actor and frame, frames/frame_NNNNN_aK.vtu (K the
//                                         actor's index), each a part of the series named after its actor, so
//                                         ParaView shows one block per actor
//   volumes.vtu                           the rigid volume actors that stay where they are (a part of the series),
//                                         when the scene has any
//   frames/volumes_NNNNN.vtu              in dynamics, the volume actors that move, where they are at each frame
//                                         (the series' last part)
//   obj/frame_NNNNN.obj                   optional OBJ per frame, with the volume actors beside it:
//                                         obj/volumes.obj (those that stay), obj/volumes_NNNNN.obj (those that move)
//   probes.csv                            per step: the probes' displacements and the contact force each volume
//                                         actor takes from the shells; each row appended as it is recorded (the
//                                         run keeps only the last and the plots' rows: tools/output/plot_rows.h)
//   summary.json                          the run's outcome (see RunSummary), with one entry per shell actor
//                                         (name, layer, size, largest displacement and speed, bounding box)
#pragma once

#include "tools/output/append_file.h"
#include "tools/output/run_checkpoint.h"
#include "tools/output/vtu.h"
#include "tools/scene/scene.h"
#include "tools/scene/scene_model.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace jetshell {

/// The state after one step (load step, time step or relaxation step).
struct StepState {
  int step = 0;             // 1-based; 0 is the initial state
  double time = 0.0;        // s (dynamics); the load factor in statics
  double loadFactor = 1.0;  // λ
  const Eigen::VectorXd* x = nullptr;         // 3N positions
  const Eigen::VectorXd* velocity = nullptr;  // 3N, or null in statics
};

/// Up to this many shell actors, each frame is one .vtu per actor (a named block each in ParaView); with more,
/// one .vtu a frame holds them all and its `actor` cell array tells them apart.
constexpr std::size_t kMaxFramePartActors = 64;

/// How the run ended, for summary.json.
struct RunSummary {
  bool converged = false;
  std::string termination;  // "converged", "interrupted", "max_steps", "solver_failure: ...", "completed"
  int steps = 0;
  int newtonIterations = 0;
  double wallSeconds = 0.0;
  std::vector<std::string> activeTerms;
  nlohmann::json extra = nlohmann::json::object();  // merged into summary.json
};

/// The contact force each of the measured volume actors takes from the shells at positions x (3N) and time t (the
/// time the solids' paths are read at: λ on a static path), in the order they were named [N].
using ContactForceGauge = std::function<std::vector<Eigen::Vector3d>(const Eigen::VectorXd& x, double t)>;

class RunOutput {
 public:
  /// Creates `directory` (and frames/, obj/ as needed). Throws InputError when it cannot.
  RunOutput(std::string directory, const Scene& scene, const SceneModel& model, std::string scenePath = "");

  /// Records the probes of this state (a row appended to probes.csv) and, every `frameStride` steps or when
  /// `forceFrame`, writes a frame (and appends it to frames.pvd). A step recorded again replaces its row.
  void record(const StepState& state, bool forceFrame = false);
  /// Records, in every row from now on, the contact force on each of `solids` (volume actors), read by `gauge` at
  /// the state's positions and time: three columns per solid in probes.csv, NAME_Fx, NAME_Fy, NAME_Fz. Called
  /// before the first record(); throws std::logic_error after it.
  void measureContactForces(std::vector<std::string> solids, ContactForceGauge gauge);
  /// The volume actors whose contact forces the rows hold (three values each, in this order).
  const std::vector<std::string>& contactSolids() const { return contactSolids_; }
  /// The rows the plots draw (PlotRows: evenly spaced buckets, the initial state's first), the last recorded row
  /// in the last bucket's range.
  PlotRows plotRows() const;
  /// The last recorded row, or none before the first record().
  const std::optional<ProbeRow>& lastRow() const { return lastRow_; }
  /// Writes summary.json (with the probes' last displacements).
  void finish(const RunSummary& summary);

  const std::string& directory() const { return directory_; }
  /// The most recent frame's files (one per shell actor with several actors), or none when none was written.
  const std::vector<std::string>& lastFrame() const { return lastFrame_; }
  /// The volume actors' files as the last frame shows them: volumes.vtu with those that stay where they are, the
  /// frame's volumes file with those that move; none when the scene has no volume actor.
  std::vector<std::string> volumeFiles() const;
  int framesWritten() const { return frames_; }
  /// The .vtu files of one frame: one per shell actor with 2 to kMaxFramePartActors actors, else one.
  int filesPerFrame() const;
  /// The last recorded displacement of each probe.
  std::map<std::string, Eigen::Vector3d> probeDisplacements() const;

  /// What a checkpoint needs to continue the outputs exactly (frame count, the last and the plots' rows, file
  /// sizes).
  OutputCheckpoint state() const;
  /// Continues the outputs of an earlier run of the same scene from its state() (as runCheckpointFromJson checks
  /// it): frames.pvd and probes.csv are cut back to their sizes at that point. Throws InputError when the files
  /// do not match it.
  void restore(const OutputCheckpoint& state);

 private:
  void writeFrame(const StepState& state);
  /// The moving volume actors as placed for the current frame (volumesFrame), written as
  /// frames/volumes_NNNNN.vtu; returns the file's name in the output directory.
  std::string writeMovingVolumes(const VtuFrame& placed);
  /// Whether probes.csv is written: the scene asks for it and it has columns beyond step, time and load factor.
  bool writesProbes() const;
  /// Appends `row` to probes.csv (created with its header by the first), or writes it over the last row.
  void appendProbeRow(const ProbeRow& row, bool overLastRow);
  /// One entry per shell actor: name, layer, vertex and face counts, and from the last recorded state the
  /// largest displacement from the reference, the largest speed (dynamics) and the bounding box.
  nlohmann::json actorSummaries() const;

  std::string directory_;
  std::string scenePath_;
  const Scene& scene_;
  const SceneModel& model_;
  AppendOnlyFile pvd_, probesCsv_;
  std::uint64_t lastRowOffset_ = 0;  // where the last row starts in probes.csv
  std::vector<std::string> lastFrame_;
  /// A volume actor's surface as placed at t = 0, its index among the scene's volume actors and its path.
  struct VolumePart {
    TriMesh surface;
    int index = 0;
    RigidPath path;
  };
  /// The parts placed where their paths put them at time t, as one mesh (its `volume` cell array the index).
  static VtuFrame volumesFrame(const std::vector<VolumePart>& parts, double t);
  std::vector<VolumePart> movingVolumes_;
  std::string staticVolumesFile_, movingVolumesFile_;  // "" when there are none (or no frame yet)
  int frames_ = 0;
  int lastFrameStep_ = -1;
  std::optional<ProbeRow> lastRow_;
  PlotRows plotRows_;
  std::vector<std::string> contactSolids_;
  ContactForceGauge contactForces_;
  Eigen::VectorXd lastPositions_, lastVelocities_;  // the last recorded state, for the per-actor summary
};

}  // namespace jetshell
