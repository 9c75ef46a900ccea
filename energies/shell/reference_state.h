// Per-face reference-state quantities of a shell: rest area, reference metric A and its inverse, and the rest
// second fundamental form B (so curved rest shapes work: the energy sees κ = B − b).
#pragma once

#include "core/mesh.h"
#include "core/topology.h"

#include <array>
#include <vector>

namespace jetshell {

/// Symmetric 2×2 tensors are stored as (t00, t01, t11).
using Sym2 = std::array<double, 3>;

struct ShellReference {
  std::vector<double> area;         // rest area per face
  std::vector<Sym2> metric;         // A = [e_a · e_b]
  std::vector<Sym2> inverseMetric;  // A⁻¹
  std::vector<Sym2> secondFundamentalForm;  // B, from the reference mid-edge normals
};

/// Computes the reference state from the mesh's rest positions. The bending stencil and B use the same
/// templated geometry as the energy (energies/shell/shell_geometry.h).
ShellReference computeReference(const TriMesh& mesh, const Topology& topology);

}  // namespace jetshell
