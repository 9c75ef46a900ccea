// `jetshell bench accuracy`: the convergence study of VALIDATION.md. Runs every benchmark at four or more
// mesh resolutions, compares the clamped-edge models and the quad splits, and measures the solver knobs that
// trade time for accuracy; prints markdown tables (error at λ = 1 and over the path, wall and CPU time, Newton
// iterations, observed order), and writes the error-versus-time chart and, with --json, every run.
#include "tools/output/atomic_file.h"
#include "tools/output/directories.h"
#include "core/format.h"
#include "core/mesh.h"
#include "tools/subcommand.h"
#include "tools/validation/validation_plots.h"
#include "validation/benchmark.h"
#include "validation/report.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace jetshell::cli {
namespace {

using namespace jetshell::validation;

const char* const kRingFamily = "page's slit ring, cosine rings, n x 16n";
const char* const kRingAngular = "page's slit ring, 5 cosine rings, angular refinement";

/// One run of the study: a benchmark, a mesh and the options that differ from the defaults.
struct StudyRun {
  std::string group;   // the table it belongs to
  std::string series;  // the line of the chart (and the order-of-convergence pairs)
  std::string benchmark;
  Resolution mesh;
  std::string variant;  // what differs from the defaults, for the table
  std::function<void(BenchmarkRunOptions&)> tweak;
};

std::vector<StudyRun> studyRuns(bool quick, bool large) {
  std::vector<StudyRun> runs;
  auto add = [&](std::string group, std::string series, std::string bench, std::vector<Resolution> meshes,
                 std::string variant, std::function<void(BenchmarkRunOptions&)> tweak) {
    for (const Resolution& m : meshes) runs.push_back({group, series, bench, m, variant, tweak});
  };
  const auto none = [](BenchmarkRunOptions&) {};
  const auto clamp = [](ClampKind k) { return [k](BenchmarkRunOptions& o) { o.clamp = k; }; };
  const auto alternating = [](BenchmarkRunOptions& o) { o.diagonals = QuadDiagonals::Alternating; };

  // 1. Convergence with the defaults (mirrored clamp, uniform diagonals, load stepping).
  const std::vector<Resolution> plate = quick ? std::vector<Resolution>{{2, 16}, {4, 32}, {8, 64}}
                                              : std::vector<Resolution>{{2, 16}, {4, 32}, {8, 64}, {16, 128}};
  const std::vector<Resolution> shear = quick ? std::vector<Resolution>{{10, 1}, {20, 2}, {40, 4}}
                                              : std::vector<Resolution>{{10, 1}, {20, 2}, {40, 4}, {80, 8}};
  const std::vector<Resolution> moment = quick ? std::vector<Resolution>{{12, 1}, {24, 2}, {48, 4}}
                                               : std::vector<Resolution>{{12, 1}, {24, 2}, {48, 4}, {96, 8}};
  const std::vector<Resolution> ring = quick ? std::vector<Resolution>{{2, 32}, {4, 64}, {8, 128}}
                                             : std::vector<Resolution>{{2, 32}, {4, 64}, {8, 128}, {16, 256}};
  add("convergence", "slit annular plate", "slit-annular-plate", plate, "", none);
  add("convergence", "cantilever end shear (Sze)", "cantilever-end-shear", shear, "", none);
  add("convergence", "cantilever end shear (elastica)", "cantilever-end-shear-elastica", shear, "", none);
  add("convergence", "cantilever end moment", "cantilever-end-moment", moment, "", none);
  add("convergence", "page's slit ring (static)", "slit-ring-page", ring, "", none);
  // Angular refinement first: the plate's error is governed by the elements along the slit edges.
  add("anisotropic", "slit annular plate, angular refinement", "slit-annular-plate",
      quick ? std::vector<Resolution>{{2, 64}, {4, 128}} : std::vector<Resolution>{{2, 64}, {4, 128}, {8, 256}},
      "", none);

  // 1b. The slit plate's observed order without the reference: successive differences of the computed path
  // under uniform refinement (both counts doubled), uniform rings and rings graded towards the free edges.
  {
    std::vector<Resolution> meshes = quick ? std::vector<Resolution>{{2, 16}, {4, 32}, {8, 64}}
                                           : std::vector<Resolution>{{2, 16}, {4, 32}, {8, 64}, {16, 128}};
    if (large) meshes.push_back({32, 256});
    add("self-convergence", "slit annular plate, uniform rings", "slit-annular-plate", meshes, "", none);
    for (Resolution& m : meshes) m.grading = MeshGrading::Cosine;
    add("self-convergence", "slit annular plate, cosine rings", "slit-annular-plate", meshes, "cosine rings", none);
    // The page's ring (the plate scaled 1:10) on the n x 16n family with cosine rings.
    const MeshGrading c = MeshGrading::Cosine;
    if (!quick)
      add("self-convergence", "page's slit ring, cosine rings, 3x48 doubled", "slit-ring-page",
          {{3, 48, c}, {6, 96, c}, {12, 192, c}}, "cosine rings", none);
    if (large)
      add("self-convergence", "page's slit ring, cosine rings, 4x64 doubled", "slit-ring-page",
          {{4, 64, c}, {8, 128, c}, {16, 256, c}}, "cosine rings", none);
  }

  // 1c. The page's ring with the best rules (moment-free free edges, mirrored clamp, cosine rings): the family
  // n x 16n (the page's 4 x 64 is n = 4), and angular refinement at 5 rings (at λ = 1 the angular count governs
  // W_B's error), for the error model of the smallest mesh within 1% at W_B (printRingConvergence).
  {
    std::vector<Resolution> family, angular;
    for (int n : quick ? std::vector<int>{4, 6, 8} : std::vector<int>{4, 5, 6, 7, 8, 10, 12})
      family.push_back({n, 16 * n, MeshGrading::Cosine});
    if (large) family.push_back({16, 256, MeshGrading::Cosine});
    for (int n : quick ? std::vector<int>{64, 96, 128} : std::vector<int>{64, 80, 96, 112, 128})
      angular.push_back({5, n, MeshGrading::Cosine});
    add("ring", kRingFamily, "slit-ring-page", family, "cosine rings", none);
    add("ring", kRingAngular, "slit-ring-page", angular, "cosine rings", none);
  }

  // 2. Clamped edges: the two other models on the same meshes.
  for (ClampKind k : {ClampKind::Normal, ClampKind::TwoRow}) {
    const std::string name = std::string(toString(k)) + " clamp";
    add("clamps", "cantilever end shear (elastica), " + name, "cantilever-end-shear-elastica", shear, name,
        clamp(k));
    add("clamps", "cantilever end moment, " + name, "cantilever-end-moment", moment, name, clamp(k));
    add("clamps", "slit annular plate, " + name, "slit-annular-plate",
        std::vector<Resolution>(plate.begin(), plate.end() - 1), name, clamp(k));
    add("clamps", "page's slit ring (static), " + name, "slit-ring-page", {{4, 64}}, name, clamp(k));
  }

  // 3. Quad split: alternating diagonals overestimate the twist 2x.
  add("diagonals", "slit annular plate, alternating diagonals", "slit-annular-plate",
      std::vector<Resolution>(plate.begin(), plate.end() - 1), "alternating diagonals", alternating);
  add("diagonals", "cantilever end shear (elastica), alternating diagonals", "cantilever-end-shear-elastica",
      {{40, 4}}, "alternating diagonals", alternating);
  add("diagonals", "page's slit ring (static), alternating, two-row", "slit-ring-page", {{4, 64}},
      "alternating diagonals, two-row clamp", [](BenchmarkRunOptions& o) {
        o.diagonals = QuadDiagonals::Alternating;
        o.clamp = ClampKind::TwoRow;
      });

  // 4. Solver knobs on fixed meshes: they change the time, not the converged answer.
  const Resolution knobPlate{8, 64};
  add("knobs", "knobs", "slit-annular-plate", {knobPlate}, "defaults", none);
  add("knobs", "knobs", "slit-annular-plate", {knobPlate}, "max increment 0.025",
      [](BenchmarkRunOptions& o) { o.maxIncrement = 0.025; });
  add("knobs", "knobs", "slit-annular-plate", {knobPlate}, "predictor 0 (start from the last equilibrium)",
      [](BenchmarkRunOptions& o) { o.predictorOrder = 0; });
  add("knobs", "knobs", "slit-annular-plate", {knobPlate}, "PSD projection clamp",
      [](BenchmarkRunOptions& o) { o.newton.projection = PsdProjection::Clamp; });
  for (double tol : {1e-3, 1e-4, 1e-8}) {
    char label[48];
    std::snprintf(label, sizeof label, "residual tolerance %g", tol);
    add("knobs", "knobs", "slit-annular-plate", {knobPlate}, label,
        [tol](BenchmarkRunOptions& o) { o.newton.residualTolerance = tol; });
  }
  add("knobs", "knobs", "cantilever-end-moment", {{48, 4}}, "defaults", none);
  add("knobs", "knobs", "cantilever-end-moment", {{48, 4}}, "predictor 0 (start from the last equilibrium)",
      [](BenchmarkRunOptions& o) { o.predictorOrder = 0; });

  // 5. The page's example as the page runs it: dynamic relaxation, Δt = 1/30 s, α_R = 0.3 1/s.
  if (!quick) {
    add("relaxation", "page's slit ring (relaxation)", "slit-ring-page-relaxation", {{4, 64}}, "two-row clamp",
        clamp(ClampKind::TwoRow));
    add("relaxation", "page's slit ring (relaxation)", "slit-ring-page-relaxation", {{4, 64}}, "mirrored clamp",
        none);
  }
  // 6. The smallest meshes found to reach 1% on the slit ring (minutes each).
  if (large)
    add("one-percent", "page's slit ring (static), fine meshes", "slit-ring-page", {{12, 384}, {16, 512}}, "", none);
  return runs;
}

std::string percent(double e) { return std::isfinite(e) ? formatNumber("%.3f", 100.0 * e) : "failed"; }

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

struct Done {
  StudyRun run;
  BenchmarkResult result;
};

/// Observed order between this run and the previous one of the same series, from the error at λ = 1 and the
/// mean edge length (∝ 1/√faces for these structured meshes).
std::string order(const Done* previous, const Done& d, bool finalError) {
  if (previous == nullptr) return "";
  const double e0 = finalError ? previous->result.finalRelError : previous->result.maxRelError;
  const double e1 = finalError ? d.result.finalRelError : d.result.maxRelError;
  const double h0 = 1.0 / std::sqrt(static_cast<double>(previous->result.faces));
  const double h1 = 1.0 / std::sqrt(static_cast<double>(d.result.faces));
  if (!(e0 > 0.0 && e1 > 0.0 && std::isfinite(e0) && std::isfinite(e1))) return "";
  return fixed(std::log(e0 / e1) / std::log(h0 / h1), 2);
}

/// The largest |q_a − q_b| / |q_ref| over every level and quantity of two runs of one benchmark; at one row
/// (row ≥ 0) or over all (row = −1). NaN when a run is incomplete.
double pathDifference(const BenchmarkResult& a, const BenchmarkResult& b, int row) {
  if (!a.completed || !b.completed || a.rows.size() != b.rows.size()) return std::nan("");
  double d = 0.0;
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    if (row >= 0 && static_cast<int>(i) != row) continue;
    for (std::size_t q = 0; q < a.rows[i].computed.size(); ++q)
      d = std::max(d, std::abs(a.rows[i].computed[q] - b.rows[i].computed[q]) / std::abs(a.rows[i].reference[q]));
  }
  return d;
}

/// Self-convergence: for each series of the self-convergence group (each mesh doubles both counts), the
/// differences between successive meshes and the observed order log2(d_k / d_{k+1}), which needs no reference.
void printSelfConvergence(const std::vector<Done>& done) {
  std::vector<const Done*> runs;
  for (const Done& d : done)
    if (d.run.group == "self-convergence") runs.push_back(&d);
  if (runs.size() < 3) return;
  std::cout << "\n### self-convergence (differences between successive meshes, relative to the reference values)\n\n"
            << "| series | meshes | max difference % (all levels) | order | difference at λ=0.025 % | order | "
               "difference at λ=1 % | order |\n|---|---|---:|---:|---:|---:|---:|---:|\n";
  auto ord = [](double d0, double d1) {
    return d0 > 0.0 && d1 > 0.0 && std::isfinite(d0) && std::isfinite(d1) ? fixed(std::log2(d0 / d1), 2)
                                                                           : std::string();
  };
  for (std::size_t k = 0; k + 1 < runs.size(); ++k) {
    const Done& a = *runs[k];
    const Done& b = *runs[k + 1];
    if (a.run.series != b.run.series) continue;
    const int last = static_cast<int>(a.result.rows.size()) - 1;
    const double d[3] = {pathDifference(a.result, b.result, -1), pathDifference(a.result, b.result, 0),
                         pathDifference(a.result, b.result, last)};
    std::string o[3];
    if (k > 0 && runs[k - 1]->run.series == a.run.series) {
      const BenchmarkResult& p = runs[k - 1]->result;
      const double e[3] = {pathDifference(p, a.result, -1), pathDifference(p, a.result, 0),
                           pathDifference(p, a.result, last)};
      for (int i = 0; i < 3; ++i) o[i] = ord(e[i], d[i]);
    }
    std::cout << "| " << a.run.series << " | " << a.result.resolution.n1 << "x" << a.result.resolution.n2 << " → "
              << b.result.resolution.n1 << "x" << b.result.resolution.n2 << " | " << percent(d[0]) << " | " << o[0]
              << " | " << percent(d[1]) << " | " << o[1] << " | " << percent(d[2]) << " | " << o[2] << " |\n";
  }
}

/// The signed relative error of quantity `name` at λ = 1 (NaN when the run is incomplete or has no such quantity).
double finalSignedError(const BenchmarkResult& r, const std::string& name) {
  const auto at = std::find(r.quantities.begin(), r.quantities.end(), name);
  if (!r.completed || r.rows.empty() || at == r.quantities.end()) return std::nan("");
  const BenchmarkRow& row = r.rows.back();
  const std::size_t q = static_cast<std::size_t>(at - r.quantities.begin());
  return (row.computed[q] - row.reference[q]) / std::abs(row.reference[q]);
}

/// The ring's error model: per series of the ring group, the error e at W_B (λ = 1) and over the path against
/// the angular count n2 (h ∝ 1/n2 in both series: n x 16n, and 5 x n2), the least-squares fit e = C n2^−p in
/// log-log over the runs with at least 5 rings (4 rings sit in the free edges' pre-asymptotic range), the n2 and
/// vertex count it predicts for 1%, and the smallest measured meshes within 1%.
void printRingConvergence(const std::vector<Done>& done) {
  std::vector<const Done*> runs;
  for (const Done& d : done)
    if (d.run.group == "ring") runs.push_back(&d);
  if (runs.empty()) return;
  std::cout << "\n### ring: error model (W_B at λ = 1, and the max over all levels and both points)\n\n"
            << "| series | mesh | vertices | W_B error at λ=1 % | max error % | CPU s | wall s |\n"
               "|---|---|---:|---:|---:|---:|---:|\n";
  const Done* smallestB = nullptr;
  const Done* smallestAll = nullptr;
  for (const Done* d : runs) {
    const BenchmarkResult& r = d->result;
    const double eB = finalSignedError(r, "W_B");
    std::cout << "| " << d->run.series << " | " << r.resolution.n1 << "x" << r.resolution.n2 << " | " << r.vertices
              << " | " << (std::isfinite(eB) ? fixed(100.0 * eB, 3) : "failed") << " | " << percent(r.maxRelError)
              << " | " << fixed(r.cpuSeconds, 2) << " | " << fixed(r.wallSeconds, 2) << " |\n";
    if (std::abs(eB) < 0.01 && (smallestB == nullptr || r.vertices < smallestB->result.vertices)) smallestB = d;
    if (r.completed && r.maxRelError < 0.01 && (smallestAll == nullptr || r.vertices < smallestAll->result.vertices))
      smallestAll = d;
  }
  std::cout << "\n| series | measure | fitted order p | constant C (e = C n2^-p) | n2 for 1% | vertices |\n"
               "|---|---|---:|---:|---:|---:|\n";
  for (const std::string series : {kRingFamily, kRingAngular}) {
    const bool family = series == kRingFamily;
    for (int measure = 0; measure < 2; ++measure) {
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      int count = 0;
      for (const Done* d : runs) {
        const BenchmarkResult& r = d->result;
        if (d->run.series != series || r.resolution.n1 < 5) continue;
        const double e = measure == 0 ? std::abs(finalSignedError(r, "W_B")) : r.maxRelError;
        if (!(e > 0.0) || !std::isfinite(e)) continue;
        const double x = std::log(static_cast<double>(r.resolution.n2)), y = std::log(e);
        sx += x, sy += y, sxx += x * x, sxy += x * y, ++count;
      }
      if (count < 2) continue;
      const double slope = (count * sxy - sx * sy) / (count * sxx - sx * sx);
      const double p = -slope, C = std::exp((sy - slope * sx) / count);
      const double n2 = p > 0.0 ? std::pow(C / 0.01, 1.0 / p) : std::nan("");
      std::string vertices = "-";
      if (std::isfinite(n2) && n2 < 1e5) {
        const double n1 = family ? std::ceil(n2 / 16.0) : 5.0;
        const double a = family ? 16.0 * n1 : std::ceil(n2);
        vertices = std::to_string(static_cast<long long>((n1 + 1.0) * (a + 1.0)));
      }
      std::cout << "| " << series << " | " << (measure == 0 ? "W_B at λ=1" : "max over the path") << " | "
                << fixed(p, 2) << " | " << fixed(C, 3) << " | " << (std::isfinite(n2) ? fixed(n2, 0) : "-") << " | "
                << vertices << " |\n";
    }
  }
  auto name = [](const Done* d) {
    return d == nullptr ? std::string("none measured")
                        : std::to_string(d->result.resolution.n1) + "x" + std::to_string(d->result.resolution.n2) +
                              " (" + std::to_string(d->result.vertices) + " vertices, " +
                              fixed(d->result.cpuSeconds, 2) + " CPU s, " + fixed(d->result.wallSeconds, 2) +
                              " wall s)";
  };
  std::cout << "\nsmallest measured within 1% at W_B (λ = 1): " << name(smallestB)
            << "\nsmallest measured within 1% at every level and both points: " << name(smallestAll) << "\n";
}

int runStudy(bool quick, bool large, const std::string& jsonPath, const std::string& chartPath, const std::string& only) {
  std::vector<Done> done;
  nlohmann::json all = nlohmann::json::array();
  for (const StudyRun& run : studyRuns(quick, large)) {
    if (!only.empty() && run.group != only) continue;
    const Benchmark& b = findBenchmark(run.benchmark);
    BenchmarkRunOptions o;
    o.resolution = run.mesh;  // with the run's grading (uniform unless the run says otherwise)
    o.defaultGrading = false;
    run.tweak(o);
    BenchmarkResult r = runBenchmark(b, o);
    std::cerr << run.group << " | " << run.series << " | " << r.resolution.n1 << "x" << r.resolution.n2 << " "
              << run.variant << ": max " << percent(r.maxRelError) << "%, final " << percent(r.finalRelError)
              << "%, " << fixed(r.wallSeconds, 2) << " s\n";
    nlohmann::json j = toJson(b, r);
    j["group"] = run.group;
    j["series"] = run.series;
    j["variant"] = run.variant;
    all.push_back(std::move(j));
    done.push_back({run, std::move(r)});
  }

  std::string group;
  const Done* previous = nullptr;
  for (const Done& d : done) {
    if (d.run.group != group) {
      group = d.run.group;
      std::cout << "\n### " << group << "\n\n"
                << "| series | variant | mesh | vertices | max error % | error at λ=1 % | order (max) | order (λ=1) "
                   "| wall s | CPU s | Newton it. | steps | cuts |\n"
                << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
      previous = nullptr;
    }
    if (previous != nullptr && previous->run.series != d.run.series) previous = nullptr;
    const bool ordered = d.run.group != "knobs" && d.run.group != "relaxation";
    const BenchmarkResult& r = d.result;
    std::cout << "| " << d.run.series << " | " << d.run.variant << " | " << r.resolution.n1 << "x"
              << r.resolution.n2 << " | " << r.vertices << " | " << percent(r.maxRelError) << " | "
              << percent(r.finalRelError) << " | " << (ordered ? order(previous, d, false) : "") << " | "
              << (ordered ? order(previous, d, true) : "") << " | " << fixed(r.wallSeconds, 2) << " | "
              << fixed(r.cpuSeconds, 2) << " | " << r.newtonIterations << " | " << r.loadSteps << " | " << r.cuts
              << " |\n";
    previous = &d;
  }

  printSelfConvergence(done);
  printRingConvergence(done);

  if (!chartPath.empty()) {
    std::vector<ErrorTimePoint> points;
    for (const Done& d : done)
      if (d.run.group == "convergence" || d.run.group == "anisotropic" || d.run.group == "one-percent" ||
          (d.run.group == "clamps" && d.run.series.find("two-row") != std::string::npos))
        points.push_back({d.run.series, d.result.cpuSeconds, d.result.maxRelError, d.run.benchmark,
                          d.run.group == "clamps" ? 2 : d.run.group == "anisotropic" ? 3 : 1});
    try {
      plotErrorVersusTime(points, "CPU seconds (whole load path)", chartPath);
      std::cout << "\nchart: " << chartPath << "\n";
    } catch (const InputError& e) {
      std::cout << "\nnote: no chart (" << e.what() << ")\n";
    }
  }
  if (!jsonPath.empty()) {
    writeFileAtomically(jsonPath, all.dump(2) + "\n");
  }
  return kOk;
}

const RegisterSubcommand registerBenchAccuracy("bench_accuracy", [](CLI::App& app, int& exitCode) {
  struct Args {
    bool quick = false;
    bool large = false;
    std::string json;
    std::string chart = "validation-output/error_vs_time.png";
    std::string only;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = benchCommand(app)->add_subcommand(
      "accuracy", "The convergence study of VALIDATION.md: error against mesh, clamp, quad split and solver knobs");
  cmd->add_flag("--quick", a->quick, "Three meshes per benchmark and no relaxation runs (about a minute)");
  cmd->add_flag("--large", a->large, "Also the fine slit-ring meshes that reach 1% (several minutes each)");
  cmd->add_option("--json", a->json, "Write every run to this JSON file");
  cmd->add_option("--chart", a->chart, "Error-versus-time PNG (default validation-output/error_vs_time.png; '' for none)");
  cmd->add_option("--only", a->only, "Run one group: convergence, self-convergence, ring, anisotropic, clamps, diagonals, knobs, relaxation, one-percent");
  cmd->callback([a, &exitCode] {
    if (!a->chart.empty()) {
      const std::string dir = a->chart.substr(0, a->chart.find_last_of('/'));
      if (dir != a->chart) createOutputDirectory(dir, "--chart");
    }
    checkOutputOption(a->json, "--json");  // here, not on the command line: it may go in the --chart directory
    exitCode = runStudy(a->quick, a->large, a->json, a->chart, a->only);
  });
});

}  // namespace
}  // namespace jetshell::cli
