// An example scene run whole as `jetshell run` would, for the accuracy tests of tests/validation/ that read its
// probes.csv (scene_accuracy_test.cpp, euler_column_test.cpp).
#pragma once

#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tests/scratch_directory.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace jetshell::test {

/// probes.csv's rows after the header, as numbers.
inline std::vector<std::vector<double>> readCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header: step,time,load_factor,tip_ux,tip_uy,tip_uz
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(std::move(row));
  }
  return rows;
}

/// An example scene run whole as `jetshell run` would, without frames or pictures, and its probes.csv rows.
struct ExampleRun {
  RunResult result;
  std::vector<std::vector<double>> probes;
};

/// `edit` changes the scene before the run (its output directory is named after the stem and `variant`).
inline ExampleRun runExample(const std::string& stem, const std::function<void(Scene&)>& edit = {},
                             const std::string& variant = "") {
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/" + stem + ".json");
  scene.outputs.frameStride = 1;  // a probes.csv row per step
  scene.outputs.vtu = false;
  if (edit) edit(scene);
  const std::filesystem::path dir = scratchDirectory("scene_accuracy") / (stem + variant);
  std::filesystem::remove_all(dir);
  RunOptions o;
  o.outputDirectory = dir.string();
  o.pictures = false;
  ExampleRun run;
  run.result = runScene(scene, o);
  run.probes = readCsv(dir / "probes.csv");
  return run;
}

}  // namespace jetshell::test
