// How far one run of a scene is from another, vertex by vertex: the benchmarks that weigh a run's speed against
// its error compare its positions with a reference run's at the same steps (bench dynamics: the time step's error
// against a run with a small step; bench contact: an iteration cap's against a run with more iterations a step).
// Input: two position vectors of one mesh (3 coordinates a vertex, equal sizes).
// Output: the RMS over the vertices of the distance between a vertex's two positions, and the largest distance.
#pragma once

#include <Eigen/Core>

namespace jetshell::cli {

struct VertexDistance {
  double rms = 0.0;
  double largest = 0.0;
};

VertexDistance vertexDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

}  // namespace jetshell::cli
