#include "tools/scene/shapes.h"

#include "core/input_limits.h"
#include "core/mesh_io.h"
#include "core/topology.h"
#include "tools/scene/open_seams.h"

#include <sstream>
#include <string>

namespace jetshell {

ShapeHandle CreateTriMeshShape(const Positions& vertices, const Faces& faces) {
  return CreateTriMeshShape(TriMesh{vertices, faces}, "arrays", {});
}

ShapeHandle CreateTriMeshShape(const std::string& objPath, double scale) {
  TriMesh mesh = readObj(objPath);
  mesh.V *= scale;
  return CreateTriMeshShape(std::move(mesh), objPath, {});
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
  // Metres, as every length of a scene: a coordinate beyond the bound on distances is a mesh in other units.
  const double far = inputLimits().maxDistance;
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (!(mesh.V.row(v).cwiseAbs().maxCoeff() <= far)) {
      std::ostringstream m;
      m << source << ": vertex " << v << " (counted from 0) lies at (" << mesh.V(v, 0) << ", " << mesh.V(v, 1)
        << ", " << mesh.V(v, 2) << "), over " << far << " m from the origin in a coordinate (lengths are in "
        << "metres: a scene's \"scale\" converts a mesh in other units)";
      throw InputError(m.str());
    }
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
