#include "energies/contact/spatial_hash.h"

#include <catch2/catch.hpp>

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
