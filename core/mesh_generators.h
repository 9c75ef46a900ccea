// Built-in mesh generators (reference configurations for examples, tests and benchmarks).
//
// Every generator documents its vertex numbering, so scenes can select vertices by index ranges, and orients
// its triangles so that the normals point the stated way. Invalid parameters throw InputError naming them,
// including a resolution whose mesh would exceed inputLimits().maxVertices or maxFaces (checked before anything
// is allocated).
#pragma once

#include "core/mesh.h"

#include <string>

namespace jetshell {

/// How the structured generators split each quad (i, j)–(i+1, j+1) of their parameter grid into two triangles.
/// Alternating: the diagonal flips from quad to quad (a symmetric pattern). Uniform: every quad along its
/// (i, j)–(i+1, j+1) diagonal. On alternating meshes the discrete second fundamental form overestimates a twist
/// (z = k·x·y along the grid lines) by 2× at every resolution, so torsion-dominated problems (the slit annular
/// plate) come out too stiff; uniform diagonals do not have that bias (VALIDATION.md, "Quad diagonals"), so they
/// are every generator's default.
enum class QuadDiagonals { Alternating, Uniform };

/// "alternating" or "uniform"; throws InputError otherwise.
QuadDiagonals quadDiagonalsFromString(const std::string& name);
const char* toString(QuadDiagonals d);

/// A rectangle [0, width] × [0, height] in the z = 0 plane, nx × ny squares, each split into two triangles
/// (uniform diagonals), normals +z. Vertex (i, j) has index j·(nx+1) + i.
TriMesh makeRectangleGrid(double width, double height, int nx, int ny);
/// The same grid and numbering with the chosen diagonals.
TriMesh makeRectangleGrid(double width, double height, int nx, int ny, QuadDiagonals diagonals);

/// How the rings of makeSlitAnnulus are spaced between its two free edges: Uniform, t_r = r/(rings − 1); Cosine,
/// t_r = ½(1 − cos(π r/(rings − 1))), fine at both edges, where a bent and twisted plate's boundary layers sit
/// (the slit annular plate within 1% at every level on 10 × 128 quads against 16 × 256 with uniform rings;
/// VALIDATION.md).
enum class RingSpacing { Uniform, Cosine };

/// "uniform" or "cosine"; throws InputError otherwise.
RingSpacing ringSpacingFromString(const std::string& name);
const char* toString(RingSpacing s);

/// An annulus innerRadius ≤ r ≤ outerRadius in the z = 0 plane, cut by a radial slit along the +x axis.
/// `rings` circles of `nodesPerRing` nodes each; node j of ring r (r = 0 innermost) sits at radius
/// innerRadius + (outerRadius − innerRadius)·t_r (t_r by `spacing`) and angle θ = 2π·j/(nodesPerRing − 1), index
/// r·nodesPerRing + j. Columns j = 0 and j = nodesPerRing − 1 coincide in position but are distinct vertices, so
/// the mesh is cut along the slit (θ = 0 side and θ = 2π side). Normals +z. Needs rings ≥ 2, nodesPerRing ≥ 4.
TriMesh makeSlitAnnulus(double innerRadius, double outerRadius, int rings, int nodesPerRing,
                        QuadDiagonals diagonals = QuadDiagonals::Uniform, RingSpacing spacing = RingSpacing::Uniform);

/// A cylinder (or cylindrical panel) of the given radius with its axis along y, 0 ≤ y ≤ length. The angle θ
/// is measured from +z towards +x: a point is (R sin θ, y, R cos θ), θ ∈ [−arc/2, arc/2], so a panel's apex is
/// on +z. nAround × nAlong quads (uniform diagonals by default), normals outward. Node (i around, j along) has index
/// j·columns + i with columns = nAround + 1 for a panel and nAround when arcRadians is 2π (closed: no seam).
TriMesh makeCylinder(double radius, double length, double arcRadians, int nAround, int nAlong,
                     QuadDiagonals diagonals = QuadDiagonals::Uniform);

/// A spherical cap of the given radius centred at the origin, from the polar angle holeRadians (0: closed at
/// the pole +z) down to the equator z = 0, over the azimuth [0, azimuthRadians] (2π: closed around, no seam).
/// `rings` quads from hole to equator, `segments` around, normals outward (the pole's fan is the same for both
/// diagonal choices). Numbering: with a closed pole,
/// vertex 0 is the pole and ring k ≥ 1 node i has index 1 + (k−1)·columns + i; with a hole, ring k (k = 0 at
/// the hole) node i has index k·columns + i; columns = segments, or segments + 1 when the azimuth is open.
TriMesh makeHemisphere(double radius, int rings, int segments, double holeRadians = 0.0,
                       double azimuthRadians = 2.0 * 3.14159265358979323846,
                       QuadDiagonals diagonals = QuadDiagonals::Uniform);

}  // namespace jetshell
