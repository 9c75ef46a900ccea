#include "validation/structured_triangulation.h"

#include <string>

namespace jetshell::validation {

const char* toString(Diagonals d) { return d == Diagonals::Alternating ? "alternating" : "uniform"; }

Diagonals parseDiagonals(const std::string& s) {
  if (s == "alternating") return Diagonals::Alternating;
  if (s == "uniform") return Diagonals::Uniform;
  throw InputError("diagonals: '" + s + "' is not one of: alternating, uniform");
}

Faces uniformDiagonalFaces(int nu, int nv, const std::function<int(int, int)>& id) {
  Faces F(2 * nu * nv, 3);
  int f = 0;
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const int v00 = id(i, j), v10 = id(i + 1, j), v01 = id(i, j + 1), v11 = id(i + 1, j + 1);
      F.row(f++) << v00, v10, v11;
      F.row(f++) << v00, v11, v01;
    }
  }
  return F;
}

}  // namespace jetshell::validation
