// What an earlier run left in an output directory. A run writes its frames one file each (frames/frame_NNNNN.vtu),
// so a second run into the same directory that writes fewer frames, or no pictures, would leave the first run's
// beside its own: a frame series that ParaView groups by name mixes the two runs, and a final.png shows a state
// the new summary.json knows nothing of. A run that does not resume therefore removes them first.
#pragma once

#include <string>

namespace jetshell {

/// Removes the files a run writes from `directory`: summary.json, frames.pvd, probes.csv, final.png, probes.png,
/// contact_forces.png, volumes.vtu, checkpoint.cbor; in frames/ and obj/ the numbered frames and moving volumes
/// (frame_NNNNN.vtu/.obj, volumes_NNNNN.vtu/.obj) and obj/volumes.obj; and the temporary files of an interrupted
/// atomic write of any of these (NAME.tmpPID). Nothing else: other files, other folders, and what a link points
/// to stay (a link named like a run's file is removed, not followed; frames/ or obj/ as a link is not entered).
/// Returns how many files it removed; throws InputError naming a file it cannot remove.
int removeEarlierRunFiles(const std::string& directory);

/// Whether `directory` holds a run that `--resume` can continue and that did not finish: its checkpoint.cbor,
/// with no summary.json (the run was killed before it wrote one: a run removes the earlier summary first) or
/// one that is unreadable or says `"termination": "interrupted"`. Empty when not; else what it holds, for a
/// message. A new run there would remove that checkpoint, so the caller refuses it.
std::string unfinishedRunIn(const std::string& directory);

}  // namespace jetshell
