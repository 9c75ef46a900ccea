#include "core/mesh_generators.h"

#include "core/input_limits.h"
#include "core/math_constants.h"

#include <array>
#include <cstdint>
#include <cmath>
#include <functional>
#include <sstream>
#include <vector>

namespace jetshell {
namespace {

[[noreturn]] void invalid(const char* generator, const std::string& what) {
  throw InputError(std::string(generator) + ": " + what);
}

void requirePositive(const char* generator, const char* name, double value) {
  if (!(std::isfinite(value) && value > 0)) {
    std::ostringstream s;
    s << name << " = " << value << ": must be finite and > 0";
    invalid(generator, s.str());
  }
}

void requireAtLeast(const char* generator, const char* name, int value, int minimum) {
  if (value < minimum) {
    std::ostringstream s;
    s << name << " = " << value << ": must be >= " << minimum;
    invalid(generator, s.str());
  }
}

/// Rejects a resolution whose mesh would exceed inputLimits() (counted in 64 bits: no int overflow).
void requireSize(const char* generator, std::int64_t vertices, std::int64_t faces) {
  const InputLimits& limits = inputLimits();
  if (vertices > limits.maxVertices || faces > limits.maxFaces) {
    std::ostringstream s;
    s << "the resolution gives " << vertices << " vertices and " << faces << " faces, too many (at most "
      << limits.maxVertices << " vertices and " << limits.maxFaces << " faces)";
    invalid(generator, s.str());
  }
}

/// Triangulates an nu × nv grid of quads whose corner (i, j) has vertex id(i, j) (i may wrap for closed
/// surfaces: id handles that). The (u, v) parameter directions and the right-hand rule give the normal;
/// alternating diagonals follow makeRectangleGrid's pattern.
void appendQuadGrid(std::vector<std::array<int, 3>>& faces, int nu, int nv, const std::function<int(int, int)>& id,
                    QuadDiagonals diagonals) {
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const int v00 = id(i, j), v10 = id(i + 1, j), v01 = id(i, j + 1), v11 = id(i + 1, j + 1);
      if (diagonals == QuadDiagonals::Uniform || (i + j) % 2 == 0) {
        faces.push_back({v00, v10, v11});
        faces.push_back({v00, v11, v01});
      } else {
        faces.push_back({v00, v10, v01});
        faces.push_back({v10, v11, v01});
      }
    }
  }
}

Faces toFaces(const std::vector<std::array<int, 3>>& faces) {
  Faces F(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    F.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  return F;
}

}  // namespace

/// The grid with alternating diagonals.
static TriMesh alternatingRectangleGrid(double width, double height, int nx, int ny) {
  if (nx < 1 || ny < 1) {
    std::ostringstream s;
    s << "rectangle grid: nx = " << nx << ", ny = " << ny << ": both must be >= 1";
    throw InputError(s.str());
  }
  if (!(width > 0) || !(height > 0)) throw InputError("rectangle grid: width and height must be > 0");
  requireSize("rectangle grid", (std::int64_t{nx} + 1) * (std::int64_t{ny} + 1), 2 * std::int64_t{nx} * ny);
  TriMesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.V.row(j * (nx + 1) + i) << width * i / nx, height * j / ny, 0.0;
  m.F.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
      if ((i + j) % 2 == 0) {
        m.F.row(f++) << v00, v10, v11;
        m.F.row(f++) << v00, v11, v01;
      } else {
        m.F.row(f++) << v00, v10, v01;
        m.F.row(f++) << v10, v11, v01;
      }
    }
  }
  return m;
}

TriMesh makeSlitAnnulus(double innerRadius, double outerRadius, int rings, int nodesPerRing, QuadDiagonals diagonals,
                        RingSpacing spacing) {
  const char* g = "slit annulus";
  requirePositive(g, "innerRadius", innerRadius);
  requirePositive(g, "outerRadius", outerRadius);
  if (!(outerRadius > innerRadius)) invalid(g, "outerRadius must be > innerRadius");
  requireAtLeast(g, "rings", rings, 2);
  requireAtLeast(g, "nodesPerRing", nodesPerRing, 4);
  requireSize(g, std::int64_t{rings} * nodesPerRing, 2 * std::int64_t{rings - 1} * (nodesPerRing - 1));
  TriMesh m;
  m.V.resize(rings * nodesPerRing, 3);
  for (int r = 0; r < rings; ++r) {
    const double s = static_cast<double>(r) / (rings - 1);
    const double t = spacing == RingSpacing::Cosine ? 0.5 * (1.0 - std::cos(0.5 * kTwoPi * s)) : s;
    const double radius = innerRadius + (outerRadius - innerRadius) * t;
    for (int j = 0; j < nodesPerRing; ++j) {
      // The last column is computed at exactly 2π so the slit's two sides coincide to rounding.
      const double theta = kTwoPi * j / (nodesPerRing - 1);
      m.V.row(r * nodesPerRing + j) << radius * std::cos(theta), radius * std::sin(theta), 0.0;
    }
  }
  std::vector<std::array<int, 3>> faces;
  // u = radius, v = angle: e_r × e_θ = +z.
  appendQuadGrid(faces, rings - 1, nodesPerRing - 1, [&](int r, int j) { return r * nodesPerRing + j; }, diagonals);
  m.F = toFaces(faces);
  return m;
}

TriMesh makeCylinder(double radius, double length, double arcRadians, int nAround, int nAlong, QuadDiagonals diagonals) {
  const char* g = "cylinder";
  requirePositive(g, "radius", radius);
  requirePositive(g, "length", length);
  if (!(std::isfinite(arcRadians) && arcRadians > 0 && arcRadians <= kTwoPi * (1 + 1e-12)))
    invalid(g, "arc must lie in (0, 360] degrees");
  const bool closed = arcRadians >= kTwoPi * (1 - 1e-12);
  requireAtLeast(g, "nAround", nAround, closed ? 3 : 1);
  requireAtLeast(g, "nAlong", nAlong, 1);
  requireSize(g, (std::int64_t{nAround} + 1) * (std::int64_t{nAlong} + 1), 2 * std::int64_t{nAround} * nAlong);
  const int columns = closed ? nAround : nAround + 1;
  TriMesh m;
  m.V.resize(columns * (nAlong + 1), 3);
  const double start = closed ? 0.0 : -0.5 * arcRadians;
  const double step = (closed ? kTwoPi : arcRadians) / nAround;
  for (int j = 0; j <= nAlong; ++j) {
    for (int i = 0; i < columns; ++i) {
      const double theta = start + step * i;
      m.V.row(j * columns + i) << radius * std::sin(theta), length * j / nAlong, radius * std::cos(theta);
    }
  }
  std::vector<std::array<int, 3>> faces;
  // u = θ, v = y: (R cos θ, 0, −R sin θ) × (0, 1, 0) points outward.
  appendQuadGrid(faces, nAround, nAlong, [&](int i, int j) { return j * columns + (closed ? i % nAround : i); },
                 diagonals);
  m.F = toFaces(faces);
  return m;
}

TriMesh makeHemisphere(double radius, int rings, int segments, double holeRadians, double azimuthRadians,
                       QuadDiagonals diagonals) {
  const char* g = "hemisphere";
  requirePositive(g, "radius", radius);
  requireAtLeast(g, "rings", rings, 1);
  if (!(std::isfinite(holeRadians) && holeRadians >= 0 && holeRadians < 0.25 * kTwoPi))
    invalid(g, "hole angle must lie in [0, 90) degrees");
  if (!(std::isfinite(azimuthRadians) && azimuthRadians > 0 && azimuthRadians <= kTwoPi * (1 + 1e-12)))
    invalid(g, "azimuth must lie in (0, 360] degrees");
  const bool closedAround = azimuthRadians >= kTwoPi * (1 - 1e-12);
  const bool pole = holeRadians == 0.0;
  requireAtLeast(g, "segments", segments, closedAround ? 3 : 1);
  if (pole && !closedAround) invalid(g, "a partial azimuth needs a hole angle > 0 (the pole would be degenerate)");
  requireSize(g, 1 + (std::int64_t{rings} + 1) * (std::int64_t{segments} + 1), 2 * std::int64_t{rings} * segments);
  const int columns = closedAround ? segments : segments + 1;
  const int firstRing = pole ? 1 : 0;  // ring 0 of a closed cap is the single pole vertex
  const int numVertices = (pole ? 1 : 0) + (rings + 1 - firstRing) * columns;
  TriMesh m;
  m.V.resize(numVertices, 3);
  auto id = [&](int k, int i) {
    if (pole && k == 0) return 0;
    const int column = closedAround ? i % segments : i;
    return (pole ? 1 + (k - 1) * columns : k * columns) + column;
  };
  if (pole) m.V.row(0) << 0.0, 0.0, radius;
  const double azimuthStep = (closedAround ? kTwoPi : azimuthRadians) / segments;
  for (int k = firstRing; k <= rings; ++k) {
    // The equator ring is set exactly to z = 0.
    const double phi = k == rings ? 0.25 * kTwoPi : holeRadians + (0.25 * kTwoPi - holeRadians) * k / rings;
    const double sinPhi = std::sin(phi), cosPhi = k == rings ? 0.0 : std::cos(phi);
    for (int i = 0; i < columns; ++i) {
      const double theta = azimuthStep * i;
      m.V.row(id(k, i)) << radius * sinPhi * std::cos(theta), radius * sinPhi * std::sin(theta), radius * cosPhi;
    }
  }
  std::vector<std::array<int, 3>> faces;
  if (pole) {
    for (int i = 0; i < segments; ++i) faces.push_back({0, id(1, i), id(1, i + 1)});
  }
  // u = polar angle φ, v = azimuth θ: ∂φ × ∂θ points outward.
  appendQuadGrid(faces, rings - firstRing, segments, [&](int k, int i) { return id(k + firstRing, i); }, diagonals);
  m.F = toFaces(faces);
  return m;
}

QuadDiagonals quadDiagonalsFromString(const std::string& name) {
  if (name == "alternating") return QuadDiagonals::Alternating;
  if (name == "uniform") return QuadDiagonals::Uniform;
  throw InputError("diagonals = \"" + name + "\": must be \"alternating\" or \"uniform\"");
}

const char* toString(QuadDiagonals d) { return d == QuadDiagonals::Uniform ? "uniform" : "alternating"; }

RingSpacing ringSpacingFromString(const std::string& name) {
  if (name == "uniform") return RingSpacing::Uniform;
  if (name == "cosine") return RingSpacing::Cosine;
  throw InputError("ringSpacing = \"" + name + "\": must be \"uniform\" or \"cosine\"");
}

const char* toString(RingSpacing s) { return s == RingSpacing::Cosine ? "cosine" : "uniform"; }

TriMesh makeRectangleGrid(double width, double height, int nx, int ny) {
  return makeRectangleGrid(width, height, nx, ny, QuadDiagonals::Uniform);
}

TriMesh makeRectangleGrid(double width, double height, int nx, int ny, QuadDiagonals diagonals) {
  TriMesh m = alternatingRectangleGrid(width, height, nx, ny);
  if (diagonals == QuadDiagonals::Alternating) return m;
  std::vector<std::array<int, 3>> faces;
  appendQuadGrid(faces, nx, ny, [&](int i, int j) { return j * (nx + 1) + i; }, diagonals);
  m.F = toFaces(faces);
  return m;
}

}  // namespace jetshell
