#include "tools/bench/stage_jet_width.h"

#include "core/mesh_generators.h"
#include "core/stage.h"
#include "core/topology.h"
#include "energies/shell/reference_state.h"
#include "energies/shell/shell_geometry.h"
#include "energies/shell/shell_stages.h"
#include "tools/bench/wavy_grid.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <stdexcept>

namespace jetshell {
namespace {

double threadNs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e9 + static_cast<double>(t.tv_nsec);
}

/// Every entity's derivatives at width W, a checksum (so that nothing is optimised away), ns per call.
template <int W, typename S>
__attribute__((noinline)) double timeWidth(const S& stage, const std::vector<double>& z, int order, double& sum) {
  constexpr int N = S::kInputs;
  const int count = static_cast<int>(z.size()) / N;
  StageDerivativesOf<S> d;
  for (auto& h : d.hessians) h.setZero();
  const double t0 = threadNs();
  for (int e = 0; e < count; ++e) {
    stageDerivativesFromJetsInlined<S, W>(stage, &z[static_cast<std::size_t>(N * e)], e, order, d);
    sum += d.jacobian(0, 0) + d.hessians[0](0, N - 1);
  }
  return (threadNs() - t0) / count;
}

template <typename S>
double largestDifference(const S& stage, const std::vector<double>& z, int order) {
  constexpr int N = S::kInputs;
  double worst = 0.0;
  for (std::size_t e = 0; e * N < z.size(); ++e) {
    StageDerivativesOf<S> a, b;
    for (auto& h : a.hessians) h.setZero();
    for (auto& h : b.hessians) h.setZero();
    stageDerivativesFromJets<S, N>(stage, &z[e * N], static_cast<int>(e), order, a);
    stageDerivativesFromJets(stage, &z[e * N], static_cast<int>(e), order, b);
    worst = std::max(worst, relativeDifference(a.jacobian, b.jacobian));
    for (int k = 0; k < S::kOutputs; ++k) worst = std::max(worst, relativeDifference(a.hessians[k], b.hessians[k]));
  }
  return worst;
}

template <typename S>
void addRows(const char* name, const S& stage, const std::vector<double>& z, int repeats,
             std::vector<StageJetWidthRow>& rows) {
  constexpr int N = S::kInputs;
  for (int order = 1; order <= 2; ++order) {
    std::vector<double> plain, framework;
    double sum = 0.0;
    timeWidth<N>(stage, z, order, sum);  // warm-up
    for (int r = 0; r < repeats; ++r) {
      plain.push_back(timeWidth<N>(stage, z, order, sum));
      framework.push_back(timeWidth<kJetWidth<N>>(stage, z, order, sum));
    }
    if (!std::isfinite(sum)) throw std::runtime_error(std::string("bench stage-jets: ") + name + " gave a non-finite value");
    std::sort(plain.begin(), plain.end());
    std::sort(framework.begin(), framework.end());
    const double diff = largestDifference(stage, z, order);
    if (!(diff <= 1e-12))
      throw std::runtime_error(std::string("bench stage-jets: ") + name + ": the two widths differ by " + std::to_string(diff));
    rows.push_back({name, order, plain[plain.size() / 2], framework[framework.size() / 2], diff});
  }
}

}  // namespace

std::vector<StageJetWidthRow> benchStageJetWidth(int n, int repeats) {
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, n, n);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  const Eigen::VectorXd x = wavyGridPositions(mesh, false);
  // Per face: c = e0 × e1, the metric a and a second form b near the reference; per edge: the mean of its faces'
  // normals (interior edges).
  const int nf = mesh.numFaces();
  std::vector<double> cross(3 * static_cast<std::size_t>(nf)), metric(cross.size()), second(cross.size()), mean;
  std::vector<Eigen::Vector3d> normal(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    const auto fs = static_cast<std::size_t>(f);
    const Eigen::Vector3i t = mesh.F.row(f).transpose();
    const Eigen::Vector3d p0 = x.segment<3>(3 * t[0]), e0 = x.segment<3>(3 * t[1]) - p0, e1 = x.segment<3>(3 * t[2]) - p0;
    const Eigen::Vector3d c = e0.cross(e1);
    normal[fs] = c.normalized();
    for (int k = 0; k < 3; ++k) cross[3 * fs + static_cast<std::size_t>(k)] = c[k];
    metric[3 * fs] = e0.dot(e0), metric[3 * fs + 1] = e0.dot(e1), metric[3 * fs + 2] = e1.dot(e1);
    for (int k = 0; k < 3; ++k)
      second[3 * fs + static_cast<std::size_t>(k)] = ref.secondFundamentalForm[fs][static_cast<std::size_t>(k)] + 0.01 * (k + 1) * c[k];
  }
  for (int e = 0; e < topo.numEdges(); ++e) {
    if (topo.isBoundaryEdge(e)) continue;
    const Eigen::Vector3d m = 0.5 * (normal[static_cast<std::size_t>(topo.edgeFaces(e, 0))] +
                                     normal[static_cast<std::size_t>(topo.edgeFaces(e, 1))]);
    mean.insert(mean.end(), {m[0], m[1], m[2]});
  }
  std::vector<StageJetWidthRow> rows;
  addRows("unit_normal", UnitNormalStage{}, cross, repeats, rows);
  addRows("kelvin", KelvinStage{}, mean, repeats, rows);
  BendingDensityStage bending;
  bending.ref = &ref, bending.alpha = 0.3, bending.beta = 0.7;
  addRows("bending_density", bending, second, repeats, rows);
  MembraneDensityStage membrane;
  membrane.ref = &ref, membrane.lambda = 0.3, membrane.mu = 0.7;
  addRows("membrane_density", membrane, metric, repeats, rows);
  return rows;
}

}  // namespace jetshell
