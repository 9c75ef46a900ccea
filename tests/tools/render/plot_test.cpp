// Plots are drawn in-process: user text (scene descriptions, probe names, output paths) is drawn as glyphs and
// reaches no other program. The injection cases below would run a command if any shell or plotting language saw
// them (backquotes are command substitution in both, a newline starts a new command).
#include "tools/render/image.h"
#include "tools/render/plot.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
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

/// Texts a hostile scene could hold; each would create `canary` if a shell or a plotting language ran any part of it.
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

namespace {

/// Pixels of a 400-pixel-wide picture left of x = 240 (so not the key, which sits in the right 35%) within 40
/// per channel (0..255) of the colour r, g, b.
int countColour(const std::vector<std::uint8_t>& rgb, int r, int g, int b) {
  int n = 0;
  for (std::size_t k = 0; k + 2 < rgb.size(); k += 3)
    if ((k / 3) % 400 < 240 && std::abs(rgb[k] - r) <= 40 && std::abs(rgb[k + 1] - g) <= 40 && std::abs(rgb[k + 2] - b) <= 40)
      ++n;
  return n;
}

/// Dark pixels (text, frame, ticks) in rows [top, bottom) of a width-wide picture.
int darkPixels(const std::vector<std::uint8_t>& rgb, int width, int top, int bottom) {
  int n = 0;
  for (int y = top; y < bottom; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t k = (static_cast<std::size_t>(y) * width + x) * 3;
      if (rgb[k] + rgb[k + 1] + rgb[k + 2] < 300) ++n;
    }
  return n;
}

PlotSpec redDiagonal() {
  PlotSpec spec;
  spec.width = 400;
  spec.height = 300;
  spec.series.push_back({"diagonal", {0, 1, 2, 3}, {0, 1, 2, 3}, "lines", "#ff0000"});
  return spec;
}

}  // namespace

TEST_CASE("plot: text is drawn as valid UTF-8 without control characters, and cut") {
  CHECK(drawableText("line one\nsystem `id`\t'q'") == "line one system `id` 'q'");
  CHECK(drawableText("λ = 1 \u2019ok\u2019 \U0001F600") == "λ = 1 \u2019ok\u2019 \U0001F600");
  const std::string replacement = "\xEF\xBF\xBD";
  CHECK(drawableText("a\xff" "b") == "a" + replacement + "b");                  // not a UTF-8 lead byte
  CHECK(drawableText("\xC0\xAF") == replacement + replacement);                // overlong '/'
  CHECK(drawableText("\xED\xA0\x80") == replacement + replacement + replacement);  // a UTF-16 surrogate
  CHECK(drawableText("\xE2\x82") == replacement + replacement);                // cut short
  CHECK(drawableText("\xC2\x85x") == " x");                                    // C1 control (NEL)
  CHECK(drawableText(std::string(1000, 'a')).size() == kMaxPlotText);
  CHECK(drawableText(std::string(300, '\xff')).size() == 3 * kMaxPlotText);
}

TEST_CASE("plot: bad series, sizes and counts are refused with the place named") {
  const std::string where = (freshPlotDirectory("refused") / "p.png").string();
  PlotSpec spec = redDiagonal();
  spec.series[0].color = "red' . system('id') . '";
  CHECK_THROWS_WITH(plotPng(spec, where), Catch::StartsWith(where) && Catch::Contains("series 'diagonal' has colour") &&
                                              Catch::Contains("expected #rrggbb"));
  spec = redDiagonal();
  spec.series[0].style = "impulses";
  CHECK_THROWS_WITH(plotPng(spec, where), Catch::Contains("style 'impulses'"));
  spec = redDiagonal();
  spec.series.push_back({"bad", {0, 1}, {0}, "lines"});
  CHECK_THROWS_WITH(plotPng(spec, where), Catch::EndsWith("series 'bad' has 2 x values and 1 y values"));
  spec = redDiagonal();
  spec.width = kMaxPlotSize + 1;
  CHECK_THROWS_WITH(plotPng(spec, where), Catch::Contains("plot size"));
  spec = redDiagonal();
  spec.series.assign(kMaxPlotSeries + 1, spec.series[0]);
  CHECK_THROWS_WITH(plotPng(spec, where), Catch::Contains("series (at most"));
  spec.series.clear();
  CHECK_THROWS_WITH(plotPng(spec, where), Catch::Contains("nothing to plot"));
  CHECK_FALSE(fs::exists(where));
}

TEST_CASE("plot: curves become a PNG of the asked size, in their colour, along their path") {
  const PlotSpec spec = redDiagonal();
  const std::vector<std::uint8_t> rgb = drawPlot(spec, "test");
  REQUIRE(rgb.size() == 400u * 300u * 3u);
  // The red line runs from the frame's bottom-left towards its top-right: its pixels rise to the right.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 240; ++x) {
      const std::size_t k = (static_cast<std::size_t>(y) * 400 + x) * 3;
      if (rgb[k] > 200 && rgb[k + 1] < 80 && rgb[k + 2] < 80) sx += x, sy += y, sxx += double(x) * x, sxy += double(x) * y, ++n;
    }
  REQUIRE(n > 150);
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  CHECK(slope < -0.3);  // image rows grow downwards

  // Non-finite values, and values ≤ 0 on a log axis, break the curve instead of failing.
  PlotSpec broken = redDiagonal();
  broken.logY = true;
  broken.series[0].y = {0.0, std::nan(""), -1.0, 3.0};
  CHECK(countColour(drawPlot(broken, "test"), 255, 0, 0) == 0);  // no two neighbours are drawable
  broken.series[0].y = {1e-3, 1e-2, std::numeric_limits<double>::infinity(), 10.0};
  CHECK(countColour(drawPlot(broken, "test"), 255, 0, 0) > 50);

  // Series without a colour take the default sequence; a title is drawn as text above the frame.
  PlotSpec titled = redDiagonal();
  titled.series[0].color.clear();
  CHECK(countColour(drawPlot(titled, "test"), 0x94, 0x00, 0xd3) > 150);
  titled.title = "       ";  // the same layout as a title, and nothing to draw
  const int blank = darkPixels(drawPlot(titled, "test"), 400, 0, 25);
  titled.title = "A title";
  CHECK(darkPixels(drawPlot(titled, "test"), 400, 0, 25) > blank + 20);

  const fs::path png = freshPlotDirectory("png") / "plot.png";
  plotPng(spec, png.string());
  int w = 0, h = 0;
  const std::vector<std::uint8_t> read = readPngRgb(png.string(), w, h);
  CHECK(w == 400);
  CHECK(h == 300);
  CHECK(read == rgb);
}

TEST_CASE("plot: degenerate data still gives a picture") {
  PlotSpec spec = redDiagonal();
  spec.series[0].x = {1, 1};
  spec.series[0].y = {5, 5};
  CHECK(drawPlot(spec, "test").size() == 400u * 300u * 3u);
  spec.series[0].x = {-1e308, 1e308};
  spec.series[0].y = {0, 1e-300};
  CHECK(drawPlot(spec, "test").size() == 400u * 300u * 3u);
  spec.series[0].x = {};
  spec.series[0].y = {};
  spec.logX = spec.logY = true;
  CHECK(drawPlot(spec, "test").size() == 400u * 300u * 3u);
  spec = redDiagonal();
  spec.width = spec.height = kMinPlotSize;
  spec.title = spec.xLabel = spec.yLabel = std::string(500, 'w');
  CHECK(drawPlot(spec, "test").size() == 16u * 16u * 3u);
}

TEST_CASE("plot: injected titles, labels, series names and paths run nothing") {
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
