// libFuzzer harness: any bytes as a run's checkpoint file (what `jetshell run --resume` reads), parsed and every
// field read against a small scene (tests/fuzz/checkpoint_scene.h). Only InputError may come
// out; anything else (a crash, a sanitizer report, another exception, a hang, memory beyond libFuzzer's
// -rss_limit_mb) is a defect. The seeds are checkpoints of that scene.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/mesh.h"
#include "tests/fuzz/checkpoint_scene.h"
#include "tools/output/run_checkpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace jetshell;
  static const CheckpointScene scene = fuzz::checkpointScene();
  try {
    const RunCheckpoint c = runCheckpointFromJson(
        parseCheckpoint(std::string(reinterpret_cast<const char*>(data), size), "fuzz.cbor"), scene, "fuzz.cbor");
    // What the run then relies on.
    const OutputCheckpoint& o = c.output;
    if (c.solver.x.size() != 12 || !o.plotRows.consistent() || !o.lastRow || o.lastRow->u.size() != 3 ||
        (o.probesBytes ? o.lastRowOffset > *o.probesBytes : o.lastRowOffset != 0))
      __builtin_trap();
  } catch (const InputError&) {
  }
  return 0;
}
