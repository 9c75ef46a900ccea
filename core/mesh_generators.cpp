#include "core/mesh_generators.h"

#include <sstream>

namespace jetshell {

TriMesh makeRectangleGrid(double width, double height, int nx, int ny) {
  if (nx < 1 || ny < 1) {
    std::ostringstream s;
    s << "rectangle grid: nx = " << nx << ", ny = " << ny << ": both must be >= 1";
    throw InputError(s.str());
  }
  if (!(width > 0) || !(height > 0)) throw InputError("rectangle grid: width and height must be > 0");
  TriMesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.V.row(j * (nx + 1) + i) << width * i / nx, height * j / ny, 0.0;
  m.F.resize(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int v00 = j * (nx + 1) + i, v10 = v00 + 1, v01 = v00 + nx + 1, v11 = v01 + 1;
      if ((i + j) % 2 == 0) {
        m.F.row(f++) << v00, v10, v11;
        m.F.row(f++) << v00, v11, v01;
      } else {
        m.F.row(f++) << v00, v10, v01;
        m.F.row(f++) << v10, v11, v01;
      }
    }
  }
  return m;
}

}  // namespace jetshell
