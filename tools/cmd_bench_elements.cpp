// `jetshell bench elements`: per-face cost of the shell energies (value, gradient, Hessian with assembly into
// the cached pattern) on a 200×200-square grid bent into a wavy shape, for the AD and analytic paths, exact
// and Gauss–Newton bending Hessians, 1 thread and all threads. Medians of repeats; peak RSS reported.
// The bending term is a stage graph (energies/shell/bending_graph.cpp); the membrane's default is one composed
// stage per face. --staged adds the rows membrane_staged and shell_staged: the membrane on its stage graph
// (MembraneTerm::setStaged), measured in the same run, so that their ratio to the default means something on a
// busy machine.
// With more than one thread, the speed-up of the shell rows is also timed in interleaved pairs on the wall clock.
// --straight-line adds the row shell_straight (1 thread, exact Hessian): the same stages with the chain rule
// written out for this one graph (tools/bench/straight_line_shell.h), what the stage framework is measured against.
// --term stage-jets times the Jet-differentiated stages alone at two dual widths (tools/bench/stage_jet_width.h).
#include "tools/output/atomic_file.h"
#include "core/assembly.h"
#include "core/garment_generator.h"
#include "core/mesh_generators.h"
#include "core/psd_projection.h"
#include "energies/shell/reference_state.h"
#include "core/topology.h"
#include "energies/examples/hinge_bending.h"
#include "energies/shell/bending_term.h"
#include "energies/shell/shell_terms.h"
#include "tools/bench/stage_jet_width.h"
#include "tools/bench/straight_line_shell.h"
#include "tools/bench/wavy_grid.h"
#include "tools/bench_cloth.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>
#include <omp.h>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace jetshell::cli {
namespace {

struct BenchOptions {
  int n = 200;
  int garment = 0;  // > 0: the T-shirt generator's mesh at this resolution instead of the grid
  bool shuffleFaces = false;  // the faces in a fixed random order
  int repeats = 5;
  std::string json;
  std::string term;  // empty = all
  std::string path;  // empty = both
  int threads = 0;   // 0 = 1 and all
  bool staged = false;  // also the rows membrane_staged, shell_staged (the membrane on its stage graph)
  bool straightLine = false;  // also the shell_straight row (tools/bench/straight_line_shell.h)
  std::string projection = "none";  // every element Hessian projected so (the targets: none)
};

struct Row {
  std::string term, path, hessian, what;
  int threads;
  double nsPerFace;
};

/// CPU time of this thread (one thread) or wall time (more), in ns.
double nowNs() {
  timespec t{};
  clock_gettime(omp_get_max_threads() == 1 ? CLOCK_THREAD_CPUTIME_ID : CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) * 1e9 + static_cast<double>(t.tv_nsec);
}

/// A term on the stage framework against the same energy as one nested-Jet element, value + gradient + exact
/// Hessian with assembly, per stencil, 1 thread (CPU time of the thread):
///   `--term hinge`:   the user's hinge-bending term (energies/examples/hinge_bending.h; 12-dof stencils);
///   `--term midedge`: the mid-edge bending term on the stage framework (its stage graph, Jets; 18-dof
///                     stencils) against its whole-stencil nested-Jet reference (makeBendingTermNestedJet).
int runNestedBench(const BenchOptions& o) {
  const bool hinge = o.term == "hinge";
  const TriMesh mesh = makeRectangleGrid(1.0, 1.0, o.n, o.n);
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  const Eigen::VectorXd x = wavyGridPositions(mesh, false);
  EnergyTermPtr staged, nested;
  if (hinge) {
    staged = makeHingeBendingTerm(mesh, topo, 1.0);
    nested = makeHingeBendingNestedJet(mesh, topo, 1.0);
  } else {
    staged = makeBendingTerm(mesh, topo, ref, 0.3, 0.7);
    nested = makeBendingTermNestedJet(mesh, topo, ref, 0.3, 0.7);
  }
  HessianAssembler assembler;
  const int slot = assembler.addStencils(staged->stencils());
  assembler.finalize(mesh.numVertices());
  Eigen::VectorXd g(x.size());
  const double stencils = staged->stencils().size();
  omp_set_num_threads(o.threads > 0 ? o.threads : 1);
  auto measure = [&](EnergyTerm& term) {
    std::vector<double> times;
    for (int r = 0; r < o.repeats + 1; ++r) {  // the first run warms up
      const double t0 = nowNs();
      assembler.setZero();
      g.setZero();
      EvalOptions opt;
      opt.path = DerivativePath::AutoDiff;
      term.evaluate(x, EvalRequest{&g, &assembler, slot}, opt);
      if (r > 0) times.push_back((nowNs() - t0) / stencils);
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
  };
  const double loadStart = loadAverage();
  const double tStaged = measure(*staged), tNested = measure(*nested);
  const double loadEnd = loadAverage();
  const char* unit = hinge ? "hinge" : "face";
  const int dofs = hinge ? 12 : 18;
  std::printf("jetshell bench elements --term %s: %d stencils of %d dofs, %d thread(s), value + gradient + exact "
              "Hessian with assembly; load average at start %.2f\n  staged (core/stage_graph.h): %10.1f ns/%s\n"
              "  one nested-Jet element:      %10.1f ns/%s\n  nested / staged: %.1fx (target >= 10)\n"
              "load average at end: %.2f\n",
              o.term.c_str(), static_cast<int>(stencils), dofs, omp_get_max_threads(), loadStart, tStaged, unit,
              tNested, unit, tNested / tStaged, loadEnd);
  if (!o.json.empty()) {
    const std::string name = hinge ? "hinge_bending" : "midedge_bending";
    nlohmann::json out = nlohmann::json::array();
    out.push_back({{"term", name}, {"path", "staged"}, {"ns_per_stencil", tStaged}, {"dofs", dofs}});
    out.push_back({{"term", name + "_nested_jet"}, {"path", "nested_jet"}, {"ns_per_stencil", tNested}, {"dofs", dofs}});
    out.push_back({{"nested_over_staged", tNested / tStaged}, {"stencils", stencils}, {"threads", omp_get_max_threads()},
                   {"load_average_start", loadStart}, {"load_average_end", loadEnd}});
    writeFileAtomically(o.json, out.dump(2) + "\n");
    std::printf("wrote %s\n", o.json.c_str());
  }
  return kOk;
}

/// `--term stage-jets`: the shell's Jet-differentiated stages at Ceres' dual width and the framework's, 1 thread.
int runStageJetBench(const BenchOptions& o) {
  const std::vector<StageJetWidthRow> rows = benchStageJetWidth(o.n, std::max(o.repeats, 5));
  std::printf("jetshell bench elements --term stage-jets: each stage's derivatives from Jets over a %dx%d grid's "
              "faces (edges: Kelvin), 1 thread, median of %d interleaved repeats\n"
              "%-18s %5s %14s %14s %12s %11s\n", o.n, o.n, std::max(o.repeats, 5), "stage", "order", "N duals ns",
              "kJetWidth ns", "N / width", "difference");
  nlohmann::json out = nlohmann::json::array();
  for (const StageJetWidthRow& r : rows) {
    std::printf("%-18s %5d %14.1f %14.1f %12.2f %11.1e\n", r.stage.c_str(), r.order, r.nsPlain, r.nsFramework,
                r.nsPlain / r.nsFramework, r.largestDifference);
    out.push_back({{"stage", r.stage}, {"order", r.order}, {"ns_plain_width", r.nsPlain},
                   {"ns_framework_width", r.nsFramework}, {"plain_over_framework", r.nsPlain / r.nsFramework},
                   {"largest_difference", r.largestDifference}});
  }
  if (!o.json.empty()) {
    writeFileAtomically(o.json, out.dump(2) + "\n");
    std::printf("wrote %s\n", o.json.c_str());
  }
  return kOk;
}

int runBench(const BenchOptions& o) {
  if ((o.garment > 0 || o.shuffleFaces) && (o.term == "stage-jets" || o.term == "hinge" || o.term == "midedge")) {
    std::fprintf(stderr, "%s: not with --term %s, which runs on the grid only\n",
                 o.garment > 0 ? "--garment" : "--shuffle-faces", o.term.c_str());
    return kUsage;
  }
  if (o.term == "stage-jets") {
    if (o.projection != "none" || o.straightLine || o.staged || !o.path.empty() || o.threads > 1) {
      std::fprintf(stderr, "--term stage-jets: takes --n, --repeats and --json only\n");
      return kUsage;
    }
    return runStageJetBench(o);
  }
  if (o.term == "hinge" || o.term == "midedge") {
    if (o.projection != "none") {
      std::fprintf(stderr, "--projection: not with --term %s, whose figures compare exact Hessians\n", o.term.c_str());
      return kUsage;
    }
    return runNestedBench(o);
  }
  if (o.straightLine && o.projection != "none") {
    std::fprintf(stderr, "--straight-line: not with --projection %s (the reference element projects nothing)\n",
                 o.projection.c_str());
    return kUsage;
  }
  // The grid, or a garment's mesh: the T-shirt example's (front panel, then back, joined along seams), whose
  // numbering and seams the grid does not have.
  TriMesh mesh = o.garment > 0 ? makeTShirt(o.garment).mesh : makeRectangleGrid(1.0, 1.0, o.n, o.n);
  if (o.shuffleFaces) {
    std::vector<int> order(static_cast<std::size_t>(mesh.numFaces()));
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), std::mt19937(97));
    Faces shuffled(mesh.numFaces(), 3);
    for (int f = 0; f < mesh.numFaces(); ++f) shuffled.row(f) = mesh.F.row(order[static_cast<std::size_t>(f)]);
    mesh.F = shuffled;
  }
  const Topology topo = buildTopology(mesh);
  const ShellReference ref = computeReference(mesh, topo);
  const ShellMaterialParams mat = ShellMaterialParamsFrom3dIsotropic(1e5, 0.25, 1000.0, 0.002);
  const Eigen::VectorXd x = wavyPositions(mesh, true);
  auto membrane = makeMembraneTerm(mesh, ref, mat.membraneLambda, mat.membraneMu);
  auto bending = makeBendingTerm(mesh, topo, ref, mat.bendingAlpha, mat.bendingBeta);
  std::shared_ptr<MembraneTerm> membraneStaged;
  if (o.staged) {
    membraneStaged = std::make_shared<MembraneTerm>(mesh, ref, mat.membraneLambda, mat.membraneMu);
    membraneStaged->setStaged(true);
  }
  std::unique_ptr<StraightLineShell> straight;
  if (o.straightLine)
    straight = std::make_unique<StraightLineShell>(mesh, topo, ref, mat.membraneLambda, mat.membraneMu, mat.bendingAlpha,
                                                   mat.bendingBeta, bending->stencils());
  HessianAssembler assembler;
  const int slotM = assembler.addStencils(membrane->stencils());
  const int slotB = assembler.addStencils(bending->stencils());
  assembler.finalize(mesh.numVertices());
  const double faces = mesh.numFaces();
  const double loadStart = loadAverage();
  std::printf("jetshell bench elements: %d faces, %d vertices, Hessian nnz (upper) %ld, pattern+scatter %.1f MB; "
              "load average at start %.2f\n",
              mesh.numFaces(), mesh.numVertices(), static_cast<long>(assembler.matrix().nonZeros()),
              static_cast<double>(assembler.memoryBytes()) / 1e6, loadStart);
  const StageWindowPlan& plan = std::static_pointer_cast<BendingTerm>(bending)->windowPlan();
  if (!plan.empty()) {
    // The bending graph's window plan: elements deferred to after the lanes and nodes forwarded before them.
    std::size_t cross = 0;
    for (const std::vector<int>& nodes : plan.cross) cross += nodes.size();
    std::printf("bending graph's window plan: %zu lanes (%zu and %zu a phase), %zu of %d elements deferred, %zu "
                "cross nodes (forwarded before the lanes, gathered after them)\n",
                plan.lanes.size(), plan.phaseLanes[0].size(), plan.phaseLanes[1].size(), plan.deferred.size(),
                mesh.numFaces(), cross);
  }
  // A projected run measures what a Newton step with projection pays; the targets are for the exact
  // Hessian unprojected, so its summary then names no target.
  const PsdProjection projection = psdProjectionFromString(o.projection);
  const bool projected = projection != PsdProjection::None;
  // A target named in the summary, or nothing for a projected run.
  const auto target = [projected](const char* text) { return projected ? "" : text; };
  if (projected) std::printf("every element Hessian projected (%s); the figures are not the issue's targets\n", toString(projection));

  Eigen::VectorXd g(x.size());
  std::vector<Row> rows;
  const int maxThreads = omp_get_max_threads();
  std::vector<int> threadCounts = {1};
  if (maxThreads > 1) threadCounts.push_back(maxThreads);
  if (o.threads > 0) threadCounts = {o.threads};

  bool wallClock = false;  // set by pairedSpeedup: both thread counts on the wall clock
  // terms empty: the straight-line reference.
  auto measure = [&](const std::vector<std::pair<EnergyTerm*, int>>& terms, const EvalOptions& opt, bool wantG,
                     bool wantH) {
    // One thread: CPU time of this thread (robust on a shared machine). More threads: wall time.
    const bool cpuClock = !wallClock && omp_get_max_threads() == 1;
    auto now = [cpuClock] {
      timespec t{};
      clock_gettime(cpuClock ? CLOCK_THREAD_CPUTIME_ID : CLOCK_MONOTONIC, &t);
      return static_cast<double>(t.tv_sec) * 1e9 + static_cast<double>(t.tv_nsec);
    };
    const double t0 = now();
    if (wantH) assembler.setZero();
    if (wantG) g.setZero();
    for (auto& [term, slot] : terms) {
      EvalRequest req{wantG ? &g : nullptr, wantH ? &assembler : nullptr, slot};
      term->evaluate(x, req, opt);
    }
    if (terms.empty()) straight->evaluate(x, opt.path, wantG ? &g : nullptr, wantH ? &assembler : nullptr, slotB);
    return (now() - t0) / faces;
  };
  auto measureMedian = [&](const std::vector<std::pair<EnergyTerm*, int>>& terms, const EvalOptions& opt, bool wantG,
                           bool wantH) {
    std::vector<double> times;
    measure(terms, opt, wantG, wantH);  // warm-up
    for (int r = 0; r < o.repeats; ++r) times.push_back(measure(terms, opt, wantG, wantH));
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
  };
  // Two variants of one evaluation compared on a shared host, whose speed drifts between the figures of the table
  // (measured one after the other): each pair is timed back to back in the order a, b, b, a (drift within a pair
  // cancels), and the median of the pairs' ratios a / b is reported with their range.
  struct PairedRatio {
    double median = std::nan(""), low = std::nan(""), high = std::nan("");
    int pairs = 0;
  };
  auto interleaved = [&](auto&& a, auto&& b) {
    a();  // warm-up
    b();
    std::vector<double> ratios;
    for (int r = 0; r < std::max(o.repeats, 5); ++r) {
      const double a1 = a(), b1 = b();
      const double b2 = b(), a2 = a();
      ratios.push_back((a1 + a2) / (b1 + b2));
    }
    std::sort(ratios.begin(), ratios.end());
    return PairedRatio{ratios[ratios.size() / 2], ratios.front(), ratios.back(), static_cast<int>(ratios.size())};
  };
  // The AD / analytic ratio of value + gradient + exact Hessian, 1 thread (CPU time of the thread).
  auto pairedRatio = [&](const std::vector<std::pair<EnergyTerm*, int>>& terms) {
    omp_set_num_threads(1);
    EvalOptions ad, an;
    ad.path = DerivativePath::AutoDiff;
    an.path = DerivativePath::Analytic;
    ad.projection = an.projection = projection;
    const PairedRatio p = interleaved([&] { return measure(terms, ad, true, true); },
                                      [&] { return measure(terms, an, true, true); });
    omp_set_num_threads(maxThreads);
    return p;
  };
  // The speed-up of all threads over one, both on the wall clock: the table's speed-up divides a one-thread CPU
  // time by a wall time measured seconds later, so the host's drift and the time it takes from the process (counted
  // by the wall clock only) enter the ratio.
  auto pairedSpeedup = [&](const std::vector<std::pair<EnergyTerm*, int>>& terms, const EvalOptions& opt) {
    wallClock = true;
    auto at = [&](int threads) {
      omp_set_num_threads(threads);
      return measure(terms, opt, true, true);
    };
    const PairedRatio p = interleaved([&] { return at(1); }, [&] { return at(maxThreads); });
    wallClock = false;
    omp_set_num_threads(maxThreads);
    return p;
  };

  struct Case {
    const char* term;
    std::vector<std::pair<EnergyTerm*, int>> terms;
  };
  std::vector<Case> cases = {{"membrane", {{membrane.get(), slotM}}},
                             {"bending", {{bending.get(), slotB}}},
                             {"shell", {{membrane.get(), slotM}, {bending.get(), slotB}}}};
  if (o.staged) {
    cases.push_back({"membrane_staged", {{membraneStaged.get(), slotM}}});
    cases.push_back({"shell_staged", {{membraneStaged.get(), slotM}, {bending.get(), slotB}}});
  }
  if (straight) cases.push_back({"shell_straight", {}});
  std::printf("\n%-15s %-9s %-13s %7s %12s %12s %12s\n", "term", "path", "bending H", "threads", "value ns",
              "+grad ns", "+Hessian ns");
  for (int threads : threadCounts) {
    omp_set_num_threads(threads);
    for (const Case& c : cases) {
      const bool isStraight = c.terms.empty();
      if (!o.term.empty() && o.term != c.term && o.term + "_staged" != c.term && !(isStraight && o.term == "shell"))
        continue;
      if (isStraight && threads != 1) continue;  // the reference runs on one thread
      for (DerivativePath path : {DerivativePath::Analytic, DerivativePath::AutoDiff}) {
        if (!o.path.empty() && o.path != (path == DerivativePath::AutoDiff ? "ad" : "analytic")) continue;
        for (HessianModel bh : {HessianModel::Exact, HessianModel::GaussNewton}) {
          if (bh == HessianModel::GaussNewton && (std::string(c.term).rfind("membrane", 0) == 0 || isStraight)) continue;
          EvalOptions opt;
          opt.path = path;
          opt.hessianModel = bh;
          opt.projection = projection;
          const char* pathName = path == DerivativePath::AutoDiff ? "ad" : "analytic";
          const char* hName = bh == HessianModel::Exact ? "exact" : "gauss_newton";
          const double v = measureMedian(c.terms, opt, false, false);
          const double vg = measureMedian(c.terms, opt, true, false);
          const double vgh = measureMedian(c.terms, opt, true, true);
          std::printf("%-15s %-9s %-13s %7d %12.1f %12.1f %12.1f\n", c.term, pathName, hName, threads, v, vg, vgh);
          rows.push_back({c.term, pathName, hName, "value", threads, v});
          rows.push_back({c.term, pathName, hName, "gradient", threads, vg});
          rows.push_back({c.term, pathName, hName, "hessian", threads, vgh});
        }
      }
    }
  }
  omp_set_num_threads(maxThreads);

  auto find = [&](const std::string& term, const std::string& path, const std::string& h, int threads) {
    for (const Row& r : rows)
      if (r.term == term && r.path == path && r.hessian == h && r.threads == threads && r.what == "hessian")
        return r.nsPerFace;
    return std::nan("");
  };
  const double an1 = find("shell", "analytic", "exact", 1), ad1 = find("shell", "ad", "exact", 1);
  std::printf("\nSummary (value + gradient + Hessian, membrane + bending, exact Hessian%s%s):\n",
              projected ? ", projected: " : "", projected ? toString(projection) : "");
  // Lines whose rows this run did not measure (another --threads, --path or --term) are left out, not printed
  // as nan.
  if (std::isfinite(an1))
    std::printf("  analytic, 1 thread: %.0f ns/face%s\n", an1, target(" (target <= 1000)"));
  const double stagedAn1 = find("shell_staged", "analytic", "exact", 1);
  if (std::isfinite(stagedAn1))
    std::printf("  membrane's stage graph, analytic, 1 thread: %.0f ns/face\n", stagedAn1);
  if (std::isfinite(an1) && std::isfinite(ad1))
    std::printf("  AD / analytic, 1 thread, ratio of the table's medians: %.2f\n", ad1 / an1);
  for (int t : threadCounts) {
    const double anT = find("shell", "analytic", "exact", t);
    if (t > 1 && std::isfinite(anT)) std::printf("  analytic, %d threads: %.0f ns/face\n", t, anT);
  }
  PairedRatio shellRatio, stagedRatio;
  const bool bothPaths = o.path.empty() && (o.threads <= 1);
  auto printPaired = [&target](const char* what, const PairedRatio& p) {
    std::printf("  %s, 1 thread: %.2f (median of %d interleaved pairs, range %.2f-%.2f%s)\n", what, p.median, p.pairs,
                p.low, p.high, target("; target <= 1.2"));
  };
  auto termsOf = [&](const std::string& name) {
    for (const Case& c : cases)
      if (name == c.term) return c.terms;
    return std::vector<std::pair<EnergyTerm*, int>>{};
  };
  if (bothPaths && (o.term.empty() || o.term == "shell")) {
    shellRatio = pairedRatio(termsOf("shell"));
    printPaired("AD / analytic", shellRatio);
  }
  // The speed-up of each measured shell row (another --path or --term leaves some out: none printed as nan).
  if (threadCounts.size() > 1)
    for (const char* term : {"shell", "shell_staged"})
      for (const char* path : {"analytic", "ad"}) {
        const double one = find(term, path, "exact", 1), many = find(term, path, "exact", maxThreads);
        if (std::isfinite(one) && std::isfinite(many) && many > 0.0)
          std::printf("  speed-up %d threads vs 1 (%s, %s), the table's figures: %.2fx\n", maxThreads, term, path,
                      one / many);
      }
  struct Speedup {
    std::string term, path;
    PairedRatio ratio;
  };
  std::vector<Speedup> speedups;
  if (threadCounts.size() > 1)
    for (const char* term : {"shell", "shell_staged"})
      for (DerivativePath path : {DerivativePath::Analytic, DerivativePath::AutoDiff}) {
        const char* pathName = path == DerivativePath::AutoDiff ? "ad" : "analytic";
        if (!std::isfinite(find(term, pathName, "exact", 1))) continue;  // a row this run did not measure
        EvalOptions opt;
        opt.path = path;
        opt.projection = projection;
        const PairedRatio p = pairedSpeedup(termsOf(term), opt);
        speedups.push_back({term, pathName, p});
        std::printf("  speed-up %d threads vs 1 (%s, %s), wall clock, interleaved: %.2fx (median of %d pairs, range "
                    "%.2f-%.2f%s)\n", maxThreads, term, pathName, p.median, p.pairs, p.low, p.high,
                    target("; target >= 1.8"));
      }
  // Only when --term ran the bending term on its own (a ratio of absent rows would print nan).
  const double gnBending = find("bending", "analytic", "gauss_newton", 1), exactBending = find("bending", "analytic", "exact", 1);
  if (std::isfinite(gnBending) && std::isfinite(exactBending))
    std::printf("  Gauss-Newton bending / exact bending, analytic, 1 thread: %.2f\n", gnBending / exactBending);
  for (const char* path : {"analytic", "ad"}) {
    const double perFace = find("shell", path, "exact", 1), staged = find("shell_staged", path, "exact", 1);
    if (std::isfinite(perFace) && std::isfinite(staged))
      std::printf("  membrane's stage graph / per face, %s, 1 thread: %.2f (%.0f vs %.0f ns/face)\n", path,
                  staged / perFace, staged, perFace);
  }
  // The framework against the same stages chained by hand for this graph, interleaved (CPU time of the thread).
  std::vector<std::pair<std::string, PairedRatio>> straightRatios;
  for (const char* path : {"analytic", "ad"}) {
    const double staged = find("shell_staged", path, "exact", 1), reference = find("shell_straight", path, "exact", 1);
    if (!std::isfinite(staged) || !std::isfinite(reference)) continue;
    omp_set_num_threads(1);
    EvalOptions opt;
    opt.path = std::string(path) == "ad" ? DerivativePath::AutoDiff : DerivativePath::Analytic;
    const PairedRatio p = interleaved([&] { return measure(termsOf("shell_staged"), opt, true, true); },
                                      [&] { return measure({}, opt, true, true); });
    omp_set_num_threads(maxThreads);
    straightRatios.emplace_back(path, p);
    std::printf("  stage framework / straight-line element, %s, 1 thread: %.2f (median of %d interleaved pairs, range "
                "%.2f-%.2f; the table: %.0f vs %.0f ns/face)\n", path, p.median, p.pairs, p.low, p.high, staged,
                reference);
  }
  const double stagedAd = find("shell_staged", "ad", "exact", 1), stagedAn = find("shell_staged", "analytic", "exact", 1);
  if (std::isfinite(stagedAd) && std::isfinite(stagedAn)) {
    std::printf("  membrane's stage graph, AD / analytic twins, 1 thread, ratio of the table's medians: %.2f\n",
                stagedAd / stagedAn);
    if (bothPaths) {
      stagedRatio = pairedRatio(termsOf("shell_staged"));
      printPaired("membrane's stage graph, AD / analytic twins", stagedRatio);
    }
  }
  std::printf("  peak resident memory: %.0f MB (target <= 300%s)\n", peakRssMb(),
              o.staged ? "; this run also holds the staged membrane and its caches" : "");
  const double loadEnd = loadAverage();
  std::printf("load average at end: %.2f\n", loadEnd);

  if (!o.json.empty()) {
    nlohmann::json out = nlohmann::json::array();
    for (const Row& r : rows) {
      if (r.what != "hessian") continue;
      if (r.term.rfind("membrane", 0) != 0 && r.hessian != "exact") continue;
      out.push_back({{"term", r.term}, {"path", r.path}, {"threads", r.threads}, {"ns_per_face", r.nsPerFace},
                     {"measures", "value+gradient+hessian"}, {"bending_hessian", r.hessian},
                     {"projection", toString(projection)}});
    }
    for (const Row& r : rows) {
      if (r.what == "hessian" && r.term.rfind("membrane", 0) != 0 && r.hessian == "exact") continue;
      out.push_back({{"term", r.term}, {"path", r.path}, {"threads", r.threads}, {"ns_per_face", r.nsPerFace},
                     {"measures", r.what == "value" ? "value" : r.what == "gradient" ? "value+gradient"
                                                                                   : "value+gradient+hessian"},
                     {"bending_hessian", r.hessian}, {"projection", toString(projection)}, {"variant", true}});
    }
    out.push_back({{"peak_rss_mb", peakRssMb()}, {"faces", mesh.numFaces()},
                   {"mesh", (o.garment > 0 ? "tshirt, resolution " + std::to_string(o.garment) : std::string("grid")) +
                                (o.shuffleFaces ? ", faces shuffled" : "")},
                   {"projection", toString(projection)},
                   {"load_average_start", loadStart}, {"load_average_end", loadEnd}});
    for (const auto& [name, p] : {std::pair<const char*, PairedRatio>{"shell", shellRatio}, {"shell_staged", stagedRatio}})
      if (p.pairs > 0)
        out.push_back({{"term", name}, {"ad_over_analytic_interleaved", p.median}, {"low", p.low}, {"high", p.high},
                       {"pairs", p.pairs}, {"threads", 1}});
    for (const auto& [path, p] : straightRatios)
      out.push_back({{"term", "shell_staged"}, {"path", path}, {"over_straight_line_interleaved", p.median},
                     {"low", p.low}, {"high", p.high}, {"pairs", p.pairs}, {"threads", 1}});
    for (const Speedup& sp : speedups)
      out.push_back({{"term", sp.term}, {"path", sp.path}, {"speedup_interleaved", sp.ratio.median},
                     {"low", sp.ratio.low}, {"high", sp.ratio.high}, {"pairs", sp.ratio.pairs},
                     {"threads", maxThreads}, {"clock", "wall"}});
    writeFileAtomically(o.json, out.dump(2) + "\n");
    std::printf("wrote %s\n", o.json.c_str());
  }
  return kOk;
}

const RegisterSubcommand registerBenchElements("bench elements", [](CLI::App& app, int& exitCode) {
  CLI::App* bench = benchCommand(app);
  auto opts = std::make_shared<BenchOptions>();
  CLI::App* el = bench->add_subcommand("elements", "Per-face cost of the membrane and bending energies");
  el->add_option("--n", opts->n, "Grid squares per side (faces = 2 n^2)")->check(CLI::Range(2, 2000));
  el->add_option("--garment", opts->garment,
                 "The T-shirt example's mesh at this resolution (4: the example's 11,008 faces) instead of the grid, "
                 "with the same waves as a displacement (not with --term hinge, midedge or stage-jets)")
      ->check(CLI::Range(1, 40));
  el->add_flag("--shuffle-faces", opts->shuffleFaces,
              "The mesh's faces in a fixed random order: a mesh numbered without regard to its connectivity");
  el->add_option("--repeats", opts->repeats,
                 "Timed repeats per figure (the median is reported); interleaved AD/analytic pairs for the ratio (at least 5)")
      ->check(CLI::Range(1, 100));
  el->add_option("--json", opts->json, "Write the figures as a JSON list")->check(outputFile());
  el->add_option("--term", opts->term, "Only this term and its membrane_staged/shell_staged twin (hinge, midedge: a staged term against the same energy as one nested-Jet "
                 "element; stage-jets: the shell's Jet-differentiated stages at two dual widths)")->check(CLI::IsMember({"membrane", "bending", "shell", "hinge", "midedge", "stage-jets"}));
  el->add_option("--path", opts->path, "Only this derivative path")->check(CLI::IsMember({"ad", "analytic"}));
  el->add_flag("--staged", opts->staged,
               "Also the membrane on its stage graph (rows membrane_staged, shell_staged), with their ratio to the default");
  el->add_flag("--straight-line", opts->straightLine,
               "Also the shell as one straight-line element per face on the same stages (row shell_straight, 1 "
               "thread, exact Hessian): the reference the stage framework is measured against");
  el->add_option("--threads", opts->threads, "Only this thread count (default: 1 and all)")->check(CLI::Range(1, 256));
  el->add_option("--projection", opts->projection,
                 "Project every element Hessian as a Newton step with projection does (clamp, abs); default none, the "
                 "exact Hessian the issue's targets are for")
      ->check(CLI::IsMember({"none", "clamp", "abs"}));
  el->callback([opts, &exitCode] { exitCode = runBench(*opts); });
});

}  // namespace
}  // namespace jetshell::cli
