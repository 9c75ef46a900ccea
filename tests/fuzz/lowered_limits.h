// The mesh bounds the scene-reading harnesses run with: smaller than the program's, so that every input stays
// cheap (the bounds themselves are what is tested: a generator beyond them must be rejected before it allocates).
#pragma once

#include "core/input_limits.h"

namespace jetshell::fuzz {

/// Lowers inputLimits()'s vertex and face bounds once per process.
inline void lowerMeshLimits() {
  static const bool lowered = [] {
    inputLimits().maxVertices = 20000;
    inputLimits().maxFaces = 40000;
    return true;
  }();
  (void)lowered;
}

}  // namespace jetshell::fuzz
