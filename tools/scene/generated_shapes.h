// Shapes from the built-in generators (core/mesh_generators.h), with named vertex groups for their boundaries
// so scenes can select, say, the loaded side of a slit without counting indices.
#pragma once

#include "core/mesh_generators.h"
#include "tools/scene/shapes.h"

namespace jetshell {

/// Groups: "left" (x = 0), "right" (x = width), "bottom" (y = 0), "top" (y = height).
ShapeHandle makeRectangleShape(double width, double height, int nx, int ny,
                               QuadDiagonals diagonals = QuadDiagonals::Uniform);

/// Groups: "inner", "outer" (the circles), "slitStart" (θ = 0 side), "slitEnd" (θ = 2π side).
ShapeHandle makeSlitAnnulusShape(double innerRadius, double outerRadius, int rings, int nodesPerRing,
                                 QuadDiagonals diagonals = QuadDiagonals::Uniform,
                                 RingSpacing spacing = RingSpacing::Uniform);

/// Groups: "start" (y = 0), "end" (y = length); panels also "sideStart" (θ = −arc/2) and "sideEnd" (θ = arc/2).
ShapeHandle makeCylinderShape(double radius, double length, double arcRadians, int nAround, int nAlong,
                              QuadDiagonals diagonals = QuadDiagonals::Uniform);

/// Groups: "equator" (z = 0), "pole" (closed cap) or "hole" (the opening's rim); with a partial azimuth also
/// "azimuthStart" (θ = 0) and "azimuthEnd" (θ = azimuth).
ShapeHandle makeHemisphereShape(double radius, int rings, int segments, double holeRadians, double azimuthRadians,
                                QuadDiagonals diagonals = QuadDiagonals::Uniform);

/// A T-shirt (core/garment_generator.h): resolution cells per 5 cm, panels 2·gap apart at rest.
/// Groups: "neck", "waist", "cuffs" (the openings' rims).
ShapeHandle makeTShirtShape(int resolution, double gap = 0.03);

}  // namespace jetshell
