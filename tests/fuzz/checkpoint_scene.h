// The scene the checkpoint harness reads checkpoints against (4 vertices, one probe, two shell actors, steps of
// 0.01 s for 0.1 s), shared with the test that checks its seeds are checkpoints of it.
#pragma once

#include "tools/output/run_checkpoint.h"

namespace jetshell::fuzz {

inline CheckpointScene checkpointScene() {
  CheckpointScene s;
  s.fingerprint = "0123456789abcdef";
  s.vertices = 4;
  s.timeStep = 0.01;
  s.duration = 0.1;
  s.probes = 1;
  s.frameFiles = 2;
  s.maxSteps = 10'000'000;
  s.cutReasons = {"iteration_cap", "line_search_failure", "linear_solver_failure", "non_finite", "stalled"};
  return s;
}

}  // namespace jetshell::fuzz
