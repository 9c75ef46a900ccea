#include "energies/contact/spatial_hash.h"

#include <catch2/catch.hpp>

#include <omp.h>

#include <random>

using namespace jetshell;

TEST_CASE("spatial hash: finds exactly the close pairs a brute-force search finds, filter applied", "[contact]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> p(3 * 3000);
  for (double& v : p) v = u(rng);
  const double r = 0.08;
  auto filter = [](int i, int j) { return (i + j) % 3 != 0; };
  std::vector<PointPair> brute;
  for (int i = 0; i < 3000; ++i)
    for (int j = i + 1; j < 3000; ++j) {
      double d2 = 0;
      for (int c = 0; c < 3; ++c) d2 += (p[3 * i + c] - p[3 * j + c]) * (p[3 * i + c] - p[3 * j + c]);
      if (d2 < r * r && filter(i, j)) brute.push_back({i, j});
    }
  const std::vector<PointPair> hashed = findClosePairs(p, r, filter);
  CHECK(brute.size() > 100);
  CHECK(hashed == brute);
  CHECK_THROWS(findClosePairs(p, 0.0));
}

TEST_CASE("spatial hash: a folded sheet on cell boundaries, on one thread and on two", "[contact]") {
  // 5,000 points (the threaded path) on two layers of a grid whose spacing is a fraction of r, many of them
  // exactly on cell faces, some with negative coordinates: pairs in one cell and across every kind of face.
  const double r = 0.04;
  std::vector<double> p;
  for (int layer = 0; layer < 2; ++layer)
    for (int a = 0; a < 50; ++a)
      for (int b = 0; b < 50; ++b) {
        p.push_back(-0.5 + 0.02 * a);
        p.push_back(0.03 * layer + 0.001 * ((a * b) % 3));
        p.push_back(0.01 * b * (layer ? 1.0 : -1.0));
      }
  const int n = static_cast<int>(p.size() / 3);
  REQUIRE(n >= 4096);
  auto filter = [](int i, int j) { return (i * 7 + j) % 5 != 0; };
  std::vector<PointPair> brute;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      double d2 = 0;
      for (int c = 0; c < 3; ++c) d2 += (p[3 * i + c] - p[3 * j + c]) * (p[3 * i + c] - p[3 * j + c]);
      if (d2 < r * r && filter(i, j)) brute.push_back({i, j});
    }
  CHECK(brute.size() > 10000);
  const int before = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    CHECK(findClosePairs(p, r, filter) == brute);
  }
  omp_set_num_threads(before);
}
