// Re-triangulates the structured quad grids of the built-in generators with every diagonal in the same
// direction.
//
// The generators (core/mesh_generators.h) split quads with alternating diagonals. On such a mesh the
// discrete second fundamental form overestimates the twist (z = k·x·y along the grid lines) by exactly 2×
// at every resolution: its energy is 2·(½β·2k²) per unit area at 8×8 and at 32×32 quads, where one
// diagonal direction gives 1.125× and 1.031× (the boundary deficit only). Torsion-dominated benchmarks (the
// slit annular plate) therefore converge to a result about 25% too stiff on alternating meshes. A stopgap until
// the generators offer the choice (requested in VALIDATION.md).
#pragma once

#include "core/mesh.h"

#include <functional>
#include <string>

namespace jetshell::validation {

enum class Diagonals { Alternating, Uniform };
const char* toString(Diagonals d);
/// "alternating" or "uniform"; throws InputError otherwise.
Diagonals parseDiagonals(const std::string& s);

/// Faces of an nu × nv quad grid whose corner (i, j) is vertex id(i, j), every quad split along its
/// (i, j)–(i+1, j+1) diagonal, oriented by the right-hand rule on (u, v) like the generators.
Faces uniformDiagonalFaces(int nu, int nv, const std::function<int(int, int)>& id);

}  // namespace jetshell::validation
