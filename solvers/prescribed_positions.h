// Prescribed nodal positions (Dirichlet conditions), per vertex and per component, constant or moving in time.
//
// Prescribed dofs are eliminated from the unknowns, not penalized: the objective marks them fixed in the Hessian
// pattern (identity rows and columns), zeroes their gradient entries, and the solvers write their values into x
// before each solve with apply(t). In statics the "time" is the load factor λ, so a prescribed displacement can
// be ramped with the loads.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <vector>

namespace jetshell {

/// A prescribed coordinate as a function of time t [s] (or of the load factor λ in statics).
using TimeFunction = std::function<double(double t)>;

class PrescribedPositions {
 public:
  struct Entry {
    int vertex;
    int component;       // 0 = x, 1 = y, 2 = z
    TimeFunction value;  // null for a constant
    double constant = 0.0;
  };

  /// Prescribes coordinate `component` (0, 1, 2) of `vertex` to a constant. A later call for the same dof
  /// replaces the earlier one. Throws InputError for a negative vertex or a component outside 0..2.
  void fix(int vertex, int component, double value);
  /// The same, moving in time.
  void fix(int vertex, int component, TimeFunction value);
  /// Prescribes all three coordinates of `vertex` to `position`.
  void fixVertex(int vertex, const Eigen::Vector3d& position);

  bool empty() const { return entries_.empty(); }
  int size() const { return static_cast<int>(entries_.size()); }
  const std::vector<Entry>& entries() const { return entries_; }
  /// True when some entry is a function of time.
  bool timeDependent() const;

  /// The fixed-dof mask (size 3N). Throws InputError naming the entry when a vertex is >= numVertices.
  std::vector<char> dofMask(int numVertices) const;
  /// Writes the prescribed values at time t into x (size 3N). Throws InputError when a value is not finite.
  void apply(double t, Eigen::VectorXd& x) const;
  /// The prescribed value of one entry at time t.
  double valueAt(const Entry& e, double t) const { return e.value ? e.value(t) : e.constant; }

 private:
  void add(Entry e);
  std::vector<Entry> entries_;
};

}  // namespace jetshell
