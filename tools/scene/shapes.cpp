#include "tools/scene/shapes.h"

#include "core/mesh_io.h"
#include "core/topology.h"

namespace jetshell {

ShapeHandle CreateTriMeshShape(const Positions& vertices, const Faces& faces) {
  return CreateTriMeshShape(TriMesh{vertices, faces}, "arrays", {});
}

ShapeHandle CreateTriMeshShape(const std::string& objPath) {
  return CreateTriMeshShape(readObj(objPath), objPath, {});
}

ShapeHandle CreateTriMeshShape(TriMesh mesh, std::string source, std::map<std::string, std::vector<int>> groups) {
  buildTopology(mesh);  // validation; the topology itself is rebuilt where it is used
  auto shape = std::make_shared<TriangularMeshShape>();
  shape->mesh = std::move(mesh);
  shape->source = std::move(source);
  shape->vertexGroups = std::move(groups);
  return shape;
}

}  // namespace jetshell
