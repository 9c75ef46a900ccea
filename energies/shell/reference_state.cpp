#include "energies/shell/reference_state.h"

#include "energies/shell/shell_geometry.h"

namespace jetshell {

ShellReference computeReference(const TriMesh& mesh, const Topology& topology) {
  const int nf = mesh.numFaces();
  ShellReference r;
  r.area.resize(nf);
  r.metric.resize(nf);
  r.inverseMetric.resize(nf);
  r.secondFundamentalForm.resize(nf);
  for (int f = 0; f < nf; ++f) {
    double x[18] = {};
    bool boundary[3];
    for (int k = 0; k < 6; ++k) {
      const int v = topology.bendingStencil(f, k);
      if (v >= 0)
        for (int c = 0; c < 3; ++c) x[3 * k + c] = mesh.V(v, c);
    }
    for (int i = 0; i < 3; ++i) boundary[i] = topology.bendingStencil(f, 3 + i) < 0;
    const V3<double> e0 = load3(x + 3) - load3(x), e1 = load3(x + 6) - load3(x);
    double a[3];
    metric(e0, e1, a);
    const double det = a[0] * a[2] - a[1] * a[1];
    r.metric[f] = {a[0], a[1], a[2]};
    r.inverseMetric[f] = {a[2] / det, -a[1] / det, a[0] / det};
    r.area[f] = 0.5 * std::sqrt(det);
    double b[3];
    stencilSecondFundamentalForm(x, boundary, b);
    r.secondFundamentalForm[f] = {b[0], b[1], b[2]};
  }
  return r;
}

}  // namespace jetshell
