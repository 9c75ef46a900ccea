#include "solvers/symmetric_product.h"

#include <catch2/catch.hpp>

#include <Eigen/SparseCore>

#include <omp.h>

#include <limits>
#include <random>
#include <vector>

using namespace jetshell;

namespace {

/// A symmetric matrix's upper triangle: a band of half-width `band`, some far entries, some empty columns.
Eigen::SparseMatrix<double> randomUpper(int n, int band, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> far(0, n - 1);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n; ++j) {
    if (j % 97 == 13) continue;  // an empty column
    for (int i = std::max(0, j - band); i <= j; ++i) {
      if ((i * 7 + j) % 3 != 0) t.emplace_back(i, j, value(rng));
    }
    const int i = far(rng);
    if (i < j) t.emplace_back(i, j, value(rng));
  }
  Eigen::SparseMatrix<double> H(n, n);
  H.setFromTriplets(t.begin(), t.end());
  H.makeCompressed();
  return H;
}

/// The product of H and p on one thread and on two: the same bits, and Eigen's product to rounding.
void checkOneAndTwoThreads(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& p) {
  SymmetricProduct product;
  Eigen::VectorXd one, two;
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  product.apply(H, p, one);
  omp_set_num_threads(2);
  product.apply(H, p, two);
  omp_set_num_threads(before);
  CHECK(one == two);
  const Eigen::VectorXd want = H.selfadjointView<Eigen::Upper>() * p;
  CHECK((one - want).norm() <= 1e-13 * want.norm());
}

}  // namespace

TEST_CASE("symmetric product: matches the serial symmetric product on one chunk and on many") {
  for (int n : {1, 50, 4000}) {
    const Eigen::SparseMatrix<double> H = randomUpper(n, 40, static_cast<unsigned>(n));
    const Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0).array().sin();
    const Eigen::VectorXd want = H.selfadjointView<Eigen::Upper>() * p;
    SymmetricProduct product;
    product.prepare(H);
    Eigen::VectorXd y;
    product.apply(H, p, y);
    CAPTURE(n, H.nonZeros());
    REQUIRE(y.size() == n);
    CHECK((y - want).norm() <= 1e-13 * (1.0 + want.norm()));
  }
}

TEST_CASE("symmetric product: the same bits on one thread and on two") {
  const Eigen::SparseMatrix<double> H = randomUpper(8000, 60, 7);
  REQUIRE(H.nonZeros() > 4 * (1 << 16));  // several chunks
  checkOneAndTwoThreads(H, Eigen::VectorXd::LinSpaced(H.cols(), 0.0, 3.0).array().cos());
}

TEST_CASE("symmetric product: a new pattern is picked up without prepare") {
  SymmetricProduct product;
  Eigen::VectorXd y;
  for (int n : {30, 3000}) {
    const Eigen::SparseMatrix<double> H = randomUpper(n, 20, 11u + static_cast<unsigned>(n));
    const Eigen::VectorXd p = Eigen::VectorXd::Ones(n);
    product.apply(H, p, y);
    const Eigen::VectorXd want = H.selfadjointView<Eigen::Upper>() * p;
    CHECK((y - want).norm() <= 1e-13 * (1.0 + want.norm()));
  }
}

TEST_CASE("symmetric product: a pattern of the same size and nonzero count but other rows is handled") {
  const int n = 3000;
  std::vector<Eigen::Triplet<double>> band, firstRow;
  for (int j = 0; j < n; ++j) {
    band.emplace_back(j, j, 2.0 + j % 5);
    firstRow.emplace_back(j, j, 2.0 + j % 5);
    if (j > 0) {
      band.emplace_back(j - 1, j, 0.5);
      firstRow.emplace_back(0, j, 0.25);  // reaches row 0 from every column: other chunks' scatter rows
    }
  }
  Eigen::SparseMatrix<double> A(n, n), B(n, n);
  A.setFromTriplets(band.begin(), band.end());
  B.setFromTriplets(firstRow.begin(), firstRow.end());
  REQUIRE(A.nonZeros() == B.nonZeros());
  const Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  SymmetricProduct product;
  Eigen::VectorXd y;
  for (const Eigen::SparseMatrix<double>* H : {&A, &B, &A}) {
    product.apply(*H, p, y);
    const Eigen::VectorXd want = H->selfadjointView<Eigen::Upper>() * p;
    CHECK((y - want).norm() <= 1e-13 * want.norm());
  }
}

TEST_CASE("symmetric product: the product with the entries' magnitudes, compressed or not") {
  const Eigen::SparseMatrix<double> H = randomUpper(4000, 40, 11);
  const Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(H.cols(), -1.0, 2.0).array().sin().abs();
  const Eigen::SparseMatrix<double> magnitudes = H.cwiseAbs();
  const Eigen::VectorXd want = magnitudes.selfadjointView<Eigen::Upper>() * p;
  SymmetricProduct product;
  Eigen::VectorXd y;
  product.applyAbsolute(H, p, y);
  CHECK((y - want).norm() <= 1e-13 * want.norm());
  Eigen::SparseMatrix<double> uncompressed = H;
  uncompressed.uncompress();
  product.applyAbsolute(uncompressed, p, y);
  CHECK((y - want).norm() <= 1e-13 * want.norm());
  // The signed product is unchanged by the magnitudes' path.
  product.apply(H, p, y);
  const Eigen::VectorXd signedWant = H.selfadjointView<Eigen::Upper>() * p;
  CHECK((y - signedWant).norm() <= 1e-13 * signedWant.norm());
}

namespace {

/// A vertex-block pattern like the assembled Hessian's: 3×3 blocks between each vertex and a few others, the
/// diagonal blocks' upper triangles; one vertex (index `gap`) with a column missing its diagonal entry.
Eigen::SparseMatrix<double> vertexBlockUpper(int vertices, int gap, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int v = 0; v < vertices; ++v) {
    for (int u : {v - 1, v - 2, v - 7, v - 40}) {
      if (u < 0) continue;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) t.emplace_back(3 * u + a, 3 * v + b, value(rng));
    }
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a <= b; ++a)
        if (!(v == gap && a == 1 && b == 1)) t.emplace_back(3 * v + a, 3 * v + b, value(rng));
  }
  Eigen::SparseMatrix<double> H(3 * vertices, 3 * vertices);
  H.setFromTriplets(t.begin(), t.end());
  H.makeCompressed();
  return H;
}

/// The product column by column in one pass, the order the file comment states: row-side sums, then the
/// column-side terms accumulated in column order.
Eigen::VectorXd columnByColumn(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& p) {
  Eigen::VectorXd y(H.cols()), s = Eigen::VectorXd::Zero(H.cols());
  for (Eigen::Index j = 0; j < H.cols(); ++j) {
    double row = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(H, j); it; ++it) {
      row += it.value() * p[it.row()];
      if (it.row() != j) s[it.row()] += it.value() * p[j];
    }
    y[j] = row;
  }
  for (Eigen::Index i = 0; i < H.cols(); ++i) y[i] += s[i];
  return y;
}

}  // namespace

TEST_CASE("symmetric product: a vertex-block pattern agrees with the column-by-column sweep") {
  const Eigen::SparseMatrix<double> H = vertexBlockUpper(600, 17, 3);
  REQUIRE(H.nonZeros() < (1 << 16));  // one chunk: the column-by-column sweep's exact order
  const Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(H.cols(), -2.0, 1.0).array().sin();
  SymmetricProduct product;
  Eigen::VectorXd y;
  product.apply(H, p, y);
  // The same sums in the same order: equal, up to the multiply-adds a native build may fuse differently
  // (an ulp of |H| |p|).
  const Eigen::SparseMatrix<double> magnitudes = H.cwiseAbs();
  const Eigen::VectorXd scale = magnitudes.selfadjointView<Eigen::Upper>() * p.cwiseAbs();
  const double ulp = std::numeric_limits<double>::epsilon();
  CHECK(((y - columnByColumn(H, p)).cwiseAbs().array() <= 4 * ulp * scale.array()).all());
  product.applyAbsolute(H, p.cwiseAbs(), y);
  CHECK(((y - columnByColumn(magnitudes, p.cwiseAbs())).cwiseAbs().array() <= 4 * ulp * scale.array()).all());
  // Many chunks: against Eigen's product, and the same bits on one thread and on two.
  const Eigen::SparseMatrix<double> big = vertexBlockUpper(8000, 2999, 5);
  REQUIRE(big.nonZeros() > 4 * (1 << 16));
  checkOneAndTwoThreads(big, Eigen::VectorXd::LinSpaced(big.cols(), 0.0, 3.0).array().cos());
}

TEST_CASE("symmetric product: vertex columns found once per pattern version, and again for a new one") {
  const Eigen::SparseMatrix<double> A = vertexBlockUpper(3000, 100, 8);
  // B: the same size, other blocks, and vertex 2000's columns not a vertex's.
  const Eigen::SparseMatrix<double> B = vertexBlockUpper(3000, 2000, 9);
  const Eigen::VectorXd p = Eigen::VectorXd::LinSpaced(A.cols(), -1.0, 1.0).array().exp();
  SymmetricProduct product;
  Eigen::VectorXd y, unversioned;
  std::uint64_t version = 1;
  for (const Eigen::SparseMatrix<double>* H : {&A, &A, &B, &B, &A}) {
    if (H == &B && version == 1) version = 2;
    if (H == &A && version == 2) version = 3;
    product.apply(*H, p, y, version);
    product.apply(*H, p, unversioned);
    const Eigen::VectorXd want = H->selfadjointView<Eigen::Upper>() * p;
    CHECK((y - want).norm() <= 1e-13 * want.norm());
    CHECK(y == unversioned);
  }
}
