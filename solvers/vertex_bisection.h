// Two parts of a mesh's vertices with few edges between them: a METIS node separator of the vertex graph
// (CHOLMOD's cholmod_bisect), each separator vertex joined to the smaller part as it goes. Used to split the
// one-ring preconditioner into two factors that are computed and applied side by side (solvers/split_factor.h).
// Inputs: the vertex graph as vertexNeighbours gives it (built once, and shared with the one-ring filter).
// Output: part[v] in {0, 1} for every vertex; all 0 (one part) when the mesh has fewer than
// kMinBisectedVertices vertices, or when METIS finds no separator (CHOLMOD built without it, a graph it cannot
// split), so a caller never has to handle a failed bisection.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace jetshell {

/// Below this many vertices a mesh stays one part: its factor costs less than a parallel region's start-up.
inline constexpr int kMinBisectedVertices = 512;

/// Each vertex's neighbours across the triangles' edges and itself, sorted. F: rows of three vertex indices in
/// [0, numVertices); an index outside it is refused (std::invalid_argument).
std::vector<std::vector<int>> vertexNeighbours(const Eigen::MatrixXi& F, int numVertices);

/// The two parts of the graph `neighbours` (as vertexNeighbours returns it).
std::vector<std::int8_t> bisectVertices(const std::vector<std::vector<int>>& neighbours);

}  // namespace jetshell
