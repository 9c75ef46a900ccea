// Benchmark results as text tables and JSON.
#pragma once

#include "validation/benchmark.h"

#include <nlohmann/json.hpp>

#include <string>

namespace jetshell::validation {

/// A one-line description of the run: mesh, clamp, diagonals, solver, vertices, time, iterations, errors.
std::string formatSummary(const Benchmark& benchmark, const BenchmarkResult& result);

/// The comparison table: λ, then per quantity the computed value, the reference and the relative error (%).
std::string formatTable(const BenchmarkResult& result);

/// {name, vertices, faces, mesh, clamp, diagonals, solver, wall_seconds, cpu_seconds, newton_iterations,
///  load_steps, cuts, completed, message, error_measure, max_rel_error, final_rel_error, quantities,
///  rows: [{lambda, computed[], reference[], rel_error[]}]}. Errors of an incomplete run are null.
nlohmann::json toJson(const Benchmark& benchmark, const BenchmarkResult& result);

const char* toString(ErrorMeasure m);

}  // namespace jetshell::validation
