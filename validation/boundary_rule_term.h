// Boundary-edge rules of the bending term that BendingTerm does not offer yet, as a correction term: per face
// with a boundary edge, area · (W_b(B − b_rule) − W_b(B − b_bending)), so bending + this term = the bending
// energy with the chosen rule on every boundary edge. Measured in VALIDATION.md; a stopgap until the bending
// term takes edge rules itself.
//
// Inputs: the mesh, its topology and reference state, the bending moduli (α, β), the vertices BendingTerm
// clamps (its setClampedBoundary mask: those edges' built-in rule is the reference normal, the others' the
// face's own normal) and a rule per boundary edge. Output: an ElementEnergyTerm over the faces' five-vertex
// stencils (the face and its interior neighbours; nested Jets: no hand derivatives; only faces with a changed
// edge are elements), or null.
//
// Each rule is a ghost normal n_B for the missing neighbour of boundary edge i of face f (normal n):
//   PageFree         n_B = n (the spec's free edge: the mid-edge normal is the face's; first order, VALIDATION.md)
//   ReferenceClamp   n_B = r, the face's reference normal (BendingTerm's clamp: the mid-edge normal turns by
//                    half the face's rotation; first order)
//   MirroredClamp    n_B = 2(n·r) r − n, so the mean is (n·r) r: the mid-edge normal keeps the reference
//                    direction (second order)
//   SecondOrderFree  no ghost: the mid-edge normal is n + a·u (u the unit in-plane direction across the edge)
//                    with a minimized out per face, in closed form (b is affine in a and W_b quadratic in b).
//                    b changes with a by a multiple of u⊗u, so the minimum is the face's energy with no moment
//                    across the edge: the free edge's natural condition M_nn = 0. (A ghost extrapolated from
//                    the face's own stencil cannot be consistent: the curvature across a boundary edge is not
//                    observable from the one-ring of a boundary face; VALIDATION.md.)
//   SymmetryPlane    n_B = n − 2(n·p) p, the face normal mirrored about the plane of unit normal p: the mean
//                    stays in the plane, as the normal of a symmetric shell on its symmetry plane does.
#pragma once

#include "core/mesh.h"
#include "core/scalar.h"
#include "core/topology.h"
#include "energies/element_energy_term.h"
#include "energies/shell/edge_rules.h"
#include "energies/shell/reference_state.h"
#include "energies/shell/shell_geometry.h"

#include <Eigen/Core>

#include <array>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace jetshell::validation {

enum class BoundaryRule : unsigned char { PageFree, ReferenceClamp, MirroredClamp, SecondOrderFree, SymmetryPlane };
const char* toString(BoundaryRule r);
/// The same rule as the bending term's (energies/shell/edge_rules.h) names it.
BoundaryRule toBoundaryRule(EdgeRule r);
/// "page_free", "reference_clamp", "mirrored_clamp", "second_order_free", "symmetry_plane"; InputError otherwise.
BoundaryRule parseBoundaryRule(const std::string& name);

struct BoundaryRuleEnergy {
  /// The face's three vertices and the opposite vertices of its (at most two) interior edges: every element
  /// has a boundary edge, whose missing neighbour would only be three dead dofs (the nested Jets' cost grows as
  /// the square of the dofs: 15 instead of 18 takes about 30% off, measured on the slit plate).
  static constexpr int kVertices = 5;
  struct Element {
    double area;
    double B[3], Ainv[3];  // BendingTerm's curvature origin b(X) (its built-in rules) and A⁻¹
    double Brule[3];       // b(X) with the chosen rules (minimized edges at a = 0): the ruled energy's origin
    double reference[3];  // the face's reference unit normal r
    double plane[3][3];   // per edge: the symmetry plane's unit normal (SymmetryPlane only)
    BoundaryRule rule[3], builtIn[3];
    bool boundary[3];
    int slot[3];  // interior edge i: its neighbour's opposite vertex is stencil vertex 3 + slot[i]
    /// Every changed edge is moment-free and BendingTerm leaves it free: at a = 0 both rules give the edge the
    /// face's normal, so b_rule = b_bending (and B_rule = B) and the term is −½ area gᵀQ⁻¹g alone.
    bool minimizedOnly;
  };
  std::shared_ptr<const std::vector<Element>> elements;
  /// The bending moduli (α, β) as differentiable parameters (energies/element_energy_term.h): a fit that
  /// changes the bending term's moduli changes these too (tools/fit/material_mapping.h).
  static constexpr int kParameters = 2;
  static constexpr std::array<const char*, 2> kParameterNames{{"alpha", "beta"}};
  std::array<double, 2> parameters{{0.0, 0.0}};

  template <typename T>
  static V3<T> neighbourNormal(const T* x, const V3<T>* p, int i, int slot) {
    // The neighbour traverses edge i backwards: (p[i+2], p[i+1], opposite).
    const V3<T>& q0 = p[(i + 2) % 3];
    return unitNormal(cross(p[(i + 1) % 3] - q0, load3(x + 9 + 3 * slot) - q0));
  }

  template <typename T>
  static V3<T> ghost(BoundaryRule rule, const Element& el, int i, const V3<T>& n, const V3<T>& r) {
    switch (rule) {
      case BoundaryRule::ReferenceClamp:
        return r;
      case BoundaryRule::MirroredClamp:
        return constant<T>(2.0) * dot(n, r) * r - n;
      case BoundaryRule::SymmetryPlane: {
        const V3<T> p{{constant<T>(el.plane[i][0]), constant<T>(el.plane[i][1]), constant<T>(el.plane[i][2])}};
        return n - constant<T>(2.0) * dot(n, p) * p;
      }
      case BoundaryRule::PageFree:
      default:
        return n;
    }
  }

  /// The second fundamental forms with the chosen rules (minimized edges at a = 0) and with BendingTerm's;
  /// for each minimized edge j (count returned) the change of b per unit a_j, dbRuled[j].
  template <typename T>
  static int forms(const T* x, const Element& el, T bRuled[3], T bBuiltIn[3], T dbRuled[3][3]) {
    const V3<T> p[3] = {load3(x), load3(x + 3), load3(x + 6)};
    const V3<T> e0 = p[1] - p[0], e1 = p[2] - p[0];
    const V3<T> n = unitNormal(cross(e0, e1));
    const V3<T> r{{constant<T>(el.reference[0]), constant<T>(el.reference[1]), constant<T>(el.reference[2])}};
    V3<T> nb[3];
    for (int i = 0; i < 3; ++i) nb[i] = el.boundary[i] ? n : neighbourNormal(x, p, i, el.slot[i]);
    V3<T> ruled[3], builtIn[3];
    for (int i = 0; i < 3; ++i) {
      if (el.boundary[i] && el.minimizedOnly) {
        ruled[i] = builtIn[i] = n;  // the mid-edge normal of n and a ghost n
      } else if (el.boundary[i]) {
        ruled[i] = midEdgeNormal(n, ghost(el.rule[i], el, i, n, r));
        builtIn[i] = midEdgeNormal(n, ghost(el.builtIn[i], el, i, n, r));
      } else {
        ruled[i] = builtIn[i] = midEdgeNormal(n, nb[i]);
      }
    }
    secondFundamentalForm(e0, e1, ruled[0], ruled[1], ruled[2], bRuled);
    if (el.minimizedOnly)
      for (int k = 0; k < 3; ++k) bBuiltIn[k] = bRuled[k];
    else
      secondFundamentalForm(e0, e1, builtIn[0], builtIn[1], builtIn[2], bBuiltIn);
    int count = 0;
    for (int i = 0; i < 3; ++i) {
      if (!el.boundary[i] || el.rule[i] != BoundaryRule::SecondOrderFree) continue;
      // n̄_i = n + a u, u the unit in-plane direction across edge i (b is linear in the mid-edge normals):
      // secondFundamentalForm(e0, e1, n0, n1, n2) with u as n_i and the other two zero, without the products
      // by zero (b0 = 2(n1 − n0)·e0, b1 = −2 n0·e1, b2 = 2(n2 − n0)·e1).
      const V3<T> t = p[(i + 2) % 3] - p[(i + 1) % 3];
      const V3<T> u = unitNormal(cross(t, n));
      T* db = dbRuled[count];
      const T zero = constant<T>(0.0);
      if (i == 0) {
        db[0] = scaledBy(-2.0, dot(u, e0));
        db[1] = db[2] = scaledBy(-2.0, dot(u, e1));
      } else if (i == 1) {
        db[0] = scaledBy(2.0, dot(u, e0));
        db[1] = db[2] = zero;
      } else {
        db[0] = db[1] = zero;
        db[2] = scaledBy(2.0, dot(u, e1));
      }
      ++count;
    }
    return count;
  }

  /// c·x for a plain number c, entry by entry at every Jet depth (a product with constant<T>(c) would multiply
  /// out every derivative of the constant, which are zeros: four times the work in nested Jets).
  template <typename T>
  static T scaledBy(double c, const T& x) {
    if constexpr (std::is_arithmetic_v<T>) {
      return c * x;
    } else {
      T r;
      r.a = scaledBy(c, x.a);
      for (int i = 0; i < r.v.size(); ++i) r.v[i] = scaledBy(c, x.v[i]);
      return r;
    }
  }

  /// What G(u, v) = α tr(Pu) tr(Pv) + β tr(PuPv) (W_b(κ) = ½ G(κ, κ)) needs of u: tr(Pu) and the 2×2 product Pu
  /// (u symmetric, stored as (00, 01, 11); P likewise), so each pair costs five products.
  template <typename T>
  struct Factored {
    T trace;
    T pu[4];  // (Pu)00, (Pu)01, (Pu)10, (Pu)11
  };
  template <typename T>
  static Factored<T> factor(const T u[3], const double P[3]) {
    Factored<T> f;
    f.pu[0] = scaledBy(P[0], u[0]) + scaledBy(P[1], u[1]);
    f.pu[1] = scaledBy(P[0], u[1]) + scaledBy(P[1], u[2]);
    f.pu[2] = scaledBy(P[1], u[0]) + scaledBy(P[2], u[1]);
    f.pu[3] = scaledBy(P[1], u[1]) + scaledBy(P[2], u[2]);
    f.trace = f.pu[0] + f.pu[3];
    return f;
  }
  template <typename T>
  static T bilinear(const Factored<T>& u, const Factored<T>& v, const T& alpha, const T& beta) {
    return alpha * (u.trace * v.trace) +
           beta * (u.pu[0] * v.pu[0] + u.pu[1] * v.pu[2] + u.pu[2] * v.pu[1] + u.pu[3] * v.pu[3]);
  }

  template <typename T>
  T operator()(const T* x, const T* moduli, int e) const {
    const Element& el = (*elements)[static_cast<std::size_t>(e)];
    const T& alpha = moduli[0];
    const T& beta = moduli[1];
    T bRuled[3], bBuiltIn[3], db[3][3];
    const int m = forms(x, el, bRuled, bBuiltIn, db);
    // minimizedOnly: W(b_rule) and W(b_bending) are the same and cancel.
    T ruledEnergy = el.minimizedOnly ? constant<T>(0.0) : bendingDensity(bRuled, el.Brule, el.Ainv, alpha, beta);
    if (m > 0) {
      // min over a of W(κ0 − Σ a_j δb_j): W(κ0) − ½ gᵀ Q⁻¹ g, g_j = G(κ0, δb_j), Q_jk = G(δb_j, δb_k).
      T k0[3];
      for (int k = 0; k < 3; ++k) k0[k] = constant<T>(el.Brule[k]) - bRuled[k];
      const Factored<T> f0 = factor(k0, el.Ainv);
      Factored<T> fd[3];
      for (int j = 0; j < m; ++j) fd[j] = factor(db[j], el.Ainv);
      T g[3], Q[3][3];
      for (int j = 0; j < m; ++j) {
        g[j] = bilinear(f0, fd[j], alpha, beta);
        for (int k = 0; k <= j; ++k) Q[j][k] = Q[k][j] = bilinear(fd[j], fd[k], alpha, beta);
      }
      // Gaussian elimination (Q is symmetric positive definite for β > 0 and independent directions).
      T y[3];
      for (int j = 0; j < m; ++j) y[j] = g[j];
      for (int c = 0; c < m; ++c)
        for (int r = c + 1; r < m; ++r) {
          const T f = Q[r][c] / Q[c][c];
          for (int k = c; k < m; ++k) Q[r][k] = Q[r][k] - f * Q[c][k];
          y[r] = y[r] - f * y[c];
        }
      T z[3];
      for (int c = m - 1; c >= 0; --c) {
        z[c] = y[c];
        for (int k = c + 1; k < m; ++k) z[c] = z[c] - Q[c][k] * z[k];
        z[c] = z[c] / Q[c][c];
      }
      T reduction = constant<T>(0.0);
      for (int j = 0; j < m; ++j) reduction = reduction + g[j] * z[j];
      ruledEnergy = ruledEnergy - constant<T>(0.5) * reduction;
    }
    if (el.minimizedOnly) return constant<T>(el.area) * ruledEnergy;
    return constant<T>(el.area) * (ruledEnergy - bendingDensity(bBuiltIn, el.B, el.Ainv, alpha, beta));
  }
};

using BoundaryRuleTerm = ElementEnergyTerm<BoundaryRuleEnergy>;

/// The rule of each boundary edge. Edges not listed take `freeRule` when BendingTerm leaves them free and
/// `clampRule` when it clamps them (both endpoints in clampedVertices).
struct BoundaryRules {
  BoundaryRule freeRule = BoundaryRule::PageFree;
  BoundaryRule clampRule = BoundaryRule::ReferenceClamp;
  BoundaryRule builtInClampRule = BoundaryRule::ReferenceClamp;  // what the bending term does on clamped edges
  /// Symmetry planes: a boundary edge whose two endpoints lie on the plane (within tolerance × the mesh's
  /// size) takes SymmetryPlane with that plane, before the free/clamp choice.
  struct Plane {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  };
  std::vector<Plane> symmetryPlanes;
  /// Free edges whose two endpoints are marked here (size N or empty) keep PageFree: edges that carry an
  /// applied moment (the moment-free rule would release the face that takes it).
  std::vector<char> momentLoadedVertices;
  double planeTolerance = 1e-9;
};

/// The correction that turns BendingTerm's boundary edges (clamped by clampedVertices, size N or empty) into
/// `rules`' choices. Null when nothing changes. The term's name is "boundary_rules".
std::shared_ptr<BoundaryRuleTerm> makeBoundaryRuleTerm(const TriMesh& mesh, const Topology& topology,
                                                       const ShellReference& reference, double alpha, double beta,
                                                       const std::vector<char>& clampedVertices,
                                                       const BoundaryRules& rules);

}  // namespace jetshell::validation
