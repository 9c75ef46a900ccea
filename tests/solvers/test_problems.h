// Small shell problems shared by the solver tests.
#pragma once

#include "core/mesh_generators.h"
#include "solvers/shell_system.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <omp.h>

#include <cmath>

namespace jetshell::testing {

/// Runs the enclosing scope on one OpenMP thread. These meshes have tens of elements: the per-colour barriers
/// of the parallel element loop then cost more than the work (measured on the shared 2-core machine under
/// load: 120 ms per assembly with 2 threads against 0.15 ms with 1), which would make the long time-stepping
/// tests slow for no benefit.
class SingleThread {
 public:
  SingleThread() : saved_(omp_get_max_threads()) { omp_set_num_threads(1); }
  ~SingleThread() { omp_set_num_threads(saved_); }
  SingleThread(const SingleThread&) = delete;
  SingleThread& operator=(const SingleThread&) = delete;

 private:
  int saved_;
};

/// A plate [0, 1] × [0, 0.4] (nx × ny squares) clamped along x = 0 (all components of the edge's vertices),
/// with a total transverse force `force` [N] in +z spread over the x = 1 edge. No gravity.
inline ShellProblem cantileverPlate(int nx, int ny, double force) {
  ShellProblem p;
  p.mesh = makeRectangleGrid(1.0, 0.4, nx, ny);
  p.material = ShellMaterialParamsFrom3dIsotropic(1e6, 0.3, 1000.0, 0.01);
  p.hasGravity = false;
  const int n = p.mesh.numVertices();
  p.nodalForces = Eigen::VectorXd::Zero(3 * n);
  p.clampedVertices.assign(static_cast<std::size_t>(n), 0);
  for (int j = 0; j <= ny; ++j) {
    const int left = j * (nx + 1), right = left + nx;
    p.prescribed.fixVertex(left, p.mesh.V.row(left).transpose());
    p.clampedVertices[static_cast<std::size_t>(left)] = 1;
    const double share = (j == 0 || j == ny) ? 0.5 : 1.0;
    p.nodalForces[3 * right + 2] = force * share / ny;
  }
  return p;
}

/// The cantilever plate above (8 × 2 squares) compressed in its plane by a total end force P (−x, spread over the
/// free edge), flat: P_cr = π² D b / (4 L²) = 0.090 N for a plate strip (D = E h³ / (12 (1 − ν²))). Every
/// out-of-plane gradient stays exactly 0, so a solver follows the flat path whatever P.
inline ShellProblem compressedPlate(double total) {
  constexpr int nx = 8, ny = 2;
  ShellProblem p = cantileverPlate(nx, ny, 0.0);
  for (int j = 0; j <= ny; ++j) {
    const int right = j * (nx + 1) + nx;
    p.nodalForces[3 * right] = -total * ((j == 0 || j == ny) ? 0.5 : 1.0) / ny;
  }
  return p;
}

/// A 1 m square (6 × 6 squares) crumpled at rest (out of plane by up to 9 cm), clamped along x = 0, under its weight
/// (−z) and a force of 0.1 N (−z) at the corner (1, 1): `jetshell stress`'s crumpled/rest_static cell. Its path
/// turns back at λ ≈ 0.185 and again at λ ≈ −0.040 (arc length, 400 steps of λ ≤ 0.0025).
inline ShellProblem crumpledSheet() {
  constexpr int n = 6;
  ShellProblem p;
  p.mesh = makeRectangleGrid(1.0, 1.0, n, n);
  for (int v = 0; v < p.mesh.numVertices(); ++v) {
    const double x = p.mesh.V(v, 0), y = p.mesh.V(v, 1);
    p.mesh.V(v, 2) = 0.09 * std::sin(17.3 * x + 5.1 * y) * std::cos(11.7 * y - 3.0 * x);
  }
  p.material = ShellMaterialParamsFrom3dIsotropic(1e6, 0.3, 1000.0, 0.01);
  p.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  const int N = p.mesh.numVertices();
  p.nodalForces = Eigen::VectorXd::Zero(3 * N);
  p.nodalForces[3 * (N - 1) + 2] = -0.1;
  p.clampedVertices.assign(static_cast<std::size_t>(N), 0);
  for (int j = 0; j <= n; ++j) {
    const int left = j * (n + 1);
    p.prescribed.fixVertex(left, p.mesh.V.row(left).transpose());
    p.clampedVertices[static_cast<std::size_t>(left)] = 1;
  }
  return p;
}

/// A 1 m square sheet of `material` on n × n squares in the z = 0 plane, held at the two corners of its y = 1
/// edge, falling under gravity −z into a drape.
inline ShellProblem hangingSheet(int n, const ShellMaterialParams& material) {
  ShellProblem p;
  p.mesh = makeRectangleGrid(1.0, 1.0, n, n);
  p.material = material;
  p.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  const int topLeft = n * (n + 1), topRight = topLeft + n;
  p.prescribed.fixVertex(topLeft, p.mesh.V.row(topLeft).transpose());
  p.prescribed.fixVertex(topRight, p.mesh.V.row(topRight).transpose());
  return p;
}

/// A cloth [0, w] × [0, h] in the z = 0 plane hanging in its own plane: gravity −y, the two top corners
/// (y = h) fixed. Material: the spec's defaults (a light cloth).
inline ShellProblem hangingCloth(double w, double h, int nx, int ny) {
  ShellProblem p;
  p.mesh = makeRectangleGrid(w, h, nx, ny);
  p.gravity = Eigen::Vector3d(0.0, -9.81, 0.0);
  const int topLeft = ny * (nx + 1), topRight = topLeft + nx;
  p.prescribed.fixVertex(topLeft, p.mesh.V.row(topLeft).transpose());
  p.prescribed.fixVertex(topRight, p.mesh.V.row(topRight).transpose());
  return p;
}

/// A free square cloth (0.2 m, 3 × 3 squares) falling under gravity −y from rest.
inline ShellProblem freeCloth() {
  ShellProblem p;
  p.mesh = makeRectangleGrid(0.2, 0.2, 3, 3);
  p.gravity = Eigen::Vector3d(0.0, -9.81, 0.0);
  return p;
}

/// Assembles a hanging cloth's first-step Hessian (inertia at Δt = 1/60 plus membrane and two-ring bending,
/// blocks projected) at its rest shape bent by 0.05 x² out of plane; it stays in the system's assembler.
inline void assembleBentFirstStep(ShellSystem& shell) {
  Eigen::VectorXd x = shell.restPositions();
  for (int v = 0; v < shell.mesh().numVertices(); ++v) x[3 * v + 2] += 0.05 * std::pow(shell.mesh().V(v, 0), 2);
  shell.inertia->setCentre(x, 3600.0);
  Eigen::VectorXd g;
  EvalOptions o;
  o.projection = PsdProjection::Clamp;
  shell.objective().evaluate(x, &g, true, o);
}

/// The dense symmetric matrix whose upper triangle is stored in `upper` (the assembler's and solvers' layout).
inline Eigen::MatrixXd symmetricFromUpper(const Eigen::SparseMatrix<double>& upper) {
  const Eigen::MatrixXd U(upper);
  Eigen::MatrixXd full = U + U.transpose();
  full.diagonal() -= U.diagonal();
  return full;
}

}  // namespace jetshell::testing
