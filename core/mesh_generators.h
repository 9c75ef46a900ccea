// Built-in mesh generators (reference configurations for examples, tests and benchmarks).
#pragma once

#include "core/mesh.h"

namespace jetshell {

/// A rectangle [0, width] × [0, height] in the z = 0 plane, nx × ny squares, each split into two triangles
/// (alternating diagonals), normals +z. Vertex (i, j) has index j·(nx+1) + i.
TriMesh makeRectangleGrid(double width, double height, int nx, int ny);

}  // namespace jetshell
