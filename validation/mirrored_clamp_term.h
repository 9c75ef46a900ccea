// A stopgap that turns BendingTerm's clamped boundary edges into mirrored ones, measured in the convergence
// study (VALIDATION.md, "Clamped edges") until BendingTerm offers the choice itself.
//
// BendingTerm::setClampedBoundary sets the missing neighbour's normal of a clamped edge to the face's reference
// normal r, so the mid-edge normal there is the Kelvin-inverted mean of the face normal n and r: it turns by
// about half the face's rotation, and the clamp behaves like one sitting about an element behind the edge
// (linear cantilevers come out 1.5·h/L too soft). Mirroring the face normal about r instead,
// n_B = 2(n·r) r − n, makes the mean (n·r) r and the mid-edge normal r/(n·r): it stays along the reference
// normal, as a clamped edge's normal should, and still diverges like the interior Kelvin inversion when the
// face folds over.
//
// The term adds, per face with a clamped edge, area · (W_b(B − b_mirrored) − W_b(B − b_reference-normal)), so
// bending + this term = the mirrored clamp. It is an ElementEnergyTerm over the face's six-vertex bending
// stencil (nested Jets: no hand derivatives; only the few clamped faces are elements).
#pragma once

#include "core/mesh.h"
#include "energies/shell/reference_state.h"
#include "core/scalar.h"
#include "core/topology.h"
#include "energies/element_energy_term.h"
#include "energies/shell/shell_geometry.h"

#include <memory>
#include <vector>

namespace jetshell::validation {

struct MirroredClampEnergy {
  static constexpr int kVertices = 6;
  struct Element {
    double area;
    double B[3], Ainv[3];
    double reference[3];  // the face's reference unit normal r
    bool boundary[3], clamped[3];
  };
  std::shared_ptr<const std::vector<Element>> elements;
  double alpha = 0.0, beta = 0.0;

  template <typename T>
  T operator()(const T* x, int e) const {
    const Element& el = (*elements)[static_cast<std::size_t>(e)];
    const V3<T> p[3] = {load3(x), load3(x + 3), load3(x + 6)};
    const V3<T> e0 = p[1] - p[0], e1 = p[2] - p[0];
    const V3<T> n = unitNormal(cross(e0, e1));
    const V3<T> r{{constant<T>(el.reference[0]), constant<T>(el.reference[1]), constant<T>(el.reference[2])}};
    V3<T> mirrored[3], referenceRule[3];
    for (int i = 0; i < 3; ++i) {
      if (el.clamped[i]) {
        mirrored[i] = midEdgeNormal(n, constant<T>(2.0) * dot(n, r) * r - n);
        referenceRule[i] = midEdgeNormal(n, r);
      } else if (el.boundary[i]) {
        mirrored[i] = referenceRule[i] = midEdgeNormal(n, n);
      } else {
        // The neighbour traverses edge i backwards: (p[i+2], p[i+1], opposite).
        const V3<T>& q0 = p[(i + 2) % 3];
        const V3<T> nB = unitNormal(cross(p[(i + 1) % 3] - q0, load3(x + 9 + 3 * i) - q0));
        mirrored[i] = referenceRule[i] = midEdgeNormal(n, nB);
      }
    }
    T bMirrored[3], bReference[3];
    secondFundamentalForm(e0, e1, mirrored[0], mirrored[1], mirrored[2], bMirrored);
    secondFundamentalForm(e0, e1, referenceRule[0], referenceRule[1], referenceRule[2], bReference);
    return constant<T>(el.area) * (bendingDensity(bMirrored, el.B, el.Ainv, alpha, beta) -
                                   bendingDensity(bReference, el.B, el.Ainv, alpha, beta));
  }
};

using MirroredClampTerm = ElementEnergyTerm<MirroredClampEnergy>;

/// The correction for the boundary edges whose two endpoints are marked in clampedVertices (size N), the
/// same selection as BendingTerm::setClampedBoundary. Null when no edge is clamped.
std::shared_ptr<MirroredClampTerm> makeMirroredClampTerm(const TriMesh& mesh, const Topology& topology,
                                                         const ShellReference& reference, double alpha,
                                                         double beta, const std::vector<char>& clampedVertices);

}  // namespace jetshell::validation
