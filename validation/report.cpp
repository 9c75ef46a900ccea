#include "validation/report.h"

#include "core/format.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace jetshell::validation {
namespace {

nlohmann::json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

/// The reference's source relative to the source tree, so the JSON does not depend on the checkout's path.
std::string relativeSource(const std::string& source) {
  const std::string root = std::string(JETSHELL_SOURCE_DIR) + "/";
  return source.rfind(root, 0) == 0 ? source.substr(root.size()) : source;
}

}  // namespace

const char* toString(ErrorMeasure m) {
  return m == ErrorMeasure::PerQuantity ? "|q - q_ref| / |q_ref|" : "|q - q_ref| / |(q_ref)| (norm over the row)";
}

std::string formatSummary(const Benchmark& b, const BenchmarkResult& r) {
  std::ostringstream s;
  s << b.title << "\n"
    << "  mesh " << r.resolution.n1 << " x " << r.resolution.n2 << " " << toString(r.resolution.grading) << " ("
    << b.resolutionMeaning << "), "
    << r.vertices << " vertices, " << r.faces << " faces; clamp " << toString(r.clamp) << ", diagonals "
    << toString(r.diagonals) << ", " << toString(r.solver) << "\n"
    << "  " << formatNumber("%.3f", r.wallSeconds) << " s wall, " << formatNumber("%.3f", r.cpuSeconds) << " s CPU, "
    << r.newtonIterations << " Newton iterations, " << r.loadSteps << " steps, " << r.cuts << " cuts; "
    << r.message << "\n"
    << "  max relative error " << formatNumber("%.3f", 100.0 * r.maxRelError) << "%, at lambda = 1 "
    << formatNumber("%.3f", 100.0 * r.finalRelError) << "% (" << toString(b.errorMeasure) << ")\n";
  if (r.maxRelErrorBeyondDigits < r.maxRelError)
    s << "  beyond the reference's printed digits (|q - q_ref| less half a unit of its last digit): max "
      << formatNumber("%.3f", 100.0 * r.maxRelErrorBeyondDigits) << "%\n";
  return s.str();
}

std::string formatTable(const BenchmarkResult& r) {
  std::ostringstream s;
  s << "  lambda";
  for (const std::string& q : r.quantities)
    s << " | " << std::string(std::max<std::size_t>(0, 9 - std::min<std::size_t>(9, q.size())), ' ') << q
      << "  reference  error %";
  s << "\n";
  for (const BenchmarkRow& row : r.rows) {
    s << formatNumber("%8.3f", row.lambda);
    for (std::size_t q = 0; q < row.computed.size(); ++q)
      s << " | " << formatNumber("%9.4f", row.computed[q]) << "  " << formatNumber("%9.4f", row.reference[q]) << "  "
        << formatNumber("%+7.3f", 100.0 * (row.computed[q] >= row.reference[q] ? 1.0 : -1.0) * row.relError[q]);
    s << "\n";
  }
  return s.str();
}

nlohmann::json toJson(const Benchmark& b, const BenchmarkResult& r) {
  nlohmann::json rows = nlohmann::json::array();
  for (const BenchmarkRow& row : r.rows)
    rows.push_back({{"lambda", row.lambda},
                    {"computed", row.computed},
                    {"reference", row.reference},
                    {"rel_error", row.relError},
                    {"rel_error_beyond_digits", row.relErrorBeyondDigits}});
  return {{"name", r.name},
          {"title", b.title},
          {"vertices", r.vertices},
          {"faces", r.faces},
          {"mesh", {r.resolution.n1, r.resolution.n2}},
          {"mesh_meaning", b.resolutionMeaning},
          {"grading", toString(r.resolution.grading)},
          {"clamp", toString(r.clamp)},
          {"diagonals", toString(r.diagonals)},
          {"solver", toString(r.solver)},
          {"wall_seconds", r.wallSeconds},
          {"cpu_seconds", r.cpuSeconds},
          {"newton_iterations", r.newtonIterations},
          {"load_steps", r.loadSteps},
          {"cuts", r.cuts},
          {"completed", r.completed},
          {"message", r.message},
          {"reference_source", relativeSource(b.reference.source)},
          {"error_measure", toString(b.errorMeasure)},
          {"max_rel_error", finiteOrNull(r.maxRelError)},
          {"final_rel_error", finiteOrNull(r.finalRelError)},
          {"max_rel_error_beyond_digits", finiteOrNull(r.maxRelErrorBeyondDigits)},
          {"quantities", r.quantities},
          {"rows", rows}};
}

}  // namespace jetshell::validation
