// An end moment as an energy term, −λ·M·θ, written only as a templated element energy: the framework's Jets
// give its gradient and Hessian (no hand derivatives). The load factor λ is a differentiable parameter
// ("load_factor"). Used by the validation benchmarks (validation/benchmarks.cpp) and available to any scene.
//
// A displacement-only shell has no rotational dofs, so a moment acts through the rotation θ of the loaded
// edge, measured from the faces along it: each boundary segment of the loaded edge contributes
// −λ · M · (segment length / edge length) · θ_f, with θ_f the rotation of its face's normal about the
// segment's current direction (oriented along the moment axis given at construction). A fixed axis would not
// do: a face twisted until its normal points along that axis has no angle about it, and the potential would
// release energy by twisting through that pole (measured: load stepping of the end-moment cantilever left the
// rolled-up branch at λ = 0.83). θ_f is unwrapped: it is the angle stored at the last advance() plus the
// signed angle (atan2) about the current segment direction from the normal stored then, carried along by the
// smallest rotation that takes the stored segment direction to the current one (so twisting the edge about
// another axis does not count). It passes π and 2π as long as one step turns a face by less than π.
#pragma once

#include "core/mesh.h"
#include "core/scalar.h"
#include "core/topology.h"
#include "energies/element_energy_term.h"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace jetshell {

/// The element energy: one element per loaded boundary segment, stencil = its face's three vertices.
struct EndMomentEnergy {
  static constexpr int kVertices = 3;
  struct Element {
    double moment;      // M × segment share
    int from, to;       // local indices (0..2) of the segment's ends, ordered along the moment axis
    double origin[3];   // unit face normal at the last advance()
    double originAxis[3];  // unit segment direction (from → to) at the last advance()
    double originAngle;
  };
  struct State {
    std::vector<Element> elements;
  };
  std::shared_ptr<State> state;
  static constexpr int kParameters = 1;
  static constexpr std::array<const char*, 1> kParameterNames{{"load_factor"}};
  std::array<double, 1> parameters{{1.0}};  // λ

  /// Rotation θ_f of element e at positions x (the face's 9 coordinates). The stored normal o is carried by
  /// the smallest rotation taking the stored direction u to the current one a (Rodrigues with w = u × a:
  /// o' = (u·a) o + w × o + (w·o)/(1 + u·a) w), then θ_f = stored angle + atan2(a·(o' × c), o'·c); the
  /// scale of the face normal c = e0 × e1 cancels in atan2.
  template <typename T>
  T rotation(const T* x, int e) const {
    const Element& el = state->elements[static_cast<std::size_t>(e)];
    const V3<T> p0 = load3(x), p1 = load3(x + 3), p2 = load3(x + 6);
    const V3<T> c = cross(p1 - p0, p2 - p0);
    const V3<T> segment = load3(x + 3 * el.to) - load3(x + 3 * el.from);
    const V3<T> a = (1.0 / norm(segment)) * segment;
    const V3<T> o{{constant<T>(el.origin[0]), constant<T>(el.origin[1]), constant<T>(el.origin[2])}};
    const V3<T> u{{constant<T>(el.originAxis[0]), constant<T>(el.originAxis[1]), constant<T>(el.originAxis[2])}};
    const V3<T> w = cross(u, a);
    const T cosine = dot(u, a);
    const V3<T> carried = cosine * o + cross(w, o) + (dot(w, o) / (1.0 + cosine)) * w;
    using std::atan2;
    return el.originAngle + atan2(dot(a, cross(carried, c)), dot(carried, c));
  }

  template <typename T>
  T operator()(const T* x, const T* p, int e) const {
    return -p[0] * state->elements[static_cast<std::size_t>(e)].moment * rotation(x, e);
  }
};

class EndMomentTerm : public ElementEnergyTerm<EndMomentEnergy> {
 public:
  /// Use makeEndMomentTerm; table holds one face (3 vertex ids) per element.
  EndMomentTerm(int numVertices, const StencilTable& table, std::shared_ptr<EndMomentEnergy::State> state,
                std::string name = "end_moment");

  void setLoadFactor(double lambda) { functor().parameters[0] = lambda; }
  double loadFactor() const { return functor().parameters[0]; }

  /// Makes x the unwrapping origin: stores every face's current rotation and normal. Call after each
  /// accepted load step.
  void advance(const Eigen::VectorXd& x);

  /// Load-weighted mean rotation of the loaded faces at x (radians, unwrapped).
  double meanRotation(const Eigen::VectorXd& x) const;

 private:
  std::vector<int> faces_;  // per element: the face's vertex ids, 3 each
};

/// The end-moment term on the loaded edge `chain` (its vertices in order; consecutive pairs must be
/// boundary edges of the mesh). `axis` gives the sense: each segment's rotation is measured about its
/// current direction, oriented the way `axis` points in the reference configuration; `moment` is the total
/// at load factor 1, positive when it turns the faces' normals by the right-hand rule about that direction,
/// shared among the segments by reference length; `name` is the term's name in an objective. Throws InputError
/// when a chain segment is not a boundary edge or is perpendicular to the axis.
std::shared_ptr<EndMomentTerm> makeEndMomentTerm(const TriMesh& mesh, const std::vector<int>& chain,
                                                 const Eigen::Vector3d& axis, double moment,
                                                 std::string name = "end_moment");
/// The same on the mesh's topology, already built (the shell system's).
std::shared_ptr<EndMomentTerm> makeEndMomentTerm(const TriMesh& mesh, const Topology& topology,
                                                 const std::vector<int>& chain, const Eigen::Vector3d& axis,
                                                 double moment, std::string name = "end_moment");

}  // namespace jetshell
