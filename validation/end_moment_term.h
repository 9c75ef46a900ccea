// An end moment as an energy term, −λ·M·θ, written only as a templated element energy: the framework's Jets
// give its gradient and Hessian (no hand derivatives).
//
// A displacement-only shell has no rotational dofs, so a moment acts through the rotation θ of the loaded
// edge, measured from the faces along it: each boundary segment of the loaded edge contributes
// −λ · M · (segment length / edge length) · θ_f, with θ_f the rotation of its face's normal about the moment
// axis. θ_f is unwrapped: it is the rotation stored at the last advance() plus the signed angle (atan2) from
// the normal stored then, so it passes π and 2π as long as one step turns a face by less than π.
#pragma once

#include "core/mesh.h"
#include "core/scalar.h"
#include "energies/element_energy_term.h"

#include <Eigen/Core>

#include <cmath>
#include <memory>
#include <vector>

namespace jetshell::validation {

/// The element energy: one element per loaded boundary segment, stencil = its face's three vertices.
struct EndMomentEnergy {
  static constexpr int kVertices = 3;
  struct Element {
    double moment;     // M × segment share
    double side[3];    // axis × origin: the direction of positive rotation from origin
    double origin[3];  // unit normal at the last advance(), projected on the plane normal to the axis
    double originAngle;
  };
  struct State {
    std::vector<Element> elements;
    double axis[3];  // unit moment axis
    double loadFactor = 1.0;
  };
  std::shared_ptr<State> state;

  /// Rotation θ_f of element e at positions x (the face's 9 coordinates). The face normal's scale cancels in
  /// atan2, so the cross product e0 × e1 serves unnormalized.
  template <typename T>
  T rotation(const T* x, int e) const {
    const Element& el = state->elements[static_cast<std::size_t>(e)];
    const V3<T> p0 = load3(x), p1 = load3(x + 3), p2 = load3(x + 6);
    const V3<T> c = cross(p1 - p0, p2 - p0);
    const V3<T> side{{constant<T>(el.side[0]), constant<T>(el.side[1]), constant<T>(el.side[2])}};
    const V3<T> origin{{constant<T>(el.origin[0]), constant<T>(el.origin[1]), constant<T>(el.origin[2])}};
    using std::atan2;
    return constant<T>(el.originAngle) + atan2(dot(side, c), dot(origin, c));
  }

  template <typename T>
  T operator()(const T* x, int e) const {
    return constant<T>(-state->loadFactor * state->elements[static_cast<std::size_t>(e)].moment) * rotation(x, e);
  }
};

class EndMomentTerm : public ElementEnergyTerm<EndMomentEnergy> {
 public:
  /// Use makeEndMomentTerm; table holds one face (3 vertex ids) per element.
  EndMomentTerm(int numVertices, StencilTable table, std::shared_ptr<EndMomentEnergy::State> state);

  void setLoadFactor(double lambda) { functor().state->loadFactor = lambda; }
  double loadFactor() const { return functor().state->loadFactor; }

  /// Makes x the unwrapping origin: stores every face's current rotation and normal. Call after each
  /// accepted load step.
  void advance(const Eigen::VectorXd& x);

  /// Load-weighted mean rotation of the loaded faces at x (radians, unwrapped).
  double meanRotation(const Eigen::VectorXd& x) const;

 private:
  std::vector<int> faces_;  // per element: the face's vertex ids, 3 each
};

/// The end-moment term on the loaded edge `chain` (its vertices in order; consecutive pairs must be
/// boundary edges of the mesh) about `axis` (normalized here); `moment` is the total at load factor 1,
/// positive when it turns the faces' normals by the right-hand rule about the axis, and is shared among the
/// segments by reference length. Throws InputError when a chain segment is not a boundary edge or the axis
/// is zero or parallel to a face normal.
std::shared_ptr<EndMomentTerm> makeEndMomentTerm(const TriMesh& mesh, const std::vector<int>& chain,
                                                 const Eigen::Vector3d& axis, double moment);

}  // namespace jetshell::validation
