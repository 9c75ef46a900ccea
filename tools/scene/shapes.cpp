#include "tools/scene/shapes.h"

#include "core/mesh_io.h"
#include "core/topology.h"
#include "tools/scene/open_seams.h"

#include <string>

namespace jetshell {

ShapeHandle CreateTriMeshShape(const Positions& vertices, const Faces& faces) {
  return CreateTriMeshShape(TriMesh{vertices, faces}, "arrays", {});
}

ShapeHandle CreateTriMeshShape(const std::string& objPath) {
  return CreateTriMeshShape(readObj(objPath), objPath, {});
}

ShapeHandle WeldOpenSeams(const ShapeHandle& shape) {
  const OpenSeams seams = findOpenSeams(shape->mesh, buildTopology(shape->mesh));
  if (seams.pairs.empty() && !seams.partial) return shape;
  TriMesh welded = weldOpenSeams(shape->mesh, seams, shape->source);
  const int removed = shape->mesh.numVertices() - welded.numVertices();
  const std::string source = shape->source + ", " + std::to_string(seams.vertices) + " vertices welded into " +
                             std::to_string(seams.vertices - removed);
  return CreateTriMeshShape(std::move(welded), source, {});  // files and arrays name no vertex groups
}

ShapeHandle CreateTriMeshShape(TriMesh mesh, std::string source, std::map<std::string, std::vector<int>> groups) {
  buildTopology(mesh);  // validation; the topology itself is rebuilt where it is used
  if (const int v = firstVertexWithoutFace(mesh); v >= 0)
    throw InputError(source + ": vertex " + std::to_string(v) + " (counted from 0) belongs to no face: a shell "
                     "vertex without a face has no stiffness and no mass (remove it from the mesh)");
  auto shape = std::make_shared<TriangularMeshShape>();
  shape->mesh = std::move(mesh);
  shape->source = std::move(source);
  shape->vertexGroups = std::move(groups);
  return shape;
}

}  // namespace jetshell
