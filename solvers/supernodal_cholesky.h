// The numeric supernodal Cholesky factorization on CHOLMOD's symbolic analysis, with BLAS and LAPACK calls and
// no OpenMP region of its own, and its solves. Used by CholmodFactor (solvers/cholmod_factor.h) in place of
// cholmod_factorize and cholmod_solve2.
// Why: Debian's CHOLMOD 3 opens an OpenMP region per supernode and per descendant update inside its numeric
// factorization; a region that its `if` clause serializes, or that is nested in another one (SplitFactor's
// parts), still builds a team of one and ends with a futex wake, 31,000 system calls per Newton iteration of
// the T-shirt (BENCHMARKS.md, "Contact → Session 28").
// The algorithm is CHOLMOD's left-looking supernodal one: each supernode's dense block (column-major, the
// layout of cholmod_factor's x) receives its columns of P(A + shift·I)Pᵀ, then the updates of every descendant
// supernode (a syrk and a gemm, scattered through the relative row map), then a potrf of its diagonal block and
// a trsm of the rows below. The result is the factor CHOLMOD's own solves read. The solves sweep the same blocks
// with plain loops: a T-shirt supernode has about 9 columns, where a BLAS call per block costs more than its work
// (CG's solves 0.96× whole-process wall against cholmod_solve2's, BENCHMARKS.md).
// The same sweep also makes an LDLᵀ factor without pivoting (unit L, D on L's diagonal) of a matrix that may be
// indefinite, for path following's inertia counts (solvers/indefinite_factor.h): each descendant's update is a
// gemm with its columns scaled by their pivots, and each supernode's own columns are eliminated in place, down
// the rows below as well (no potrf, no trsm).
// Inputs: the analysed supernodal factor (symbolic or numeric, int indices), the matrix as its upper triangle
// (Eigen CSC, the analysed pattern). Outputs: L's values; the first column where the matrix is not positive
// definite (or its pivot not finite); for LDLᵀ, the first column whose pivot is zero or not finite.
#pragma once

#include <Eigen/Sparse>

#include <cstddef>
#include <string>
#include <vector>

struct cholmod_factor_struct;

namespace jetshell {

class SupernodalCholesky {
 public:
  /// Maps each stored entry of upper's upper triangle to its place in L's values. Called after each analysis.
  /// False (with message) if L is not a supernodal factor of upper's size.
  bool prepare(const cholmod_factor_struct& L, const Eigen::SparseMatrix<double>& upper, std::string& message);
  /// Fills L's values (allocated and real: cholmod_change_factor) with the factor of upper + shift·I, upper
  /// having the prepared pattern. Returns L.n on success, else the first column (in L's order) whose pivot is
  /// not positive and finite.
  std::size_t factorize(cholmod_factor_struct& L, const Eigen::SparseMatrix<double>& upper, double shift);
  /// x = (LLᵀ)⁻¹ b, b and x of size L.n in the matrix's order (x may be b), with L factorized.
  void solve(const cholmod_factor_struct& L, const double* b, double* x);
  /// Fills L's values with the LDLᵀ factor of upper (unit L below the diagonal, D on it), without pivoting.
  /// Returns L.n on success, else the first column (in L's order) whose pivot is zero or not finite.
  std::size_t factorizeLdlt(cholmod_factor_struct& L, const Eigen::SparseMatrix<double>& upper);
  /// x = (LDLᵀ)⁻¹ b in the matrix's order (x may be b), with L's LDLᵀ factor.
  void solveLdlt(const cholmod_factor_struct& L, const double* b, double* x);
  /// x = Pᵀ L⁻ᵀ u: u in L's order, x in the matrix's, with L's LDLᵀ factor (its unit Lᵀ only).
  void solveUnitTransposed(const cholmod_factor_struct& L, const double* u, double* x);
  /// D of L's LDLᵀ factor, in L's order.
  void pivots(const cholmod_factor_struct& L, double* d) const;
  /// The number of stored entries of the prepared matrix.
  std::size_t entries() const { return target_.size(); }

 private:
  /// The left-looking sweep of factorize (LLᵀ) and factorizeLdlt.
  std::size_t sweep(cholmod_factor_struct& L, const Eigen::SparseMatrix<double>& upper, double shift, bool ldlt);
  /// Moves the columns of P(A + shift·I)Pᵀ into L's values (zero elsewhere).
  void scatterMatrix(cholmod_factor_struct& L, const Eigen::SparseMatrix<double>& upper, double shift);
  /// Calls update(d, first, inColumns, below) for each descendant d of supernode t whose next unprocessed rows
  /// [first, first + inColumns) are columns of t (below: d's rows from first to its end), then links d onward.
  template <class Update>
  void forEachDescendant(const cholmod_factor_struct& L, int t, Update&& update);
  /// y = L⁻¹ y in L's order; with `unit` (an LDLᵀ factor) L's diagonal is 1 and y is then divided by D.
  void forwardSweep(const cholmod_factor_struct& L, double* y, bool unit);
  /// y = L⁻ᵀ y in L's order; with `unit` (an LDLᵀ factor) L's diagonal is 1.
  void backwardSweep(const cholmod_factor_struct& L, double* y, bool unit);
  /// Puts descendant t, its columns done, on the list of the supernode owning its next row (if any).
  void linkDescendant(const cholmod_factor_struct& L, int t, int position);
  /// Subtracts the update block c (below × inColumns, leading dimension below) from supernode block `block`
  /// through the relative row map, for rows rowIndex[j..below) of column j.
  void scatterUpdate(double* block, int k1, int rows, const int* rowIndex, const double* c, int below,
                     int inColumns);

  std::vector<long> target_;    // per stored entry of upper: its index in L's values, or −1 (below diagonal)
  std::vector<long> diagonal_;  // per column (L's order): the index of its diagonal in L's values
  std::vector<int> superOf_;    // per column: its supernode
  std::vector<int> head_, next_, position_, map_;  // the left-looking sweep's lists and relative row map
  std::vector<double> update_;  // one descendant's update block
  std::vector<double> scaled_;  // LDLᵀ: one descendant's rows in the target's columns, scaled by its pivots
  std::vector<double> permuted_, rows_;  // the solve's right-hand side in L's order, one supernode's rows
};

}  // namespace jetshell
