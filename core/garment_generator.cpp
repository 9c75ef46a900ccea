#include "core/garment_generator.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <string>

namespace jetshell {
namespace {

// Outline in cell units of 5 cm: x ∈ [−9, 9] (sleeves beyond ±5), y ∈ [0, 14], sleeves y ∈ [10, 14], neck |x| < 2.
bool insideCell(double cx, double cy) {  // cell centre in 5 cm units
  if (cy < 0 || cy > 14) return false;
  if (std::abs(cx) < 5) return true;
  return std::abs(cx) < 9 && cy > 10;
}

}  // namespace

GarmentMesh makeTShirt(int resolution, double gap) {
  if (resolution < 1 || resolution > 40) throw InputError("tshirt resolution = " + std::to_string(resolution) + ": must lie in [1, 40]");
  if (!(std::isfinite(gap) && gap >= 0.0)) throw InputError("tshirt gap: must be finite and >= 0");
  const int k = resolution;
  const int nx = 18 * k, ny = 14 * k;  // cells; grid vertex (i, j) at x = −0.45 + i h, y = j h
  auto cellIn = [&](int i, int j) {
    return i >= 0 && j >= 0 && i < nx && j < ny && insideCell((i + 0.5) / k - 9.0, (j + 0.5) / k);
  };
  const int W = nx + 1, H = ny + 1;
  std::vector<char> used(static_cast<std::size_t>(W * H), 0), boundary(static_cast<std::size_t>(W * H), 0);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      int in = 0;
      for (int a = -1; a <= 0; ++a)
        for (int b = -1; b <= 0; ++b) in += cellIn(i + a, j + b) ? 1 : 0;
      used[j * W + i] = in > 0;
      boundary[j * W + i] = in > 0 && in < 4;
    }
  // Open rims: the neck (top edge, |x| < 0.1), the waist (y = 0), the cuffs (|x| = 0.45). Their end points,
  // where a seam meets the opening, stay shared.
  auto xOf = [&](int i) { return static_cast<double>(i) / k - 9.0; };  // 5 cm units
  auto yOf = [&](int j) { return static_cast<double>(j) / k; };
  auto openKind = [&](int i, int j) -> int {  // 0 seam or interior; 1 neck, 2 waist, 3 cuff
    const double x = xOf(i), y = yOf(j);
    if (j == ny && std::abs(x) < 2.0 - 1e-9) return 1;
    if (j == 0 && std::abs(x) < 5.0 - 1e-9) return 2;
    if (std::abs(std::abs(x) - 9.0) < 1e-9 && y > 10.0 + 1e-9 && y < 14.0 - 1e-9) return 3;
    return 0;
  };
  std::vector<char> shared(static_cast<std::size_t>(W * H), 0);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) shared[j * W + i] = boundary[j * W + i] && openKind(i, j) == 0;
  // Grid distance (in cells) to the nearest seam vertex, for the bulge.
  std::vector<int> steps(static_cast<std::size_t>(W * H), 1 << 20);
  std::deque<int> queue;
  for (int v = 0; v < W * H; ++v)
    if (shared[v]) {
      steps[v] = 0;
      queue.push_back(v);
    }
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    const int i = v % W, j = v / W;
    const int nb[4][2] = {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}};
    for (const auto& n : nb) {
      if (n[0] < 0 || n[1] < 0 || n[0] > nx || n[1] > ny) continue;
      const int u = n[1] * W + n[0];
      if (!used[u] || steps[u] <= steps[v] + 1) continue;
      steps[u] = steps[v] + 1;
      queue.push_back(u);
    }
  }
  GarmentMesh g;
  std::vector<int> front(static_cast<std::size_t>(W * H), -1), back(static_cast<std::size_t>(W * H), -1);
  std::vector<Eigen::Vector3d> V;
  for (int side = 0; side < 2; ++side) {
    std::vector<int>& id = side == 0 ? front : back;
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const int v = j * W + i;
        if (!used[v]) continue;
        if (side == 1 && shared[v]) {
          id[v] = front[v];
          continue;
        }
        const double s = std::min(1.0, steps[v] / 3.0);
        id[v] = static_cast<int>(V.size());
        V.emplace_back(0.05 * xOf(i), 0.05 * yOf(j), (side == 0 ? 1.0 : -1.0) * gap * s);
        const int kind = openKind(i, j);
        if (kind == 1) g.neck.push_back(id[v]);
        if (kind == 2) g.waist.push_back(id[v]);
        if (kind == 3) g.cuffs.push_back(id[v]);
      }
  }
  std::vector<Eigen::Vector3i> F;
  for (int side = 0; side < 2; ++side) {
    const std::vector<int>& id = side == 0 ? front : back;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (!cellIn(i, j)) continue;
        const int a = id[j * W + i], b = id[j * W + i + 1], c = id[(j + 1) * W + i + 1], d = id[(j + 1) * W + i];
        Eigen::Vector3i t1, t2;
        if ((i + j) % 2 == 0) {
          t1 = {a, b, c};
          t2 = {a, c, d};
        } else {
          t1 = {a, b, d};
          t2 = {b, c, d};
        }
        if (side == 1) {  // back panel: outward normal −z
          std::swap(t1[1], t1[2]);
          std::swap(t2[1], t2[2]);
        }
        F.push_back(t1);
        F.push_back(t2);
      }
  }
  g.mesh.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (std::size_t v = 0; v < V.size(); ++v) g.mesh.V.row(static_cast<Eigen::Index>(v)) = V[v].transpose();
  g.mesh.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (std::size_t f = 0; f < F.size(); ++f) g.mesh.F.row(static_cast<Eigen::Index>(f)) = F[f].transpose();
  return g;
}

}  // namespace jetshell
