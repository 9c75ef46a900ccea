#include "solvers/prescribed_positions.h"

#include "core/mesh.h"

#include <cmath>
#include <sstream>

namespace jetshell {

void PrescribedPositions::add(Entry e) {
  if (e.vertex < 0 || e.component < 0 || e.component > 2) {
    std::ostringstream s;
    s << "prescribed position: vertex " << e.vertex << ", component " << e.component
      << ": vertex must be >= 0 and component 0, 1 or 2";
    throw InputError(s.str());
  }
  for (Entry& old : entries_) {
    if (old.vertex == e.vertex && old.component == e.component) {
      old = std::move(e);
      return;
    }
  }
  entries_.push_back(std::move(e));
}

void PrescribedPositions::fix(int vertex, int component, double value) { add({vertex, component, nullptr, value}); }

void PrescribedPositions::fix(int vertex, int component, TimeFunction value) {
  add({vertex, component, std::move(value), 0.0});
}

void PrescribedPositions::fixVertex(int vertex, const Eigen::Vector3d& position) {
  for (int c = 0; c < 3; ++c) fix(vertex, c, position[c]);
}

bool PrescribedPositions::timeDependent() const {
  for (const Entry& e : entries_)
    if (e.value) return true;
  return false;
}

std::vector<char> PrescribedPositions::dofMask(int numVertices) const {
  std::vector<char> mask(3 * static_cast<std::size_t>(numVertices), 0);
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    if (e.vertex >= numVertices) {
      std::ostringstream s;
      s << "prescribed position " << i << ": vertex " << e.vertex << " is out of range (mesh has " << numVertices
        << " vertices)";
      throw InputError(s.str());
    }
    mask[3 * static_cast<std::size_t>(e.vertex) + e.component] = 1;
  }
  return mask;
}

void PrescribedPositions::apply(double t, Eigen::VectorXd& x) const {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    const Entry& e = entries_[i];
    const double v = valueAt(e, t);
    if (!std::isfinite(v)) {
      std::ostringstream s;
      s << "prescribed position " << i << " (vertex " << e.vertex << ", component " << e.component
        << "): value at t = " << t << " is not finite";
      throw InputError(s.str());
    }
    x[3 * e.vertex + e.component] = v;
  }
}

}  // namespace jetshell
