// Plots must never let user text (scene descriptions, probe names, output paths) reach gnuplot's command
// language: backquotes are command substitution and a newline starts a new command there.
#include "tools/render/image.h"
#include "tools/render/plot.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

fs::path freshPlotDirectory(const std::string& name) {
  const fs::path dir = test::scratchDirectory("plot_tests") / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Texts a hostile scene could hold; each would create `canary` if gnuplot (or a shell) ran any part of it.
std::vector<std::string> injections(const fs::path& canary) {
  const std::string c = canary.string();
  return {
      "`touch " + c + "`",
      "title\nsystem \"touch " + c + "\"\nset title 'x",
      "\" . system(\"touch " + c + "\") . \"",
      "' . system('touch " + c + "') . '",
      "'\nsystem 'touch " + c + "'\n'",
      "a\\\"`touch " + c + "`\\\"",
      "@ARG0 `touch " + c + "` $(touch " + c + ")",
      "\r\nshell\r\n",
  };
}

}  // namespace

TEST_CASE("plot: user text becomes one single-quoted gnuplot literal") {
  PlotSpec spec;
  spec.title = "line one\nsystem \"rm -rf x\" `id` 'quoted'";
  spec.xLabel = "x";
  spec.yLabel = "y";
  spec.series.push_back({"probe\n`id`", {0, 1}, {0, 1}, "lines"});
  const std::string script = gnuplotScript(spec, {"d.dat"}, "o.png");
  // Six fixed lines and the plot command; no user newline survives, no backquote at all.
  CHECK(std::count(script.begin(), script.end(), '\n') == 8);
  CHECK(script.find('`') == std::string::npos);
  CHECK(script.find("set title 'line one system \"rm -rf x\" id \u2019quoted\u2019'\n") != std::string::npos);
  CHECK(script.find("title 'probe id'") != std::string::npos);
}

TEST_CASE("plot: colours other than #rrggbb are refused, not passed on") {
  PlotSpec spec;
  spec.series.push_back({"a", {0, 1}, {0, 1}, "lines", "red' . system('id') . '"});
  CHECK_THROWS_WITH(plotPng(spec, (freshPlotDirectory("colour") / "p.png").string()),
                    Catch::Contains("colour") && Catch::Contains("expected #rrggbb"));
}

TEST_CASE("plot: gnuplot curves become a PNG") {
  PlotSpec spec;
  spec.title = "a \"quoted\" title";
  spec.xLabel = "x";
  spec.yLabel = "y";
  spec.series.push_back({"x^2", {0, 1, 2, 3}, {0, 1, 4, 9}, "linespoints"});
  spec.width = 320;
  spec.height = 240;
  spec.series.push_back({"bad", {0, 1}, {0}, "lines"});
  const fs::path dir = freshPlotDirectory("png");
  CHECK_THROWS_WITH(plotPng(spec, (dir / "bad.png").string()), Catch::EndsWith("series 'bad' has 2 x values and 1 y values"));
  spec.series.pop_back();
  if (!gnuplotAvailable()) return;
  const std::string png = (dir / "plot.png").string();
  plotPng(spec, png);
  int w = 0, h = 0;
  readPngRgb(png, w, h);
  CHECK(w == 320);
  CHECK(h == 240);
}

TEST_CASE("plot: injected titles, labels, series names and paths run nothing") {
  if (!gnuplotAvailable()) return;
  const fs::path dir = freshPlotDirectory("injection");
  const fs::path canary = dir / "canary";
  int drawn = 0;
  for (const std::string& text : injections(canary)) {
    INFO(text);
    PlotSpec spec;
    spec.title = spec.xLabel = spec.yLabel = text;
    spec.series.push_back({text, {0, 1, 2}, {0, 1, 4}, "linespoints"});
    spec.width = 200;
    spec.height = 150;
    // The output path carries the text too (a directory named by it), minus the slashes a name cannot hold.
    std::string name = text;
    std::replace(name.begin(), name.end(), '/', '_');
    const fs::path sub = dir / name;
    fs::create_directories(sub);
    plotPng(spec, (sub / "plot.png").string());
    CHECK(fs::exists(sub / "plot.png"));
    CHECK_FALSE(fs::exists(canary));
    ++drawn;
  }
  CHECK(drawn == 8);
}

TEST_CASE("plot: a hostile scene's description and probe names run nothing and keep probes.csv parseable") {
  if (!gnuplotAvailable()) return;
  const fs::path dir = freshPlotDirectory("scene");
  const fs::path canary = dir / "canary";
  const std::vector<std::string> texts = injections(canary);
  nlohmann::json probes = nlohmann::json::array();
  for (std::size_t k = 0; k < 3; ++k)
    probes.push_back({{"name", texts[k] + ",\"x\"" + std::to_string(k)}, {"select", {{"nearest", {1.0, 0.0, 0.0}}}}});
  const nlohmann::json document = {
      {"description", texts[1] + texts[3]},
      {"actors",
       {{{"type", "shell"},
         {"name", "sheet"},
         {"shape", {{"generator", "rectangle"}, {"width", 1.0}, {"height", 1.0}, {"nx", 2}, {"ny", 2}}},
         {"material", {{"youngsModulus", 1e6}, {"poissonRatio", 0.3}, {"thickness", 0.001}, {"volumeDensity", 300}}},
         {"colliderType", "None"},
         {"fixed", {{{"select", {{{"nearest", {0.0, 1.0, 0.0}}}, {{"nearest", {1.0, 1.0, 0.0}}}}}}}},
         {"probes", probes}}}},
      {"analysis", {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.03}}}};
  Scene scene = sceneFromJson(document, dir.string());
  RunOptions o;
  o.outputDirectory = (dir / "out").string();
  const RunResult r = runScene(scene, o);
  CHECK_FALSE(r.probesPng.empty());
  CHECK_FALSE(fs::exists(canary));
  // The probes.csv header is one line of RFC 4180 fields: names with commas, quotes or newlines are quoted.
  std::ifstream csv(fs::path(o.outputDirectory) / "probes.csv");
  std::stringstream all;
  all << csv.rdbuf();
  const std::string text = all.str();
  int fields = 1, rows = 0;
  bool quoted = false;
  for (char c : text) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    if (c == ',' && rows == 0) ++fields;
    if (c == '\n') ++rows;
  }
  CHECK_FALSE(quoted);
  CHECK(fields == 3 + 3 * 3);
  CHECK(rows >= 2);
}
