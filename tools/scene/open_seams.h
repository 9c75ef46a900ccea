// Vertices of one shell that lie on one another with no edge between them: an open seam. A garment exported as
// unjoined panels, or a mesh split along its texture seams, reads as a valid mesh and falls apart at the seam
// once it moves. The scene reader names such meshes (a warning, since a slit may be meant: the slit ring's is),
// and welds them when the shape asks ("weld": true).
//
// Input: the actor's mesh and topology. Output: the pairs of vertices within a small tolerance (1e-3 of the mean
// edge) of one another that no edge joins, found by the reader's bounded search for near pairs
// (tools/scene/near_pairs.h): O(n log n), serial.
#pragma once

#include "core/mesh.h"
#include "core/topology.h"

#include <array>
#include <vector>

namespace jetshell {

/// The tolerance is kOpenSeamTolerance × the mean edge length. The search visits at most kOpenSeamVisits × n
/// vertices in all (a mesh with thousands of vertices crowded within the tolerance would take quadratic time).
constexpr double kOpenSeamTolerance = 1e-3;
constexpr long long kOpenSeamVisits = 64;
/// At most this many pairs a vertex are kept; past it the search stops (partial).
constexpr long long kOpenSeamPairs = 4;

struct OpenSeams {
  double tolerance = 0.0;                  // m: vertices closer than this lie on one another
  std::vector<std::array<int, 2>> pairs;   // (smaller id, larger), sorted
  int vertices = 0;                        // distinct vertices in `pairs`
  /// The search stopped at its budget of visits or of pairs, so `pairs` may be incomplete. Also set, with no
  /// pairs, for a mesh whose coordinates cannot be placed in cells of the tolerance's size (over 1e15 tolerances
  /// from the origin).
  bool partial = false;
};

OpenSeams findOpenSeams(const TriMesh& mesh, const Topology& topology);

/// The mesh with each group of vertices the pairs join merged into the group's first vertex (the others
/// removed, ids kept in order, faces renumbered). Throws InputError naming `where` when the search was partial.
/// The result is not validated: welding may fold or pinch the mesh (CreateTriMeshShape checks it).
TriMesh weldOpenSeams(const TriMesh& mesh, const OpenSeams& seams, const std::string& where);

}  // namespace jetshell
