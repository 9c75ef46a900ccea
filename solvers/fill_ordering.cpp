#include "solvers/fill_ordering.h"

#include "core/mesh.h"

namespace jetshell {

FillOrdering fillOrderingFromString(const std::string& name) {
  if (name == "auto") return FillOrdering::Auto;
  if (name == "amd") return FillOrdering::AMD;
  if (name == "metis") return FillOrdering::METIS;
  if (name == "nesdis") return FillOrdering::NESDIS;
  throw InputError("fill ordering '" + name + "': expected auto, amd, metis or nesdis");
}

const char* toString(FillOrdering o) {
  switch (o) {
    case FillOrdering::Auto: return "auto";
    case FillOrdering::AMD: return "amd";
    case FillOrdering::METIS: return "metis";
    case FillOrdering::NESDIS: return "nesdis";
  }
  return "?";
}

}  // namespace jetshell
