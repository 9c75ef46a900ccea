// What a fit file chooses for the optimizer: the algorithm, each fitted variable's start, bounds and scale, and
// the stopping rules. Plain data, read by tools/fit/fit_file.h and used by tools/fit/fit_optimizer.h; it needs
// no solver, so the fit-file reader builds with the other parsers (cmake/parser_sources.cmake).
#pragma once

#include <functional>
#include <string>

namespace jetshell {

enum class FitAlgorithm { Bobyqa, NelderMead, Lbfgs, Mma, LevenbergMarquardt };
const char* toString(FitAlgorithm a);
/// "bobyqa" | "nelder-mead" | "lbfgs" | "mma" | "levenberg-marquardt"; InputError otherwise.
FitAlgorithm fitAlgorithmFromString(const std::string& name);
/// True for the algorithms that use derivatives.
bool usesDerivatives(FitAlgorithm a);

struct FitVariable {
  std::string label;  // for reports, e.g. "strip.youngsModulus"
  double initial = 1.0, lower = 0.0, upper = 1.0;
  bool logScale = false;
};

struct FitOptions {
  FitAlgorithm algorithm = FitAlgorithm::LevenbergMarquardt;
  int maxEvaluations = 200;          // forward evaluations (each a full solve of every level)
  double parameterTolerance = 1e-9;  // stop when a step changes no scaled variable by more than this
  double misfitTolerance = 1e-14;    // stop when a step lowers the misfit by less than this fraction
  /// Asked before each forward evaluation: true stops the fit there, with the best values so far (Ctrl-C).
  std::function<bool()> stopRequested;
};

}  // namespace jetshell
