// The benchmark definitions: Sze, Liu, Lo (2004) §3.1, §3.2, §3.3 and the Shell Actors page's scaled slit ring.
#include "validation/benchmark.h"

#include "core/math_constants.h"
#include "core/mesh_generators.h"
#include "energies/shell/material.h"
#include "validation/line_load.h"

#include <cmath>

namespace jetshell::validation {
namespace {

ShellProblem staticProblem(TriMesh mesh, const ShellMaterialParams& material) {
  ShellProblem p;
  p.mesh = std::move(mesh);
  p.material = material;
  p.hasGravity = false;
  p.gravity.setZero();
  return p;
}

/// Clamps the nodes `edge` (fixed in place) with the chosen model; `nextRow` is the neighbouring row the
/// two-row clamp also fixes.
void clamp(ShellProblem& p, const std::vector<int>& edge, const std::vector<int>& nextRow, ClampKind kind) {
  for (int v : edge) p.prescribed.fixVertex(v, p.mesh.V.row(v).transpose());
  if (kind == ClampKind::TwoRow) {
    for (int v : nextRow) p.prescribed.fixVertex(v, p.mesh.V.row(v).transpose());
  } else {
    p.clampedVertices.assign(static_cast<std::size_t>(p.mesh.numVertices()), 0);
    for (int v : edge) p.clampedVertices[v] = 1;
  }
}

// ---- Cantilever strips (§3.1, §3.2): L × 1, h = 0.1, E = 1.2e6, ν = 0 (EI = 100), clamped at x = 0. ----

/// Grid column i of a makeRectangleGrid mesh, j = 0..ny.
std::vector<int> gridColumn(int nx, int ny, int i) {
  std::vector<int> c;
  for (int j = 0; j <= ny; ++j) c.push_back(j * (nx + 1) + i);
  return c;
}

BenchmarkCase cantilever(double length, const Resolution& r, ClampKind kind, QuadDiagonals diagonals) {
  BenchmarkCase c;
  c.problem = staticProblem(makeRectangleGrid(length, 1.0, r.n1, r.n2, diagonals),
                            ShellMaterialParamsFrom3dIsotropic(1.2e6, 0.0, 1.0, 0.1));
  clamp(c.problem, gridColumn(r.n1, r.n2, 0), gridColumn(r.n1, r.n2, 1), kind);
  const std::vector<int> tip = gridColumn(r.n1, r.n2, r.n1);
  c.probes = {Probe{tip, 0, -1.0}, Probe{tip, 2, 1.0}};
  return c;
}

BenchmarkCase cantileverEndShear(const Resolution& r, ClampKind kind, QuadDiagonals diagonals) {
  BenchmarkCase c = cantilever(10.0, r, kind, diagonals);
  // Pmax = 4 over the width 1.
  c.problem.nodalForces = consistentLineLoad(c.problem.mesh, gridColumn(r.n1, r.n2, r.n1), {0.0, 0.0, 4.0});
  return c;
}

BenchmarkCase cantileverEndMoment(const Resolution& r, ClampKind kind, QuadDiagonals diagonals) {
  BenchmarkCase c = cantilever(12.0, r, kind, diagonals);
  EndMomentLoad m;
  m.chain = gridColumn(r.n1, r.n2, r.n1);
  m.axis = {0.0, -1.0, 0.0};             // turns +x towards +z: the strip rolls up
  m.moment = 2.0 * kPi * 100.0 / 12.0;  // Mmax = 2π EI / L
  m.where = "cantilever-end-moment";
  c.problem.endMoments.push_back(std::move(m));
  return c;
}

// ---- Slit annular plate (§3.3): Ri = 6, Ro = 10, h = 0.03, E = 21e6, ν = 0, q = 0.8 lifting the free side. ----

BenchmarkCase slitAnnulus(double scale, double youngsModulus, double density, double massDamping,
                          const Resolution& r, ClampKind kind, QuadDiagonals diagonals) {
  const int rings = r.n1 + 1, nodes = r.n2 + 1;
  ShellMaterialParams m = ShellMaterialParamsFrom3dIsotropic(youngsModulus, 0.0, density, 0.03 * scale);
  m.massDampingCoefficient = massDamping;
  BenchmarkCase c;
  // Cosine grading: ring k at radius Ri + (Ro − Ri)·½(1 − cos(πk/n1)), fine at both free edges.
  const RingSpacing spacing = r.grading == MeshGrading::Cosine ? RingSpacing::Cosine : RingSpacing::Uniform;
  c.problem = staticProblem(makeSlitAnnulus(6.0 * scale, 10.0 * scale, rings, nodes, diagonals, spacing), m);
  // Node j of ring k has index k·nodes + j: column 0 (θ = 0) is the clamped side, column nodes − 1 (θ = 2π)
  // the loaded one.
  std::vector<int> clamped, next, loaded;
  for (int k = 0; k < rings; ++k) {
    clamped.push_back(k * nodes);
    next.push_back(k * nodes + 1);
    loaded.push_back(k * nodes + nodes - 1);
  }
  clamp(c.problem, clamped, next, kind);
  c.problem.nodalForces = consistentLineLoad(c.problem.mesh, loaded, {0.0, 0.0, 0.8});
  c.probes = {Probe{{loaded.front()}, 2, 1.0}, Probe{{loaded.back()}, 2, 1.0}};
  return c;
}

std::vector<Benchmark> makeBenchmarks() {
  const std::string dir = referenceDirectory();
  std::vector<Benchmark> b;
  {
    Benchmark s;
    s.name = "slit-annular-plate";
    s.title = "Slit annular plate under lifting line force (Sze et al. 2004 §3.3)";
    s.resolutionMeaning = "radial x angular quads (each split in two triangles)";
    s.reference = loadReferenceTable(dir + "/sze2004_3.3_slit_annular_plate.tsv", {"W_A", "W_B"});
    s.defaultResolution = {10, 128, MeshGrading::Cosine};  // within 1% at every level in about 5 s (VALIDATION.md)
    s.minimumResolution = {1, 3};                              // 2 rings of 4 nodes
    s.build = [](const Resolution& r, ClampKind k, QuadDiagonals d) { return slitAnnulus(1.0, 21e6, 1.0, 0.0, r, k, d); };
    b.push_back(std::move(s));
  }
  {
    Benchmark s;
    s.name = "cantilever-end-shear";
    s.title = "Cantilever under end shear force (Sze et al. 2004 §3.1)";
    s.resolutionMeaning = "nx x ny squares along x 10 and y 1 (each split in two triangles)";
    s.reference = loadReferenceTable(dir + "/sze2004_3.1_cantilever_end_shear.tsv", {"-u_tip", "w_tip"});
    s.defaultResolution = {20, 2};
    s.build = cantileverEndShear;
    b.push_back(s);
    s.name = "cantilever-end-shear-elastica";
    s.title = "Cantilever under end shear force, against the inextensible elastica (Sze et al. 2004 §3.1 problem)";
    s.reference = endShearElastica(10.0, 100.0, 4.0, s.reference.lambda);
    b.push_back(std::move(s));
  }
  {
    Benchmark s;
    s.name = "cantilever-end-moment";
    s.title = "Cantilever under end moment, against the closed form (Sze et al. 2004 §3.2)";
    s.resolutionMeaning = "nx x ny squares along x 12 and y 1 (each split in two triangles)";
    s.reference = endMomentClosedForm(12.0, 20);
    s.errorMeasure = ErrorMeasure::DisplacementNorm;
    s.defaultResolution = {48, 4};
    s.build = cantileverEndMoment;
    b.push_back(std::move(s));
  }
  {
    Benchmark s;
    s.name = "slit-ring-page";
    s.title = "The Shell Actors page's slit annular ring (§3.3 scaled 1:10), static load stepping";
    s.resolutionMeaning = "radial x angular quads; the page's mesh is 4 x 64 (5 rings x 65 nodes)";
    s.reference = scaled(loadReferenceTable(dir + "/sze2004_3.3_slit_annular_plate.tsv", {"W_A", "W_B"}), 0.1);
    s.defaultResolution = {4, 64};
    s.minimumResolution = {1, 3};
    s.build = [](const Resolution& r, ClampKind k, QuadDiagonals d) {
      return slitAnnulus(0.1, 210e6, 1000.0, 0.3, r, k, d);
    };
    b.push_back(s);
    s.name = "slit-ring-page-relaxation";
    s.title = "The Shell Actors page's slit annular ring, dynamic relaxation (dt 1/30 s, alpha_R 0.3 1/s), lambda = 1";
    s.defaultSolver = SolverKind::DynamicRelaxation;
    b.push_back(std::move(s));
  }
  return b;
}

}  // namespace

const char* toString(ClampKind k) {
  switch (k) {
    case ClampKind::Normal: return "normal";
    case ClampKind::Mirrored: return "mirrored";
    case ClampKind::TwoRow: return "two-row";
  }
  return "?";
}

ClampKind parseClampKind(const std::string& s) {
  for (ClampKind k : {ClampKind::Normal, ClampKind::Mirrored, ClampKind::TwoRow})
    if (s == toString(k)) return k;
  throw InputError("clamp: '" + s + "' is not one of: normal, mirrored, two-row");
}

const char* toString(MeshGrading g) { return g == MeshGrading::Cosine ? "cosine" : "uniform"; }

MeshGrading parseMeshGrading(const std::string& s) {
  if (s == "uniform") return MeshGrading::Uniform;
  if (s == "cosine") return MeshGrading::Cosine;
  throw InputError("--grading: '" + s + "' is not one of: uniform, cosine");
}

const char* toString(SolverKind k) {
  return k == SolverKind::LoadStepping ? "load-stepping" : "dynamic-relaxation";
}

double Probe::read(const Eigen::VectorXd& x, const Eigen::VectorXd& X) const {
  double sum = 0.0;
  for (int v : vertices) sum += x[3 * v + component] - X[3 * v + component];
  return sign * sum / static_cast<double>(vertices.size());
}

const std::vector<Benchmark>& allBenchmarks() {
  static const std::vector<Benchmark> benchmarks = makeBenchmarks();
  return benchmarks;
}

const Benchmark& findBenchmark(const std::string& name, const std::vector<std::string>& otherNames) {
  std::string names;
  for (const Benchmark& b : allBenchmarks()) {
    if (b.name == name) return b;
    names += (names.empty() ? "" : ", ") + b.name;
  }
  for (const std::string& other : otherNames) names += ", " + other;
  throw InputError("validate: no benchmark named '" + name + "' (benchmarks: " + names + ")");
}

}  // namespace jetshell::validation
