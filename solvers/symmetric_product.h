// y = H p for a symmetric sparse H stored as its upper triangle (column-major, the layout the Objective
// assembles), on the OpenMP threads.
//
// Data flow: prepare(H) cuts the columns into chunks of about equal nonzero count; a chunk's count depends on H
// alone, never on the thread count, and apply() redoes the cut only when H's size or nonzero count changes (a
// stale cut is only less balanced, never wrong). apply(): each chunk computes, for its own columns j, the row-side sums
// y_j = Σ_{i<=j} H_ij p_i directly into y, and scatters the column-side terms H_ij p_j (i < j) into a buffer of its
// own that spans rows [first row it touches, its last column]. The buffers are then added into y in chunk
// order. Every sum runs in a fixed order, so the result has the same bits on any number of threads.
// Chunks hold whole vertices (three columns). Three columns that are one vertex's (the same rows above the
// vertex, then the diagonal block's upper triangle; checked in full on every call, or once per pattern version
// when the caller passes one, then only their shape) are swept together: each of their
// shared rows' index, p_i and scatter entry is read once instead of three times. Every sum adds its terms in
// the order of the column-by-column sweep, so the two agree to the bit unless the compiler fuses multiplies and
// adds differently in them (-march=native: within an ulp); the thread count never changes the bits.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <vector>

namespace jetshell {

class SymmetricProduct {
 public:
  /// Cuts H's columns into chunks (one pass over the column pointers).
  void prepare(const Eigen::SparseMatrix<double>& upper);
  /// y = H p (y is resized), for any pattern with rows sorted within each column (Eigen's compressed form); an
  /// uncompressed H takes Eigen's serial product. patternVersion (core/assembly.h's: it changes whenever the
  /// pattern does; 0: unknown) lets the vertex columns be found once per pattern instead of on every call.
  void apply(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p, Eigen::VectorXd& y,
             std::uint64_t patternVersion = 0);
  /// y = |H| p, the product with H's entries' magnitudes (Newton's round-off floor), the same way.
  void applyAbsolute(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p, Eigen::VectorXd& y);

 private:
  template <bool Absolute>
  void product(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& p, Eigen::VectorXd& y,
               std::uint64_t patternVersion);

  struct Chunk {
    Eigen::Index begin = 0, end = 0;  // columns [begin, end)
    Eigen::Index firstRow = 0;        // the smallest row index in those columns (set by apply)
    std::vector<double> scatter;      // rows [firstRow, end), reused
  };
  std::vector<Chunk> chunks_;
  Eigen::Index cols_ = -1, nonZeros_ = -1;
  std::vector<char> vertexStart_;    // per column: three columns of one vertex start here (checked in full)
  std::uint64_t checkedVersion_ = 0;  // the pattern version vertexStart_ was found for (0: none)
};

}  // namespace jetshell
