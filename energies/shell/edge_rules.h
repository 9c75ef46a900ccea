// Boundary-edge rules of the bending term: the normal of the missing ("ghost") neighbour across a boundary edge.
//
// The mid-edge normal of a boundary edge is n̄ = kelvinInversion(½(n + n_ghost)), n the face's current unit
// normal. A rule is one templated function of
//   n       the face's current unit normal (any scalar type T: double, Jets of any nesting depth), and
//   data    per-edge constants fixed when the rule is set (EdgeRuleData: the face's reference unit normal r, and
//           a spare unit vector `axis` for rules that need a direction, e.g. a symmetry plane's normal),
// returning n_ghost. The bending term (energies/shell/bending_term.cpp) differentiates the rule with Jets as a
// 3 → 3 stage (value, Jacobian, Hessians), so a new rule needs no derivatives.
//
// To add a rule: an enumerator before Count, its name in edgeRuleName(), and one case in ghostNormal().
#pragma once

#include "core/scalar.h"

#include <cstdint>
#include <string>

namespace jetshell {

enum class EdgeRule : std::uint8_t {
  PageFree,        // n_ghost = n: the page's free edge (first order)
  ReferenceClamp,  // n_ghost = r: the missing neighbour keeps the reference normal (clamped edge)
  MirroredClamp,   // n_ghost = 2(n·r) r − n: the mean normal stays along r, so n̄ = r/(n·r) (clamped edge)
  Count
};

/// Per-edge constants of a rule.
struct EdgeRuleData {
  double reference[3] = {0.0, 0.0, 1.0};  // r: the face's reference unit normal
  double axis[3] = {0.0, 0.0, 0.0};       // a spare direction for rules that need one (unused so far)
};

/// "page_free" | "reference_clamp" | "mirrored_clamp".
inline const char* edgeRuleName(EdgeRule rule) {
  switch (rule) {
    case EdgeRule::PageFree: return "page_free";
    case EdgeRule::ReferenceClamp: return "reference_clamp";
    case EdgeRule::MirroredClamp: return "mirrored_clamp";
    case EdgeRule::Count: break;
  }
  return "?";
}

/// The rule named `name`; throws InputError (core/mesh.h) listing the names otherwise.
EdgeRule edgeRuleFromString(const std::string& name);

/// The ghost neighbour's normal across a boundary edge of a face with current unit normal n.
template <typename T>
V3<T> ghostNormal(EdgeRule rule, const V3<T>& n, const EdgeRuleData& data) {
  const V3<T> r{{constant<T>(data.reference[0]), constant<T>(data.reference[1]), constant<T>(data.reference[2])}};
  switch (rule) {
    case EdgeRule::ReferenceClamp: return r;
    case EdgeRule::MirroredClamp: return (constant<T>(2.0) * dot(n, r)) * r - n;
    case EdgeRule::PageFree:
    case EdgeRule::Count: break;
  }
  return n;
}

}  // namespace jetshell
