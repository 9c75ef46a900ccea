#include "tools/fit/fit_options.h"

#include "core/mesh.h"

namespace jetshell {

const char* toString(FitAlgorithm a) {
  switch (a) {
    case FitAlgorithm::Bobyqa: return "bobyqa";
    case FitAlgorithm::NelderMead: return "nelder-mead";
    case FitAlgorithm::Lbfgs: return "lbfgs";
    case FitAlgorithm::Mma: return "mma";
    case FitAlgorithm::LevenbergMarquardt: return "levenberg-marquardt";
  }
  return "?";
}

FitAlgorithm fitAlgorithmFromString(const std::string& name) {
  for (FitAlgorithm a : {FitAlgorithm::Bobyqa, FitAlgorithm::NelderMead, FitAlgorithm::Lbfgs, FitAlgorithm::Mma,
                         FitAlgorithm::LevenbergMarquardt})
    if (name == toString(a)) return a;
  throw InputError("algorithm '" + name + "' is not one of: bobyqa, nelder-mead, lbfgs, mma, levenberg-marquardt");
}

bool usesDerivatives(FitAlgorithm a) {
  return a == FitAlgorithm::Lbfgs || a == FitAlgorithm::Mma || a == FitAlgorithm::LevenbergMarquardt;
}

}  // namespace jetshell
