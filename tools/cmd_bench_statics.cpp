// `jetshell bench statics`: the static example scenes through the one statics path (solvers/statics.h), as
// `jetshell run` takes them, each under the path controls asked for (by default load control and arc length;
// `scene` keeps the scene's own; a scene that follows its path past limit points is not run under load control,
// which stops at the first). Per scene and control: vertices, the solves of the path (load steps or path
// points), Newton iterations, iterations per solve (summary.json's `newton_iterations_per_load_step`, the figure
// of the static scenes' target: at most 6 on smooth paths), cuts, the median wall time over --repeats runs, and how
// the run ended; then the mean iterations per solve over the load-control rows and, per scene, arc length's wall
// time against load control's. Frames, probes and pictures are not written (only summary.json, into a scratch
// directory removed afterwards), so the times are the solver's.
// Wall time: run it on a quiet machine and quote the load printed beside the figures.
#include "tools/bench_cloth.h"
#include "tools/output/atomic_file.h"
#include "tools/output/directories.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tools/subcommand.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace jetshell::cli {
namespace {

struct StaticsBenchArgs {
  std::vector<std::string> scenes{"cantilever_strip",         "sze_cantilever_end_shear", "cantilever_end_moment",
                                  "pinched_hemisphere",       "slit_annular_ring_static", "sze_slit_annular_plate",
                                  "hinged_roof_snap_through"};
  std::vector<std::string> controls{"load", "arcLength"};
  int repeats = 3;
  std::string json;
};

/// The scene file of a name in examples/ (or a path as given, when it names a file).
std::string scenePath(const std::string& name) {
  if (std::filesystem::is_regular_file(name)) return name;
  return std::string(JETSHELL_SOURCE_DIR) + "/examples/" + name + ".json";
}

template <class T>
T extraValue(const RunSummary& s, const char* key, T fallback) {
  const auto it = s.extra.find(key);
  return it != s.extra.end() && !it->is_null() ? it->get<T>() : fallback;
}

/// One scene under one control, `repeats` times: the first run's counts (every run takes the same path) and the
/// median wall time.
nlohmann::json runCase(const Scene& base, const std::string& path, const std::string& control, int repeats,
                       const TemporaryDirectory& scratch) {
  Scene scene = base;
  if (control != "scene") {
    scene.analysis.pathControl = PathControlSettings{};
    scene.analysis.pathControl.type = control;
  }
  scene.outputs.vtu = scene.outputs.obj = scene.outputs.probesCsv = false;
  scene.outputs.png = scene.outputs.plots = false;
  RunOptions options;
  options.outputDirectory = scratch.path().string();
  options.scenePath = path;
  options.pictures = false;
  std::vector<double> walls;
  RunResult first;
  for (int r = 0; r < repeats; ++r) {
    RunResult result = runScene(scene, options);
    walls.push_back(result.summary.wallSeconds);
    if (r == 0) first = std::move(result);
  }
  std::sort(walls.begin(), walls.end());
  const RunSummary& s = first.summary;
  std::ifstream summaryFile(scratch.path() / "summary.json");
  const nlohmann::json written = nlohmann::json::parse(summaryFile, nullptr, false);
  const int vertices = written.is_object() ? written.value("vertices", 0) : 0;
  return {{"control", scene.analysis.pathControl.type},
          {"vertices", vertices},
          {"requested_levels", scene.analysis.loadSteps},
          {"solves", extraValue<int>(s, "load_steps_solved", 0)},
          {"newton_iterations", s.newtonIterations},
          {"iterations_per_solve", extraValue<double>(s, "newton_iterations_per_load_step", 0.0)},
          {"cuts", extraValue<int>(s, "load_step_cuts", 0)},
          {"limit_points", s.extra.contains("limit_points") ? s.extra["limit_points"].size() : 0},
          {"wall_seconds_median", walls[walls.size() / 2]},
          {"wall_seconds_all", walls},
          {"termination", s.termination},
          {"converged", s.converged}};
}

int run(const StaticsBenchArgs& a) {
  const TemporaryDirectory scratch("jetshell-bench-statics-");  // this process's runs, removed at the end
  const double loadStart = loadAverage();
  std::printf("jetshell bench statics: %zu scenes x %zu controls, median of %d runs; load average at start %.2f\n",
              a.scenes.size(), a.controls.size(), a.repeats, loadStart);
  std::printf("%-28s %-11s %8s %7s %7s %7s %8s %5s %9s  %s\n", "scene", "control", "vertices", "levels", "solves",
              "Newton", "it/solve", "cuts", "wall s", "ended");
  nlohmann::json rows = nlohmann::json::array();
  int code = kOk;
  double perSolveSum = 0.0;
  int perSolveCount = 0;
  std::map<std::string, std::map<std::string, double>> wall;  // scene → control → median wall
  for (const std::string& name : a.scenes) {
    const std::string path = scenePath(name);
    const Scene scene = loadSceneFile(path);
    if (scene.analysis.type != AnalysisType::Static)
      throw InputError("bench statics: " + path + ": /analysis/type is not \"static\"");
    for (const std::string& control : a.controls) {
      if (control == "load" && scene.analysis.pathControl.type != "load") {
        std::printf("%-28s %-11s (skipped: the scene follows its path by %s past limit points)\n", name.c_str(),
                    "load", scene.analysis.pathControl.type.c_str());
        continue;
      }
      nlohmann::json row = runCase(scene, path, control, a.repeats, scratch);
      row["scene"] = name;
      const bool completed = row["termination"] == "completed";
      if (!completed) code = kFailed;
      std::printf("%-28s %-11s %8d %7d %7d %7d %8.2f %5d %9.3f  %s\n", name.c_str(),
                  row["control"].get<std::string>().c_str(), row["vertices"].get<int>(),
                  row["requested_levels"].get<int>(), row["solves"].get<int>(), row["newton_iterations"].get<int>(),
                  row["iterations_per_solve"].get<double>(), row["cuts"].get<int>(),
                  row["wall_seconds_median"].get<double>(), row["termination"].get<std::string>().c_str());
      if (row["control"] == "load" && completed) {
        perSolveSum += row["iterations_per_solve"].get<double>();
        ++perSolveCount;
      }
      wall[name][row["control"].get<std::string>()] = row["wall_seconds_median"].get<double>();
      rows.push_back(std::move(row));
    }
  }
  nlohmann::json j = {{"rows", rows}, {"repeats", a.repeats}, {"load_average_start", loadStart}};
  if (perSolveCount > 0) {
    const double mean = perSolveSum / perSolveCount;
    std::printf("load control: mean Newton iterations per solve over %d scenes %.2f (target <= 6 on smooth paths)\n",
                perSolveCount, mean);
    j["load_control_mean_iterations_per_solve"] = mean;
  }
  nlohmann::json ratios = nlohmann::json::object();
  for (const auto& [name, byControl] : wall) {
    const auto load = byControl.find("load"), arc = byControl.find("arcLength");
    if (load == byControl.end() || arc == byControl.end() || !(load->second > 0.0)) continue;
    std::printf("%s: arc length / load control wall time %.2f\n", name.c_str(), arc->second / load->second);
    ratios[name] = arc->second / load->second;
  }
  j["arc_length_over_load_wall"] = ratios;
  const double loadEnd = loadAverage();
  std::printf("load average at end: %.2f\n", loadEnd);
  j["load_average_end"] = loadEnd;
  if (!a.json.empty()) writeFileAtomically(a.json, j.dump(2) + "\n");
  return code;
}

const RegisterSubcommand registerBenchStatics("bench-statics", [](CLI::App& app, int& exitCode) {
  auto a = std::make_shared<StaticsBenchArgs>();
  CLI::App* cmd = benchCommand(app)->add_subcommand(
      "statics", "Static scenes under load control and arc length: Newton iterations per solve, cuts, wall time");
  cmd->add_option("--scenes", a->scenes, "Static scenes: names in examples/ or scene files")
      ->delimiter(',')
      ->check([](const std::string& s) { return s.empty() || s.size() > 4096 ? "empty or too long" : ""; });
  cmd->add_option("--controls", a->controls, "Path controls: load, arcLength, or scene (the scene's own)")
      ->delimiter(',')
      ->check(CLI::IsMember({"load", "arcLength", "scene"}));
  cmd->add_option("--repeats", a->repeats, "Runs per scene and control (the median wall time is reported)")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--json", a->json, "Write the figures as JSON")->check(outputFile());
  cmd->callback([a, &exitCode] { exitCode = run(*a); });
});

}  // namespace
}  // namespace jetshell::cli
