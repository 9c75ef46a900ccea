#include "tools/fit/fit_file.h"

#include "core/mesh.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

const char* kScene = R"({
  "gravity": [0, 0, 0],
  "actors": [{
    "type": "shell", "name": "strip",
    "shape": { "generator": "rectangle", "width": 1.0, "height": 0.2, "nx": 4, "ny": 1 },
    "material": { "youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.01, "volumeDensity": 0 },
    "hasGravity": false, "colliderType": "None",
    "fixed": [ { "select": { "group": "left" }, "clampRotation": true } ],
    "loads": [ { "select": { "group": "right" }, "force": [0, 0, 0.01], "distribution": "edgeLength" } ],
    "probes": [ { "name": "tip", "select": { "nearest": [1, 0, 0] } } ]
  }],
  "analysis": { "type": "static", "loadSteps": 2 }
})";

fs::path directory() {
  const fs::path d = test::scratchDirectory("fit_file_tests");
  fs::create_directories(d);
  return d;
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

/// A fit file with the scene inline; `parameters` and `observations` replace the defaults when given.
nlohmann::json fitJson() {
  nlohmann::json j;
  j["scene"] = nlohmann::json::parse(kScene);
  j["parameters"] = nlohmann::json::parse(
      R"([{ "actor": "strip", "name": "youngsModulus", "initial": 5e5, "lower": 1e4, "upper": 1e8, "logScale": true }])");
  j["observations"] = nlohmann::json::parse(
      R"([{ "type": "probe", "probe": "tip", "loadFactor": 1.0, "component": "z", "displacement": 0.05 }])");
  return j;
}

std::string fitErrorOf(const nlohmann::json& j) {
  try {
    fitFromJson(j, directory().string(), "fit.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("fit file: a valid file is read with its defaults", "[fit]") {
  const FitFile f = fitFromJson(fitJson(), directory().string(), "fit.json");
  REQUIRE(f.parameters.size() == 1);
  CHECK(f.parameters[0].variable.label == "strip.youngsModulus");
  CHECK(f.parameters[0].variable.logScale);
  CHECK(f.material.isotropic);
  CHECK(f.material.poissonRatio == 0.3);
  REQUIRE(f.observations.size() == 1);
  CHECK(f.observations[0].components == std::vector<int>{2});
  CHECK(f.observations[0].displacements[0].z() == 0.05);
  CHECK(f.options.algorithm == FitAlgorithm::LevenbergMarquardt);
}

TEST_CASE("fit file: bad fields give one-line errors naming the JSON pointer", "[fit]") {
  nlohmann::json j = fitJson();
  j["parametrs"] = 1;
  CHECK_THAT(fitErrorOf(j), Catch::Contains("parametrs") && Catch::Contains("parameters"));

  j = fitJson();
  j["parameters"][0]["name"] = "youngModulus";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/name") && Catch::Contains("youngsModulus"));

  j = fitJson();
  j["parameters"][0]["name"] = "membraneLambda";  // the scene gives E, nu, h: lambda is not a free input
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/name") && Catch::Contains("not a fittable"));

  j = fitJson();
  j["parameters"][0]["upper"] = 1e3;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/upper"));

  j = fitJson();
  j["parameters"][0]["lower"] = -1.0;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/lower"));

  j = fitJson();
  j["parameters"][0]["actor"] = "cloth";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/actor"));

  j = fitJson();
  j["observations"][0]["probe"] = "tipp";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/probe") && Catch::Contains("did you mean \"tip\""));

  j = fitJson();
  j["observations"][0]["component"] = "w";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/component"));

  j = fitJson();
  j["observations"][0]["time"] = 0.5;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/time"));

  j = fitJson();
  j["observations"][0]["loadFactor"] = -1;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/loadFactor"));

  j = fitJson();
  j["observations"][0]["weight"] = "heavy";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/weight"));

  j = fitJson();
  j["algorithm"] = "newton";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/algorithm"));

  j = fitJson();
  j["maxEvaluations"] = 1000000;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/maxEvaluations"));

  j = fitJson();
  j["scene"]["actors"][0]["material"]["poissonRatio"] = 0.7;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/scene/actors/0/material/poissonRatio"));

  j = fitJson();
  j["scene"]["analysis"] =
      nlohmann::json::parse(R"({ "type": "dynamicRelaxation", "timeStep": 0.01, "massDamping": 1 })");
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/scene") && Catch::Contains("static"));

  j = fitJson();
  j["observations"][0].erase("loadFactor");
  j["observations"][0]["time"] = 0.1;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/time") && Catch::Contains("dynamic scene"));

  j = fitJson();
  j["parameters"] = nlohmann::json::array();
  for (int k = 0; k < 9; ++k) j["parameters"].push_back(fitJson()["parameters"][0]);
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters") && Catch::Contains("at most 8"));
}

TEST_CASE("fit file: weights and observed displacements are bounded, and some weight must count", "[fit]") {
  nlohmann::json j = fitJson();
  j["observations"][0]["weight"] = 1e308;  // squared, it overflowed the misfit to inf
  CHECK(fitErrorOf(j) == "/observations/0/weight = 1e+308: must be at most 1e+12");
  j = fitJson();
  j["observations"][0]["displacement"] = 1e308;
  CHECK(fitErrorOf(j) == "/observations/0/displacement = 1e+308: must be at most 1e+06 m in size");
  j = fitJson();
  j["observations"][0].erase("component");
  j["observations"][0]["displacement"] = {1e200, 0, 0};
  CHECK(fitErrorOf(j) == "/observations/0/displacement = [1e+200, 0, 0]: too large (norm at most 1e+06)");
  j = fitJson();
  j["observations"][0]["weight"] = 0;
  CHECK(fitErrorOf(j) == "/observations: every observation has weight 0: nothing to fit");
}

TEST_CASE("fit file: CSV curves and target shapes are read and checked", "[fit]") {
  const fs::path d = directory();
  write(d / "curve.csv", "load,u\n0.5,0.01\n1.0,0.02\n");
  nlohmann::json j = fitJson();
  j["observations"] = nlohmann::json::parse(R"([{ "type": "curve", "probe": "tip", "component": "z", "csv": "curve.csv" }])");
  const FitFile f = fitFromJson(j, d.string(), "fit.json");
  REQUIRE(f.observations[0].levels == std::vector<double>{0.5, 1.0});
  CHECK(f.observations[0].displacements[1].z() == 0.02);

  write(d / "bad_curve.csv", "0.5,0.01\n0.4,0.02\n");
  j["observations"][0]["csv"] = "bad_curve.csv";
  CHECK_THAT(fitErrorOf(j), Catch::Contains("bad_curve.csv:2") && Catch::Contains("increase"));
  write(d / "bad_curve.csv", "0.5,0.01\n1.0,x\n");
  CHECK_THAT(fitErrorOf(j), Catch::Contains("bad_curve.csv:2") && Catch::Contains("at least 2 numbers"));
  write(d / "table.tsv", "# lambda W_A W_B\n0.5\t1\t2\n1.0\t3\t4\n");
  j["observations"][0]["csv"] = "table.tsv";
  j["observations"][0]["displacementColumn"] = 2;
  CHECK(fitFromJson(j, d.string(), "fit.json").observations[0].displacements[1].z() == 4.0);
  j["observations"][0]["displacementColumn"] = 0;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/displacementColumn"));
  j["observations"][0].erase("displacementColumn");
  // A header after comment lines is still the header; a second line without numbers is an error.
  write(d / "commented.csv", "# measured 2026-11-29\n\n# load factor, deflection\nlambda,w\n0.5,0.01\n1,0.03\n");
  j["observations"][0]["csv"] = "commented.csv";
  CHECK(fitFromJson(j, d.string(), "fit.json").observations[0].displacements[1].z() == 0.03);
  write(d / "two_headers.csv", "lambda,w\nload,u\n0.5,0.01\n");
  j["observations"][0]["csv"] = "two_headers.csv";
  CHECK_THAT(fitErrorOf(j), Catch::Contains("two_headers.csv:2") && Catch::Contains("at least 2 numbers"));
  j["observations"][0]["csv"] = "missing.csv";
  CHECK_THAT(fitErrorOf(j), Catch::Contains("missing.csv") && Catch::Contains("cannot open"));

  write(d / "target.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  j = fitJson();
  j["observations"] = nlohmann::json::parse(R"([{ "type": "shape", "actor": "strip", "loadFactor": 1, "obj": "target.obj" }])");
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/obj") && Catch::Contains("has 3 vertices"));
}

TEST_CASE("fit file: every example fit file (examples/fit_*.json) reads", "[fit]") {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(JETSHELL_SOURCE_DIR) / "examples")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("fit_", 0) != 0 || entry.path().extension() != ".json") continue;
    INFO(name);
    const FitFile f = loadFitFile(entry.path().string());
    CHECK(!f.parameters.empty());
    CHECK(!f.observations.empty());
    ++count;
  }
  CHECK(count >= 3);
}

TEST_CASE("fit file: a dynamic scene's observations are at step times, bad times and new fields name their pointer",
          "[fit]") {
  auto dynamic = [] {
    nlohmann::json j = fitJson();
    j["scene"]["analysis"] = nlohmann::json::parse(R"({ "type": "dynamic", "timeStep": 0.01, "duration": 0.1 })");
    j["observations"][0].erase("loadFactor");
    j["observations"][0]["time"] = 0.05;
    return j;
  };
  const FitFile f = fitFromJson(dynamic(), directory().string(), "fit.json");
  REQUIRE(f.observations.size() == 1);
  CHECK(f.observations[0].levels == std::vector<double>{5 * 0.01});

  nlohmann::json j = dynamic();
  j["observations"][0]["time"] = 0.0500000001;  // within round-off of a step time: snapped
  CHECK(fitFromJson(j, directory().string(), "fit.json").observations[0].levels[0] == 5 * 0.01);

  j = dynamic();
  j["observations"][0]["time"] = 0.055;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/time = 0.055: not a step time"));
  j["observations"][0]["time"] = 0.11;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/time = 0.11: beyond the end"));
  j["observations"][0]["time"] = 0.0;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/time"));
  j["observations"][0]["time"] = -0.01;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/time"));
  j["observations"][0]["time"] = "soon";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/time"));

  j = dynamic();
  j["observations"][0].erase("time");
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0") && Catch::Contains("time"));
  j["observations"][0]["loadFactor"] = 1.0;
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/loadFactor") && Catch::Contains("dynamic"));

  j = dynamic();
  j["observations"][0] = nlohmann::json::parse(R"({ "type": "curve", "probe": "tip", "component": "z", "csv": "c.csv" })");
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/observations/0/type") && Catch::Contains("static"));

  j = dynamic();
  j["parameters"][0] = nlohmann::json::parse(
      R"({ "actor": "strip", "name": "massDampingCoefficient", "initial": 1, "lower": -1, "upper": 10 })");
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/lower"));
  j["parameters"][0]["name"] = "massDamping";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/name") && Catch::Contains("massDampingCoefficient"));
  j["parameters"][0] = nlohmann::json::parse(
      R"({ "actor": "strip", "name": "gravityScale", "lower": 0.5, "upper": 2 })");
  const FitFile g = fitFromJson(j, directory().string(), "fit.json");
  CHECK(g.parameters[0].variable.initial == 1.0);

  // The scale of one named load.
  j = dynamic();
  j["scene"]["actors"][0]["loads"][0]["name"] = "push";
  j["parameters"][0] = nlohmann::json::parse(
      R"({ "actor": "strip", "name": "loadScale", "load": "push", "lower": 0.5, "upper": 2 })");
  CHECK(fitFromJson(j, directory().string(), "fit.json").parameters[0].load == "push");
  j["parameters"][0]["load"] = "puhs";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/load") && Catch::Contains("did you mean \"push\""));
  j["parameters"][0]["load"] = "push";
  j["parameters"][0]["name"] = "gravityScale";
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/parameters/0/load") && Catch::Contains("loadScale"));
  j = dynamic();
  j["scene"]["actors"][0]["loads"][0]["name"] = "push";
  j["scene"]["actors"][0]["loads"].push_back(j["scene"]["actors"][0]["loads"][0]);
  CHECK_THAT(fitErrorOf(j), Catch::StartsWith("/scene/actors/0/loads/1/name") && Catch::Contains("duplicate"));
}
