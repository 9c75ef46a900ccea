// Element stencils: which vertices each element of an energy term touches.
#pragma once

#include <vector>

namespace jetshell {

/// A table of elements × width vertex ids; -1 marks an absent vertex (e.g. across a boundary edge).
struct StencilTable {
  int width = 0;
  std::vector<int> ids;  // element-major
  int size() const { return width == 0 ? 0 : static_cast<int>(ids.size()) / width; }
  const int* element(int e) const { return ids.data() + static_cast<std::size_t>(e) * width; }
};

}  // namespace jetshell
