// Triangle-mesh shapes of shell actors (the spec's TriangularMeshShape and CreateTriMeshShape).
#pragma once

#include "core/mesh.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

/// A validated triangle mesh in actor-local coordinates, with optional named vertex groups (the built-in
/// generators name their boundaries, e.g. a slit annulus's "slitStart" and "slitEnd", so scenes can select them).
struct TriangularMeshShape {
  TriMesh mesh;
  std::string source;                                   // "file.obj", "generator slitAnnulus", "arrays"
  std::map<std::string, std::vector<int>> vertexGroups;  // sorted vertex ids
};

/// Shared and immutable, like the spec's ShapeHandle: several actors may use one shape.
using ShapeHandle = std::shared_ptr<const TriangularMeshShape>;

/// A shape from vertex positions (N×3) and faces (F×3). Throws InputError when the mesh is invalid (index out
/// of range, degenerate or non-manifold faces, inconsistent orientation, non-finite coordinates, a coordinate
/// beyond inputLimits().maxDistance metres, empty).
ShapeHandle CreateTriMeshShape(const Positions& vertices, const Faces& faces);

/// A shape read from a Wavefront OBJ file, its coordinates multiplied by `scale` (0.01 for a file in
/// centimetres). Throws InputError naming the file and line on any problem.
ShapeHandle CreateTriMeshShape(const std::string& objPath, double scale = 1.0);

/// The shape with the vertices that lie on one another with no edge between them merged (tools/scene/open_seams.h),
/// its source "<source>, N vertices welded into M". Throws InputError when there are too many to weld, or when
/// the welded mesh is invalid (two panels that face opposite ways, a seam that pinches three faces onto an edge).
ShapeHandle WeldOpenSeams(const ShapeHandle& shape);

/// A shape from an already built mesh and its groups (used by the generators); validates like the others.
ShapeHandle CreateTriMeshShape(TriMesh mesh, std::string source, std::map<std::string, std::vector<int>> groups);

}  // namespace jetshell
