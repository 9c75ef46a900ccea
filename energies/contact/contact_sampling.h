// Where contact is sampled on a shell (the spec's contactElementType): at vertices, or at quadrature points of
// the faces. Input: a mesh (possibly one actor's faces over stacked vertex ids) and its rest face areas.
// Output: a ContactSampling: elements of K vertices (1 for vertices, 3 for faces), each with Q points given by
// barycentric weights and an area weight (the rest area the point stands for; the areas of all points sum to
// the mesh's area).
#pragma once

#include "core/mesh.h"
#include "core/stencil.h"

#include <vector>

namespace jetshell {

enum class ContactQuadrature { Vertices, FaceCentroids, FaceThreePoint };

struct ContactSampling {
  int verticesPerElement = 1;  // K
  int pointsPerElement = 1;    // Q
  StencilTable table;          // elements × K vertex ids
  std::vector<double> weights; // elements × Q × K barycentric weights
  std::vector<double> area;    // elements × Q area weights [m²]

  int numElements() const { return table.size(); }
  int numPoints() const { return numElements() * pointsPerElement; }
};

/// Samples on the mesh; faceArea has one rest area per face. Vertices touched by no face get no sample.
ContactSampling sampleContactPoints(const TriMesh& mesh, const std::vector<double>& faceArea,
                                    ContactQuadrature quadrature);

}  // namespace jetshell
