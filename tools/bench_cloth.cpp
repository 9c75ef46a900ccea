#include "tools/bench_cloth.h"

#include "core/mesh_generators.h"

#include <sys/resource.h>

#include <ctime>
#include <fstream>

namespace jetshell::cli {

ShellProblem hangingCloth(int n, double massDamping, double stiffnessDamping, SheetMaterial material,
                          double youngsModulus, double thickness) {
  ShellProblem p;
  p.mesh = makeRectangleGrid(1.0, 1.0, n, n);
  const bool foil = material == SheetMaterial::SteelFoil;
  const double E = youngsModulus > 0.0 ? youngsModulus : (foil ? 2e11 : 1e5);
  const double h = thickness > 0.0 ? thickness : (foil ? 1e-4 : 0.002);
  p.material = foil ? ShellMaterialParamsFrom3dIsotropic(E, 0.3, 7850.0, h)
                    : ShellMaterialParamsFrom3dIsotropic(E, 0.25, 1000.0, h);
  p.material.massDampingCoefficient = massDamping;
  p.material.stiffnessDampingCoefficient = stiffnessDamping;
  p.gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  const int topLeft = n * (n + 1), topRight = topLeft + n;
  p.prescribed.fixVertex(topLeft, p.mesh.V.row(topLeft).transpose());
  p.prescribed.fixVertex(topRight, p.mesh.V.row(topRight).transpose());
  return p;
}

double wallSeconds() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double loadAverage() {
  std::ifstream f("/proc/loadavg");
  double load = -1.0;
  if (!(f >> load)) return -1.0;
  return load;
}

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;
}

}  // namespace jetshell::cli
