#include "energies/contact/sdf_grid.h"

#include "core/format.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <sstream>

namespace jetshell {
namespace {

constexpr long long kMaxSamples = 16777216;

/// The grid's dims against its values (a grid built by a caller, not read from a file, may disagree): each at
/// least 2, at most kMaxSamples in all, and as many values as they announce.
void checkDims(const SdfGrid& grid) {
  if (grid.nx < 2 || grid.ny < 2 || grid.nz < 2) throw InputError("SDF grid: each dimension must be >= 2");
  const long long plane = static_cast<long long>(grid.nx) * grid.ny;  // ints: no overflow in long long
  if (plane > kMaxSamples || plane * grid.nz > kMaxSamples) throw InputError("SDF grid: at most 16777216 samples");
  if (plane * grid.nz != static_cast<long long>(grid.values.size()))
    throw InputError("SDF grid: values do not match dims");
}

/// A bound on how deep any point of the solid lies inside it: the deepest sample's depth (or 0) plus half a cell's
/// diagonal, since a signed distance changes no faster than the point moves and every point is that close to a
/// sample.
double largestDepth(const SdfGrid& grid) {
  double deepest = 0.0;
  for (const double v : grid.values) deepest = std::max(deepest, -v);
  return deepest + 0.5 * std::sqrt(3.0) * grid.spacing;
}

class GridShape : public VolumeShape {
 public:
  explicit GridShape(SdfGrid g) : g_(std::move(g)) {}
  std::string kind() const override { return "sdf_grid"; }
  // A sampled solid resolves no part thinner than its spacing; nothing bounds it from below more tightly.
  double thinnestHalfWidth() const override { return g_.spacing; }

  SdfSample signedDistance(const Eigen::Vector3d& p) const override {
    const double h = g_.spacing;
    const Eigen::Vector3d upper = g_.origin + h * Eigen::Vector3d(g_.nx - 1, g_.ny - 1, g_.nz - 1);
    const Eigen::Vector3d c = p.cwiseMax(g_.origin).cwiseMin(upper);
    SdfSample s = inside(c);
    const Eigen::Vector3d out = p - c;
    const double o = out.norm();
    if (o > 0.0) {  // outside the grid: a conservative continuation, distance grows like the distance to it
      s.distance += o;
      s.gradient = out / o;
      s.hessian = (Eigen::Matrix3d::Identity() - s.gradient * s.gradient.transpose()) / o;
    }
    return s;
  }

 private:
  double at(int i, int j, int k) const {
    return g_.values[static_cast<std::size_t>(i) + static_cast<std::size_t>(g_.nx) * (j + static_cast<std::size_t>(g_.ny) * k)];
  }

  SdfSample inside(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d u = (p - g_.origin) / g_.spacing;
    const int n[3] = {g_.nx, g_.ny, g_.nz};
    int i0[3];
    double f[3];
    for (int a = 0; a < 3; ++a) {
      // Clamped as a double: the cast of a value outside int's range (or of NaN) would be undefined.
      const double cell = std::isnan(u[a]) ? 0.0 : std::clamp(std::floor(u[a]), 0.0, static_cast<double>(n[a] - 2));
      i0[a] = static_cast<int>(cell);
      f[a] = u[a] - i0[a];
    }
    double c[2][2][2];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int d = 0; d < 2; ++d) c[a][b][d] = at(i0[0] + a, i0[1] + b, i0[2] + d);
    // Trilinear φ(f) = Σ c_abd w_a(fx) w_b(fy) w_d(fz), w_0 = 1 − f, w_1 = f; derivatives in cell units.
    auto w = [](int a, double t) { return a ? t : 1.0 - t; };
    auto dw = [](int a) { return a ? 1.0 : -1.0; };
    SdfSample s;
    s.distance = 0.0;
    s.gradient.setZero();
    s.hessian.setZero();
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int d = 0; d < 2; ++d) {
          const double v = c[a][b][d];
          const double wx = w(a, f[0]), wy = w(b, f[1]), wz = w(d, f[2]);
          s.distance += v * wx * wy * wz;
          s.gradient += v * Eigen::Vector3d(dw(a) * wy * wz, wx * dw(b) * wz, wx * wy * dw(d));
          s.hessian(0, 1) += v * dw(a) * dw(b) * wz;
          s.hessian(0, 2) += v * dw(a) * wy * dw(d);
          s.hessian(1, 2) += v * wx * dw(b) * dw(d);
        }
    s.hessian(1, 0) = s.hessian(0, 1);
    s.hessian(2, 0) = s.hessian(0, 2);
    s.hessian(2, 1) = s.hessian(1, 2);
    s.gradient /= g_.spacing;
    s.hessian /= g_.spacing * g_.spacing;
    return s;
  }

  SdfGrid g_;
};

}  // namespace

SdfGrid readSdfGrid(const std::string& path) {
  std::ifstream in = openInputFile(path, inputLimits().maxSdfBytes, "SDF grid file");
  return parseSdfGrid(in, path);
}

SdfGrid parseSdfGrid(std::istream& in, const std::string& path) {
  const InputLimits& limits = inputLimits();
  SdfGrid g;
  int line = 0;
  std::int64_t totalBytes = 0;
  std::string text;
  enum { Dims, Origin, Spacing, Values } stage = Dims;
  long long expected = 0;
  auto fail = [&](const std::string& what) -> void {
    throw InputError(path + ":" + std::to_string(line) + ": " + what);
  };
  while (readBoundedLine(in, text, limits.maxSdfLineBytes, path, line + 1, totalBytes, limits.maxSdfBytes)) {
    ++line;
    std::istringstream s(text);
    std::string word;
    if (!(s >> word) || word[0] == '#') continue;
    if (stage == Dims) {
      long long n[3];
      if (word != "dims" || !(s >> n[0] >> n[1] >> n[2])) fail("expected 'dims nx ny nz'");
      for (long long v : n)
        if (v < 2 || v > kMaxSamples) fail("each grid dimension must be in [2, 16777216]");
      // Each factor is at most 2^24, so neither product overflows once the first is bounded.
      if (n[0] * n[1] > kMaxSamples || n[0] * n[1] * n[2] > kMaxSamples) fail("at most 16777216 samples");
      g.nx = static_cast<int>(n[0]);
      g.ny = static_cast<int>(n[1]);
      g.nz = static_cast<int>(n[2]);
      expected = n[0] * n[1] * n[2];
      stage = Origin;
    } else if (stage == Origin) {
      if (word != "origin" || !(s >> g.origin[0] >> g.origin[1] >> g.origin[2]) ||
          !(g.origin.cwiseAbs().maxCoeff() <= limits.maxDistance))
        fail("expected 'origin ox oy oz' (each at most " + formatNumber("%g", limits.maxDistance) + " m in size)");
      stage = Spacing;
    } else if (stage == Spacing) {
      if (word != "spacing" || !(s >> g.spacing) || !(g.spacing > 0 && g.spacing <= limits.maxDistance))
        fail("expected 'spacing h' with h > 0 and at most " + formatNumber("%g", limits.maxDistance) + " m");
      stage = Values;
      g.values.reserve(static_cast<std::size_t>(expected));
    } else {
      std::istringstream values(text);
      std::string token;
      while (values >> token) {
        char* end = nullptr;
        const double v = std::strtod(token.c_str(), &end);
        if (end == token.c_str() || *end != '\0' || !std::isfinite(v)) fail("'" + token.substr(0, 32) + "': not a finite number");
        if (static_cast<long long>(g.values.size()) >= expected) fail("more values than dims announce");
        g.values.push_back(v);
      }
    }
  }
  if (stage != Values || static_cast<long long>(g.values.size()) != expected)
    throw InputError(path + ": " + std::to_string(g.values.size()) + " distance values, " + std::to_string(expected) +
                     " expected (dims, origin, spacing, then the values)");
  return g;
}

VolumeShapePtr makeSdfGridShape(SdfGrid grid) {
  checkDims(grid);
  if (!(std::isfinite(grid.spacing) && grid.spacing > 0)) throw InputError("SDF grid: spacing must be > 0");
  const Eigen::Vector3d upper = grid.origin + grid.spacing * Eigen::Vector3d(grid.nx - 1, grid.ny - 1, grid.nz - 1);
  if (!grid.origin.allFinite() || !upper.allFinite()) throw InputError("SDF grid: its box must be finite");
  for (double v : grid.values)
    if (!std::isfinite(v)) throw InputError("SDF grid: values must be finite");
  return std::make_shared<GridShape>(std::move(grid));
}

Eigen::AlignedBox3d sdfGridBox(const SdfGrid& grid) {
  return {grid.origin, grid.origin + grid.spacing * Eigen::Vector3d(grid.nx - 1, grid.ny - 1, grid.nz - 1)};
}

double sdfGridThinnestHalfWidth(const SdfGrid& grid) {
  checkDims(grid);
  const double halfDiagonal = 0.5 * std::sqrt(3.0) * grid.spacing;
  double thinnest = largestDepth(grid);
  const std::ptrdiff_t sx = 1, sy = grid.nx, sz = static_cast<std::ptrdiff_t>(grid.nx) * grid.ny;
  for (int k = 1; k + 1 < grid.nz; ++k)
    for (int j = 1; j + 1 < grid.ny; ++j)
      for (int i = 1; i + 1 < grid.nx; ++i) {
        const std::ptrdiff_t at = i * sx + j * sy + k * sz;
        const double value = grid.values[static_cast<std::size_t>(at)];
        if (!(value < 0.0) || -value + halfDiagonal >= thinnest) continue;
        bool ridge = true;  // no neighbour deeper, so no neighbour's value below this one's
        for (int dz = -1; dz <= 1 && ridge; ++dz)
          for (int dy = -1; dy <= 1 && ridge; ++dy)
            for (int dx = -1; dx <= 1 && ridge; ++dx)
              ridge = grid.values[static_cast<std::size_t>(at + dx * sx + dy * sy + dz * sz)] >= value;
        if (ridge) thinnest = -value + halfDiagonal;
      }
  return thinnest;
}

}  // namespace jetshell
