// Sparse Hessian assembly with a pattern computed once and value-only refills.
//
// Data flow: every term declares its StencilTable (addStencils) -> finalize() builds the upper-triangular CSC
// pattern of the 3N×3N matrix, one scatter table per element (the value index of each 3×3 vertex block of the
// element's local upper triangle; per entry where a dof is fixed or a vertex repeats) -> at each evaluation,
// setZero() and the terms add dense element blocks. Terms colour their elements (colorElements: one colour =
// no shared vertex) and run one colour at a time in parallel (core/element_loop.h), so every entry is summed in
// the same order whatever the thread count (same bits).
// Fixed (eliminated) dofs scatter into a discarded slot and get 1 on the diagonal: their rows and columns are
// identity, so a Newton step never moves them.
// Patterns that follow moving contacts (clearStencils, addStencils, finalize again) can be grow-only
// (setGrowOnly): the matrix pattern is then the union of every pattern declared since the last reset, so the
// entries of pairs no stencil touches any more stay as stored zeros, and when the new stencils fit in the kept
// pattern only the scatter tables are rebuilt: patternVersion() stays and a linear solver keeps its symbolic
// analysis. The pattern is reset to the exact one (pruned) when it has to grow and would otherwise carry more
// stale vertex pairs than `pruneFraction` × the pairs in use.
// Re-declaring only the slots that moved (replaceStencils, then finalize): the other slots' scatter tables are
// kept when the pattern is kept, and translated (old value index -> new, one gather per entry) when a new pattern
// is built, instead of searched again: the mesh terms (bending's 12x12 blocks) are most of the scatter entries,
// and a contact pattern changes at almost every Newton iteration.
#pragma once

#include "core/stencil.h"

#include <Eigen/Sparse>

#include <cstdint>
#include <vector>

namespace jetshell {

class HessianAssembler {
 public:
  /// Declares one term's stencils; returns its slot. Call before finalize().
  int addStencils(const StencilTable& table);
  /// Builds the pattern for numVertices vertices. fixedDof (size 3N, or empty) marks eliminated dofs. The values
  /// end as setZero() leaves them, whether the pattern is new or kept (callers rely on it: no second setZero).
  void finalize(int numVertices, const std::vector<char>& fixedDof = {});
  bool finalized() const { return finalized_; }
  /// Forgets every slot so that stencils can be declared anew (a pattern that follows moving contacts); the
  /// next finalize() bumps patternVersion() when it builds a new pattern (always, unless grow-only).
  void clearStencils();
  /// Replaces the stencils of one declared slot (same width, any element count); the next finalize() builds the
  /// pattern anew as finalize() after clearStencils() and every slot's addStencils() would, keeping or translating
  /// the scatter tables of the slots not replaced (see the file comment).
  void replaceStencils(int slot, const StencilTable& table);
  /// Grow-only patterns (see the file comment); pruneFraction >= 0. Off by default.
  void setGrowOnly(bool growOnly, double pruneFraction = 0.25);
  bool growOnly() const { return growOnly_; }
  /// How often finalize() built a new matrix pattern (the first build included), and how often a re-declared
  /// set of stencils fitted in the kept pattern (no new pattern).
  int patternBuilds() const { return patternBuilds_; }
  int patternReuses() const { return patternReuses_; }
  /// Vertex pairs (upper triangle, diagonal included) in the matrix pattern and in the declared stencils.
  std::int64_t patternPairs() const { return patternPairs_; }
  std::int64_t usedPairs() const { return usedPairs_; }

  /// Zeroes the values (pattern kept). Fixed dofs get their unit diagonal. Split over the threads from
  /// kParallelZeroValues values on (a serial pass over a large matrix otherwise; BENCHMARKS.md, session 92).
  void setZero();
  static constexpr std::int64_t kParallelZeroValues = 1 << 18;
  /// Adds a dense symmetric element block H (3K×3K, column-major, leading dimension 3K); reads the upper
  /// triangle only. Safe to call concurrently for elements of one colour.
  void addElementHessian(int slot, int element, const double* H);

  const StencilTable& stencils(int slot) const { return slots_[slot].table; }
  int numSlots() const { return static_cast<int>(slots_.size()); }

  /// The assembled matrix: upper triangle, column-major, compressed.
  const Eigen::SparseMatrix<double>& matrix() const { return matrix_; }
  Eigen::SparseMatrix<double>& matrix() { return matrix_; }
  const std::vector<char>& fixedDof() const { return fixedDof_; }
  /// Bumped whenever finalize() builds a new matrix pattern: linear solvers redo their symbolic analysis only
  /// when it changes.
  std::uint64_t patternVersion() const { return patternVersion_; }
  /// Bytes held by scatter tables and the matrix (for memory reports).
  std::size_t memoryBytes() const;

 private:
  // The scatter table of a slot, per element one of two forms:
  //  - blocks (most elements): per vertex pair (a, b), a <= b in stencil order (b outer, a inner), the value
  //    index of the global block's first entry (row 0, column 0 of the pair's 3×3 block in the matrix's own
  //    orientation), or -1 when a vertex is absent; the block's other entries follow from its column vertex's
  //    stride (columnStride_): K(K+1)/2 indices per element, a tenth of a per-entry table for K = 6.
  //  - entries (elements with a fixed dof or a repeated vertex): per entry of the local upper triangle, the
  //    value index; -1 discard; <= -2 doubled (a repeated vertex maps an off-diagonal entry onto a diagonal one).
  struct Slot {
    StencilTable table;
    std::vector<std::int32_t> blocks;   // K(K+1)/2 per element (unused rows for elements with entries)
    std::vector<std::int32_t> entryRow; // per element: its row in `scatter`, or -1 (blocks)
    std::vector<std::int32_t> scatter;  // (3K)(3K+1)/2 per element with entries
    bool stale = true;                  // the scatter table does not match the table (declared or replaced)
    bool moving = false;                // replaced at least once since declared (not in the base adjacency)
  };
  /// Builds the matrix pattern from rows (per column vertex, the sorted row vertices <= it).
  void buildMatrix(int numVertices);
  /// Fills the scatter tables of the stale slots (all with everything) against rows_.
  void buildScatter(bool everything);
  /// For a new pattern (newRows) over the same vertices and fixed dofs: the new value index of every value index
  /// of the current matrix whose vertex pair newRows keeps (-1 for the others).
  std::vector<std::int32_t> translationTo(const std::vector<std::vector<int>>& newRows) const;

  std::vector<Slot> slots_;
  std::vector<std::vector<int>> rows_;  // the matrix pattern's vertex pairs: per column vertex j, rows i <= j
  // The adjacency (as rows_) of the base slots (never replaced since declared), and which slots they were.
  std::vector<std::vector<int>> keptRows_;
  // The next finalize's working rows: the previous pattern's buffers (or a discarded candidate's), filled again in
  // place so that a finalize allocates only where a column outgrows its old capacity.
  std::vector<std::vector<int>> spareRows_;
  std::vector<char> baseSlots_;
  std::vector<char> fixedDof_;
  Eigen::SparseMatrix<double> matrix_;
  std::vector<std::int32_t> diagonalIndex_;
  std::vector<std::int32_t> columnStride_;  // per vertex j: 3 (|rows_[j]| − 1), the off-diagonal rows of its columns
  bool finalized_ = false;
  std::uint64_t patternVersion_ = 0;
  bool growOnly_ = false;
  double pruneFraction_ = 0.25;
  int patternBuilds_ = 0, patternReuses_ = 0;
  std::int64_t patternPairs_ = 0, usedPairs_ = 0;
};

/// Greedy colouring of elements so that no two elements of one colour share a vertex.
std::vector<std::vector<int>> colorElements(const StencilTable& table, int numVertices);

/// A contiguous range of element indices.
struct ElementRange {
  int begin, end;
};

/// The parallel schedule of a term's elements: contiguous blocks of elements (cache-friendly: neighbouring
/// elements touch neighbouring matrix entries), coloured so that blocks of one colour share no vertex. Blocks
/// of one colour run in parallel, elements inside a block in order, colours one after another. The blocks
/// depend only on the mesh, not on the thread count, so every sum is taken in the same order (same bits).
struct ElementSchedule {
  std::vector<std::vector<ElementRange>> colors;
};

/// Builds the schedule; blockSize 0 picks one from the element count.
ElementSchedule scheduleElements(const StencilTable& table, int numVertices, int blockSize = 0);

}  // namespace jetshell
