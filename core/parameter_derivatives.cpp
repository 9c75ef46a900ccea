#include "core/parameter_derivatives.h"

#include "core/mesh.h"

#include <cmath>
#include <sstream>

namespace jetshell {

void validateParameterValues(const std::string& term, const std::vector<std::string>& names,
                             const std::vector<double>& values) {
  if (values.size() != names.size()) {
    std::ostringstream s;
    s << "term '" << term << "': " << values.size() << " parameter values given, " << names.size() << " expected";
    throw InputError(s.str());
  }
  for (std::size_t j = 0; j < values.size(); ++j) {
    if (!std::isfinite(values[j])) {
      std::ostringstream s;
      s << "term '" << term << "': parameter '" << names[j] << "' = " << values[j] << ": must be finite";
      throw InputError(s.str());
    }
  }
}

StencilTable vertexStencils(int numVertices) {
  StencilTable t;
  t.width = 1;
  t.ids.resize(static_cast<std::size_t>(numVertices));
  for (int v = 0; v < numVertices; ++v) t.ids[static_cast<std::size_t>(v)] = v;
  return t;
}

}  // namespace jetshell
