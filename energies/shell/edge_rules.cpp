#include "energies/shell/edge_rules.h"

#include "core/mesh.h"

namespace jetshell {

EdgeRule edgeRuleFromString(const std::string& name) {
  std::string all;
  for (int k = 0; k < static_cast<int>(EdgeRule::Count); ++k) {
    const EdgeRule rule = static_cast<EdgeRule>(k);
    if (name == edgeRuleName(rule)) return rule;
    all += (all.empty() ? "" : ", ") + std::string(edgeRuleName(rule));
  }
  throw InputError("edge rule: '" + name + "' is not one of " + all);
}

}  // namespace jetshell
