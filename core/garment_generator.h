// A T-shirt: front and back panels with sleeves, joined at the shoulder, under-sleeve and side seams into one
// manifold triangle mesh open at the neck, the waist and both cuffs.
//
// Outline (local x across, y up, metres): body |x| ≤ 0.25, 0 ≤ y ≤ 0.7; sleeves 0.25 ≤ |x| ≤ 0.45,
// 0.5 ≤ y ≤ 0.7; neck opening |x| < 0.1 on the top edge. Both panels are grids of square cells of side
// h = 0.05 / resolution (each cell split along alternating diagonals); the outline's vertices on seams are
// shared by the two panels, the others (neck, waist, cuffs, interior) are duplicated. The panels bulge apart:
// the front lies at z = +gap·s, the back at z = −gap·s, with s rising from 0 on the seams to 1 three cells
// inside, so the rest shape is a flattened tube (a worn garment) and front and back start 2·gap apart.
// Vertices (numbered front panel first, then the back panel's own vertices): about 0.86 / h² in all;
// resolution 4 (h = 1.25 cm) gives ≈ 5,400. Normals of the front panel point +z, of the back −z (outward).
#pragma once

#include "core/mesh.h"

#include <vector>

namespace jetshell {

struct GarmentMesh {
  TriMesh mesh;
  std::vector<int> neck, waist, cuffs;  // vertices on the openings' rims
};

/// resolution ≥ 1 cells per 5 cm (≤ 40); gap ≥ 0 [m]. Throws InputError otherwise.
GarmentMesh makeTShirt(int resolution, double gap = 0.03);

}  // namespace jetshell
