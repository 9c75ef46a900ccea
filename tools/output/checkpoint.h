// Checkpoints of dynamic runs: `jetshell run --checkpoint-every N` writes DIR/checkpoint.cbor (atomically) every
// N steps; `--resume DIR` continues from it and ends bit for bit where the uninterrupted run would have.
//
// The file is CBOR (binary JSON: doubles stored exactly) holding the solver's state (positions, velocities, time,
// BDF2 history), the run's counters, the probe history and the output writer's state (frame count, probe rows,
// the sizes of frames.pvd and probes.csv to cut back to), with a fingerprint of the scene it belongs to.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace jetshell {

/// The checkpoint file of an output directory.
std::string checkpointPath(const std::string& directory);

/// Writes the checkpoint atomically (`state` by value: a run's is a temporary, moved in, not copied). Throws
/// InputError naming the file when it cannot.
void writeCheckpoint(const std::string& directory, nlohmann::json state);

/// Reads it back. Throws InputError naming the file when it is missing, unreadable or not a checkpoint. Its
/// fields are read by runCheckpointFromJson (tools/output/run_checkpoint.h).
nlohmann::json readCheckpoint(const std::string& directory);

/// FNV-1a of a text, as 16 hex digits: a scene's fingerprint.
std::string fingerprint(const std::string& text);

}  // namespace jetshell
