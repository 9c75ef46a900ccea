#include "tools/bench_trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jetshell::cli {

VertexDistance vertexDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() != b.size() || a.size() % 3 != 0)
    throw std::invalid_argument("vertexDistance: position vectors of different sizes, or not 3 a vertex");
  const Eigen::Index n = a.size() / 3;
  double sum = 0.0, largest = 0.0;
  for (Eigen::Index v = 0; v < n; ++v) {
    const double squared = (a.segment<3>(3 * v) - b.segment<3>(3 * v)).squaredNorm();
    sum += squared;
    largest = std::max(largest, squared);
  }
  VertexDistance d;
  if (n > 0) d.rms = std::sqrt(sum / static_cast<double>(n));
  d.largest = std::sqrt(largest);
  return d;
}

}  // namespace jetshell::cli
