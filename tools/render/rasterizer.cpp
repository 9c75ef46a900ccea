#include "tools/render/rasterizer.h"

#include "core/math_constants.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetshell {
namespace {

float srgbToLinear(double c) { return static_cast<float>(std::pow(c, 2.2)); }

struct Camera {
  Eigen::Vector3d eye, forward, right, up;
  double focal = 1.0;  // pixels
  double cx = 0, cy = 0;
};

Camera frame(const std::vector<RenderMesh>& meshes, const RenderOptions& o, int width, int height) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const RenderMesh& m : meshes)
    for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
      lo = lo.cwiseMin(Eigen::Vector3d(m.V.row(v)));
      hi = hi.cwiseMax(Eigen::Vector3d(m.V.row(v)));
    }
  const Eigen::Vector3d center = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * (hi - lo).norm(), 1e-9);
  const Eigen::Vector3d up = o.up.normalized();
  // A "front" direction perpendicular to up: −y for z-up scenes, +z for y-up ones.
  Eigen::Vector3d front = -Eigen::Vector3d::UnitY();
  for (const Eigen::Vector3d& c : {Eigen::Vector3d(-Eigen::Vector3d::UnitY()), Eigen::Vector3d(Eigen::Vector3d::UnitZ()),
                                  Eigen::Vector3d(Eigen::Vector3d::UnitX())})
    if (std::abs(c.dot(up)) < 0.5) {
      front = c;
      break;
    }
  front = (front - front.dot(up) * up).normalized();
  const Eigen::Vector3d side = (-front).cross(up);
  const double az = o.azimuthDegrees * kRadiansPerDegree, el = o.elevationDegrees * kRadiansPerDegree;
  const Eigen::Vector3d toEye =
      (std::cos(el) * (std::cos(az) * front + std::sin(az) * side) + std::sin(el) * up).normalized();
  const double halfFov = 0.5 * o.fieldOfViewDegrees * kRadiansPerDegree;
  const double distance = 1.08 * radius / std::sin(halfFov);
  Camera c;
  c.eye = center + distance * toEye;
  c.forward = -toEye;
  c.right = c.forward.cross(up);
  if (c.right.norm() < 1e-9) c.right = c.forward.cross(front);  // looking straight along up
  c.right.normalize();
  c.up = c.right.cross(c.forward);
  c.focal = 0.5 * std::min(width, height) / std::tan(halfFov);
  c.cx = 0.5 * width;
  c.cy = 0.5 * height;
  return c;
}

std::vector<Eigen::Vector3d> vertexNormals(const RenderMesh& m) {
  std::vector<Eigen::Vector3d> n(static_cast<std::size_t>(m.V.rows()), Eigen::Vector3d::Zero());
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d x0 = m.V.row(m.F(f, 0)), x1 = m.V.row(m.F(f, 1)), x2 = m.V.row(m.F(f, 2));
    const Eigen::Vector3d a = (x1 - x0).cross(x2 - x0);  // area-weighted
    for (int k = 0; k < 3; ++k) n[static_cast<std::size_t>(m.F(f, k))] += a;
  }
  for (Eigen::Vector3d& v : n)
    if (v.norm() > 0) v.normalize();
  return n;
}

}  // namespace

Rgb viridis(double s) {
  static const double table[5][3] = {
      {0.267, 0.005, 0.329}, {0.229, 0.322, 0.546}, {0.128, 0.567, 0.551}, {0.369, 0.789, 0.383}, {0.993, 0.906, 0.144}};
  s = std::clamp(std::isfinite(s) ? s : 0.0, 0.0, 1.0) * 4.0;
  const int k = std::min(3, static_cast<int>(s));
  const double t = s - k;
  Rgb c;
  c.r = srgbToLinear((1 - t) * table[k][0] + t * table[k + 1][0]);
  c.g = srgbToLinear((1 - t) * table[k][1] + t * table[k + 1][1]);
  c.b = srgbToLinear((1 - t) * table[k][2] + t * table[k + 1][2]);
  return c;
}

Image renderMeshes(const std::vector<RenderMesh>& meshes, const RenderOptions& o) {
  if (o.width < kMinImageSize || o.height < kMinImageSize || o.width > kMaxImageSize || o.height > kMaxImageSize)
    throw InputError("render: image size must be between 16 and 8192 pixels");
  if (o.supersample < 1 || o.supersample > kMaxSupersample) throw InputError("render: supersample must be 1..8");
  const long long samples = static_cast<long long>(o.width) * o.height * o.supersample * o.supersample;
  if (samples > kMaxImageSamples)
    throw InputError("render: width x height x supersample^2 = " + std::to_string(samples) +
                     " samples, too many (at most " + std::to_string(kMaxImageSamples) + ")");
  bool any = false;
  for (const RenderMesh& m : meshes) any = any || m.F.rows() > 0;
  if (!any) throw InputError("render: nothing to draw (no triangles)");
  const int S = o.supersample, W = o.width * S, H = o.height * S;
  const Camera cam = frame(meshes, o, W, H);

  Image image(W, H);
  for (int y = 0; y < H; ++y) {
    const float t = static_cast<float>(y) / static_cast<float>(H);
    const float g = 0.92f - 0.35f * t;  // soft vertical gradient
    for (int x = 0; x < W; ++x) image.at(x, y) = {g, g, 0.98f * g + 0.02f};
  }
  std::vector<float> depth(static_cast<std::size_t>(W) * H, std::numeric_limits<float>::infinity());

  const Eigen::Vector3d keyLight = (0.5 * cam.up - 0.35 * cam.right - 0.45 * cam.forward).normalized();
  for (const RenderMesh& m : meshes) {
    const std::vector<Eigen::Vector3d> normals = vertexNormals(m);
    double smin = o.scalarMin, smax = o.scalarMax;
    if (!m.scalar.empty() && smax < smin) {
      smin = *std::min_element(m.scalar.begin(), m.scalar.end());
      smax = *std::max_element(m.scalar.begin(), m.scalar.end());
    }
    const double sRange = smax > smin ? smax - smin : 1.0;
    // Project every vertex once: screen x, y and view depth.
    std::vector<Eigen::Vector3d> screen(static_cast<std::size_t>(m.V.rows()));
    for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
      const Eigen::Vector3d q = Eigen::Vector3d(m.V.row(v)) - cam.eye;
      const double z = q.dot(cam.forward);
      screen[static_cast<std::size_t>(v)] = {cam.cx + cam.focal * q.dot(cam.right) / z, cam.cy - cam.focal * q.dot(cam.up) / z, z};
    }
    bool edges = o.edges == RenderOptions::Edges::On;
    if (o.edges == RenderOptions::Edges::Auto) {
      double sum = 0;
      for (Eigen::Index f = 0; f < m.F.rows(); ++f)
        sum += (screen[static_cast<std::size_t>(m.F(f, 0))] - screen[static_cast<std::size_t>(m.F(f, 1))]).head<2>().norm();
      edges = sum / std::max<Eigen::Index>(1, m.F.rows()) > 14.0 * S;  // average edge > 14 output pixels
    }
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      const int id[3] = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
      const Eigen::Vector3d* p[3] = {&screen[static_cast<std::size_t>(id[0])], &screen[static_cast<std::size_t>(id[1])],
                                     &screen[static_cast<std::size_t>(id[2])]};
      if ((*p[0])[2] <= 1e-9 || (*p[1])[2] <= 1e-9 || (*p[2])[2] <= 1e-9) continue;  // behind the eye
      const double area = ((*p[1])[0] - (*p[0])[0]) * ((*p[2])[1] - (*p[0])[1]) -
                          ((*p[2])[0] - (*p[0])[0]) * ((*p[1])[1] - (*p[0])[1]);
      if (std::abs(area) < 1e-12) continue;
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({(*p[0])[0], (*p[1])[0], (*p[2])[0]}))));
      const int x1 = std::min(W - 1, static_cast<int>(std::ceil(std::max({(*p[0])[0], (*p[1])[0], (*p[2])[0]}))));
      const int y0 = std::max(0, static_cast<int>(std::floor(std::min({(*p[0])[1], (*p[1])[1], (*p[2])[1]}))));
      const int y1 = std::min(H - 1, static_cast<int>(std::ceil(std::max({(*p[0])[1], (*p[1])[1], (*p[2])[1]}))));
      double edgeLength[3];
      for (int k = 0; k < 3; ++k) edgeLength[k] = ((*p[(k + 2) % 3]) - (*p[(k + 1) % 3])).head<2>().norm();
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const double px = x + 0.5, py = y + 0.5;
          double b[3];
          for (int k = 0; k < 3; ++k) {
            const Eigen::Vector3d& a = *p[(k + 1) % 3];
            const Eigen::Vector3d& c = *p[(k + 2) % 3];
            b[k] = ((c[0] - a[0]) * (py - a[1]) - (px - a[0]) * (c[1] - a[1])) / area;
          }
          if (b[0] < 0 || b[1] < 0 || b[2] < 0) continue;
          // Perspective-correct weights.
          double w[3], sum = 0;
          for (int k = 0; k < 3; ++k) sum += (w[k] = b[k] / (*p[k])[2]);
          const double z = 1.0 / sum;
          float& zbuf = depth[static_cast<std::size_t>(y) * W + x];
          if (z >= static_cast<double>(zbuf)) continue;
          zbuf = static_cast<float>(z);
          Eigen::Vector3d n = Eigen::Vector3d::Zero(), world = Eigen::Vector3d::Zero();
          double s = 0;
          for (int k = 0; k < 3; ++k) {
            const double wk = w[k] * z;
            n += wk * normals[static_cast<std::size_t>(id[k])];
            world += wk * Eigen::Vector3d(m.V.row(id[k]));
            if (!m.scalar.empty()) s += wk * m.scalar[static_cast<std::size_t>(id[k])];
          }
          const Eigen::Vector3d toEye = (cam.eye - world).normalized();
          if (n.norm() < 1e-12) n = toEye;
          n.normalize();
          const bool backSide = n.dot(toEye) < 0;
          if (backSide) n = -n;
          Rgb base = !m.scalar.empty() ? viridis((s - smin) / sRange) : (backSide ? m.back : m.front);
          if (backSide && !m.scalar.empty()) base = {0.8f * base.r, 0.8f * base.g, 0.8f * base.b};
          const Eigen::Vector3d half = (keyLight + toEye).normalized();
          const double diffuse = 0.22 + 0.58 * std::max(0.0, n.dot(keyLight)) + 0.30 * std::max(0.0, n.dot(toEye));
          const double specular = 0.12 * std::pow(std::max(0.0, n.dot(half)), 40.0);
          const float lit = static_cast<float>(diffuse), shine = static_cast<float>(specular);
          Rgb c{base.r * lit + shine, base.g * lit + shine, base.b * lit + shine};
          if (edges) {
            double d = std::numeric_limits<double>::infinity();
            for (int k = 0; k < 3; ++k) d = std::min(d, b[k] * std::abs(area) / edgeLength[k]);
            if (d < 0.6 * S) c = {0.45f * c.r, 0.45f * c.g, 0.45f * c.b};
          }
          image.at(x, y) = c;
        }
      }
    }
  }
  return S > 1 ? image.downsample(S) : image;
}

}  // namespace jetshell
