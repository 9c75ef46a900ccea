// libFuzzer harness: any bytes as an SDF grid file. A grid that parses is bounded as the scene reader bounds it
// (its thinnest part), becomes a shape and is queried inside, on and outside its box. Only InputError may come
// out; anything else (a crash, a sanitizer report, another exception, a hang, memory beyond libFuzzer's
// -rss_limit_mb) is a defect.
#include "core/mesh.h"
#include "energies/contact/sdf_grid.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace jetshell;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    SdfGrid grid = parseSdfGrid(in, "fuzz.sdf");
    const Eigen::Vector3d low = grid.origin;
    const Eigen::Vector3d high = low + grid.spacing * Eigen::Vector3d(grid.nx - 1, grid.ny - 1, grid.nz - 1);
    sdfGridThinnestHalfWidth(grid);  // the scene reader's bound on the thinnest part walks every sample
    const VolumeShapePtr shape = makeSdfGridShape(std::move(grid));
    for (double t : {-0.5, 0.0, 0.37, 1.0, 1.5}) shape->signedDistance(low + t * (high - low));
  } catch (const InputError&) {
  }
  return 0;
}
