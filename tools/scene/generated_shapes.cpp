#include "tools/scene/generated_shapes.h"

#include "core/garment_generator.h"
#include "core/math_constants.h"
#include "core/mesh_generators.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace jetshell {
namespace {

using Groups = std::map<std::string, std::vector<int>>;

std::vector<int> sorted(std::vector<int> ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::vector<int> sequence(int count, const std::function<int(int)>& id) {
  std::vector<int> ids;
  for (int k = 0; k < count; ++k) ids.push_back(id(k));
  return sorted(std::move(ids));
}

}  // namespace

ShapeHandle makeRectangleShape(double width, double height, int nx, int ny, QuadDiagonals diagonals) {
  TriMesh m = makeRectangleGrid(width, height, nx, ny, diagonals);
  Groups g;
  g["left"] = sequence(ny + 1, [&](int j) { return j * (nx + 1); });
  g["right"] = sequence(ny + 1, [&](int j) { return j * (nx + 1) + nx; });
  g["bottom"] = sequence(nx + 1, [&](int i) { return i; });
  g["top"] = sequence(nx + 1, [&](int i) { return ny * (nx + 1) + i; });
  return CreateTriMeshShape(std::move(m), "generator rectangle", std::move(g));
}

ShapeHandle makeSlitAnnulusShape(double innerRadius, double outerRadius, int rings, int nodesPerRing,
                                 QuadDiagonals diagonals, RingSpacing spacing) {
  TriMesh m = makeSlitAnnulus(innerRadius, outerRadius, rings, nodesPerRing, diagonals, spacing);
  Groups g;
  g["inner"] = sequence(nodesPerRing, [&](int j) { return j; });
  g["outer"] = sequence(nodesPerRing, [&](int j) { return (rings - 1) * nodesPerRing + j; });
  g["slitStart"] = sequence(rings, [&](int r) { return r * nodesPerRing; });
  g["slitEnd"] = sequence(rings, [&](int r) { return r * nodesPerRing + nodesPerRing - 1; });
  return CreateTriMeshShape(std::move(m), "generator slitAnnulus", std::move(g));
}

ShapeHandle makeCylinderShape(double radius, double length, double arcRadians, int nAround, int nAlong,
                              QuadDiagonals diagonals) {
  TriMesh m = makeCylinder(radius, length, arcRadians, nAround, nAlong, diagonals);
  const bool closed = arcRadians >= kTwoPi * (1 - 1e-12);
  const int columns = closed ? nAround : nAround + 1;
  Groups g;
  g["start"] = sequence(columns, [&](int i) { return i; });
  g["end"] = sequence(columns, [&](int i) { return nAlong * columns + i; });
  if (!closed) {
    g["sideStart"] = sequence(nAlong + 1, [&](int j) { return j * columns; });
    g["sideEnd"] = sequence(nAlong + 1, [&](int j) { return j * columns + nAround; });
  }
  return CreateTriMeshShape(std::move(m), "generator cylinder", std::move(g));
}

ShapeHandle makeHemisphereShape(double radius, int rings, int segments, double holeRadians, double azimuthRadians,
                                QuadDiagonals diagonals) {
  TriMesh m = makeHemisphere(radius, rings, segments, holeRadians, azimuthRadians, diagonals);
  const bool closedAround = azimuthRadians >= kTwoPi * (1 - 1e-12);
  const bool pole = holeRadians == 0.0;
  const int columns = closedAround ? segments : segments + 1;
  // Ring k's first vertex, following the numbering documented in core/mesh_generators.h.
  auto ringStart = [&](int k) { return pole ? 1 + (k - 1) * columns : k * columns; };
  Groups g;
  g["equator"] = sequence(columns, [&](int i) { return ringStart(rings) + i; });
  if (pole) {
    g["pole"] = {0};
  } else {
    g["hole"] = sequence(columns, [&](int i) { return i; });
  }
  if (!closedAround) {
    const int first = pole ? 1 : 0;
    g["azimuthStart"] = sequence(rings + 1 - first, [&](int k) { return ringStart(k + first); });
    g["azimuthEnd"] = sequence(rings + 1 - first, [&](int k) { return ringStart(k + first) + segments; });
  }
  return CreateTriMeshShape(std::move(m), "generator hemisphere", std::move(g));
}

}  // namespace jetshell

namespace jetshell {

ShapeHandle makeTShirtShape(int resolution, double gap) {
  GarmentMesh g = makeTShirt(resolution, gap);
  Groups groups;
  groups["neck"] = sorted(g.neck);
  groups["waist"] = sorted(g.waist);
  groups["cuffs"] = sorted(g.cuffs);
  return CreateTriMeshShape(std::move(g.mesh), "generator tshirt", std::move(groups));
}

}  // namespace jetshell
