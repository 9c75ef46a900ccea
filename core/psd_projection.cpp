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

}  // namespace jetshell
