// The one-ring part of a vertex-blocked Hessian: the entries that couple a vertex with itself or with a vertex it
// shares an edge with. Bending stencils couple each vertex with its two-ring, which makes the Cholesky factor of
// the full Hessian several times larger than that of the one-ring pattern (membrane + inertia); the one-ring
// part's factor is therefore a cheap preconditioner for CG on the full Hessian.
// Inputs: the mesh's triangles (vertex indices), the upper triangle of a 3N×3N Hessian (CSC, compressed).
// Outputs: the upper triangle restricted to the one-ring vertex pairs (same 3N×3N size, compressed), each dropped
// entry's magnitude added to the two diagonal entries it couples (so the result ⪰ H: positive definite whenever H
// is); fixed dofs' identity rows stay as they are (they are diagonal).
// Split in two (parts = 2, solvers/vertex_bisection.h): vertices of different parts count as not adjacent, so
// the couplings across the cut are dropped the same way and the result is block diagonal over the two parts,
// which solvers/split_factor.h factors one part per core.
#pragma once

#include <Eigen/Core>
#include <Eigen/Sparse>

#include <cstdint>
#include <vector>

namespace jetshell {

class OneRingFilter {
 public:
  OneRingFilter() = default;
  /// F: triangles (rows of three vertex indices in [0, numVertices)). parts: 1, or 2 to split the mesh by
  /// bisectVertices (which keeps small meshes whole).
  OneRingFilter(const Eigen::MatrixXi& F, int numVertices, int parts = 1);

  bool empty() const { return neighbours_.empty(); }
  int numVertices() const { return static_cast<int>(neighbours_.size()); }
  /// Whether vertices a and b are equal or share an edge, within one part.
  bool adjacent(int a, int b) const;
  /// Each vertex's part (empty: one part).
  const std::vector<std::int8_t>& vertexParts() const { return part_; }

  /// The one-ring part of `upper` (3·numVertices square). Reuses `out`'s storage; the result's pattern depends
  /// only on upper's pattern.
  void apply(const Eigen::SparseMatrix<double>& upper, Eigen::SparseMatrix<double>& out) const;

 private:
  std::vector<std::vector<int>> neighbours_;  // sorted, self included
  std::vector<std::int8_t> part_;             // per vertex; empty: one part
};

/// The filter for a sequence of matrices of one pattern: plan() decides once which entries are kept and which
/// dropped (one adjacency search per run of a row vertex's entries), then apply() only gathers values and adds
/// the dropped magnitudes. Both run on the OpenMP threads, column by column, each output summed in a fixed
/// order: the result has the same bits on any number of threads.
/// OneRingFilter::apply is a plan used once.
class OneRingPlan {
 public:
  /// Plans for upper's pattern (3·filter.numVertices() square, compressed).
  void plan(const OneRingFilter& filter, const Eigen::SparseMatrix<double>& upper);
  bool planned() const { return planned_; }
  /// The one-ring part of upper, whose pattern must be the planned one. The pattern of the result is fixed
  /// between plans.
  const Eigen::SparseMatrix<double>& apply(const Eigen::SparseMatrix<double>& upper);
  /// The last apply()'s result.
  const Eigen::SparseMatrix<double>& result() const { return result_; }

 private:
  bool planned_ = false;
  Eigen::Index cols_ = 0, nonZeros_ = 0;
  std::vector<char> keep_;                 // per source entry: kept (1) or dropped (0)
  std::vector<int> kept_;                  // source position of each result entry
  // The dropped entries' source positions, grouped by column and by row (CSC- and CSR-like starts per dof): a
  // dropped (i, j) adds its magnitude to both diagonals i and j.
  std::vector<int> droppedByColumn_, droppedColumnStart_;
  std::vector<int> droppedByRow_, droppedRowStart_;
  std::vector<int> diagonal_;              // result position of each row's diagonal, -1 when absent
  Eigen::SparseMatrix<double> result_;
};

}  // namespace jetshell
