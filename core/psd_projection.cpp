#include "core/psd_projection.h"

#include "core/mesh.h"

namespace jetshell {

PsdProjection psdProjectionFromString(const std::string& name) {
  if (name == "none") return PsdProjection::None;
  if (name == "clamp") return PsdProjection::Clamp;
  if (name == "abs") return PsdProjection::Abs;
  throw InputError("projection: '" + name + "' is not one of none, clamp, abs");
}

const char* toString(PsdProjection p) {
  switch (p) {
    case PsdProjection::None: return "none";
    case PsdProjection::Clamp: return "clamp";
    case PsdProjection::Abs: return "abs";
  }
  return "?";
}

#define JETSHELL_INSTANTIATE_PSD_PROJECTION(N) template bool projectPsd<N>(Eigen::Matrix<double, N, N>&, PsdProjection);
JETSHELL_PSD_PROJECTION_SIZES(JETSHELL_INSTANTIATE_PSD_PROJECTION)
#undef JETSHELL_INSTANTIATE_PSD_PROJECTION

}  // namespace jetshell
