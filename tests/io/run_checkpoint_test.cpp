#include "tools/output/run_checkpoint.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include "core/mesh.h"
#include "tests/fuzz/checkpoint_scene.h"

using namespace jetshell;
using Json = nlohmann::json;

namespace {

/// The fuzz harness's scene (4 vertices, one probe), of one shell actor, checkpointed after 5 steps of 0.01 s.
CheckpointScene fourVertices() {
  CheckpointScene s = fuzz::checkpointScene();
  s.frameFiles = 1;
  return s;
}

/// Numbers as the checkpoint packs a plot row's lists: a byte string of little-endian doubles.
Json packed(const std::vector<double>& values) {
  std::vector<std::uint8_t> bytes;
  for (double v : values) {
    std::uint64_t word = 0;
    std::memcpy(&word, &v, sizeof word);
    for (int b = 0; b < 8; ++b) bytes.push_back(static_cast<std::uint8_t>(word >> (8 * b)));
  }
  return Json::binary(bytes);
}

RunCheckpoint afterFiveSteps() {
  RunCheckpoint c;
  c.solver.x = Eigen::VectorXd::LinSpaced(12, 0.0, 1.0);
  c.solver.v = Eigen::VectorXd::Constant(12, -0.25);
  c.solver.t = 0.05;
  c.solver.historyStep = 0.01;
  c.solver.steps = 5;
  c.checkpointEvery = 5;
  c.newtonIterations = 11;
  c.cuts = 1;
  c.stepsAtIterationCap = 1;
  c.worstResidualOverTolerance = 3.5;
  c.safeguards.cuts = {{"iteration_cap", 1}};
  c.safeguards.largestShift = 1e-6;
  for (int step = 0; step <= 5; ++step) {
    const ProbeRow row{step, 0.01 * step, 1.0, {0.0, 0.0, -0.1 * step}, {}};
    c.output.plotRows.add(row, c.output.lastRow ? &*c.output.lastRow : nullptr);
    c.output.lastRow = row;
  }
  c.output.frames = 6;
  c.output.lastFrameStep = 5;
  c.output.lastFrame = {"frames/frame_00005.vtu"};
  c.output.pvdBytes = 603;
  c.output.probesBytes = 224;
  c.output.lastRowOffset = 200;
  return c;
}

}  // namespace

TEST_CASE("run checkpoint: every field is written and read back exactly") {
  const CheckpointScene scene = fourVertices();
  RunCheckpoint c = afterFiveSteps();
  c.solver.historyValid = true;
  c.solver.xPrev = c.solver.x * 0.5;
  c.solver.vPrev = c.solver.v * 2.0;
  const Json j = Json::from_cbor(Json::to_cbor(toJson(c, scene)));
  const RunCheckpoint r = runCheckpointFromJson(j, scene, "c.cbor");
  CHECK(r.solver.x == c.solver.x);
  CHECK(r.solver.v == c.solver.v);
  CHECK(r.solver.xPrev == c.solver.xPrev);
  CHECK(r.solver.vPrev == c.solver.vPrev);
  CHECK(r.solver.t == c.solver.t);
  CHECK(r.solver.historyStep == c.solver.historyStep);
  CHECK(r.solver.steps == 5);
  CHECK(r.solver.historyValid);
  CHECK(r.checkpointEvery == 5);
  CHECK(r.newtonIterations == 11);
  CHECK(r.cuts == 1);
  CHECK(r.stepsAtIterationCap == 1);
  CHECK(r.worstResidualOverTolerance == 3.5);
  CHECK(r.safeguards.cuts == c.safeguards.cuts);
  CHECK(r.safeguards.largestShift == 1e-6);
  REQUIRE(r.output.lastRow);
  CHECK(r.output.lastRow->u == c.output.lastRow->u);
  CHECK(r.output.lastRow->step == 5);
  REQUIRE(r.output.plotRows.rows.size() == 6);
  CHECK(r.output.plotRows.rows[3].u == c.output.plotRows.rows[3].u);
  CHECK(r.output.plotRows.rows[3].time == c.output.plotRows.rows[3].time);
  REQUIRE(r.output.plotRows.ranges.size() == 6);
  CHECK(r.output.plotRows.ranges[3].uLow == c.output.plotRows.ranges[3].uLow);
  CHECK(r.output.plotRows.ranges[3].uHigh == c.output.plotRows.ranges[3].uHigh);
  CHECK(r.output.plotRows.recorded == 6);
  CHECK(r.output.plotRows.stride == 1);
  CHECK(r.output.lastRowOffset == 200);
  CHECK(r.output.lastFrame == c.output.lastFrame);
  CHECK(r.output.frames == 6);
  CHECK(r.output.pvdBytes == c.output.pvdBytes);
  CHECK(r.output.probesBytes == c.output.probesBytes);
  // Without a BDF2 history the previous state may be absent; closed files have no size.
  c.solver.historyValid = false;
  c.solver.xPrev.resize(0);
  c.solver.vPrev.resize(0);
  c.output.pvdBytes.reset();
  const RunCheckpoint s = runCheckpointFromJson(toJson(c, scene), scene, "c.cbor");
  CHECK(s.solver.xPrev.size() == 0);
  CHECK(!s.output.pvdBytes);
}

TEST_CASE("run checkpoint: the rows' contact forces are read back, three per measured solid") {
  CheckpointScene scene = fourVertices();
  scene.contactSolids = 2;
  RunCheckpoint c = afterFiveSteps();
  for (std::size_t k = 0; k < c.output.plotRows.rows.size(); ++k) {
    ProbeRow& row = c.output.plotRows.rows[k];
    row.force = {0.0, 0.0, 0.5 * row.step, -1.0, 0.0, 0.25};
    c.output.plotRows.ranges[k] = RowRange(row);
  }
  c.output.lastRow = c.output.plotRows.rows.back();
  const Json saved = toJson(c, scene);
  const RunCheckpoint r = runCheckpointFromJson(Json::from_cbor(Json::to_cbor(saved)), scene, "c.cbor");
  REQUIRE(r.output.plotRows.rows.size() == 6);
  for (std::size_t k = 0; k < 6; ++k) CHECK(r.output.plotRows.rows[k].force == c.output.plotRows.rows[k].force);
  CHECK(r.output.lastRow->force == c.output.lastRow->force);
  const auto refused = [&](const std::function<void(Json&)>& edit, const std::string& message) {
    Json j = saved;
    edit(j);
    INFO(message);
    CHECK_THROWS_WITH(runCheckpointFromJson(j, scene, "c.cbor"), "c.cbor: " + message);
  };
  refused([](Json& j) { j["output"]["plot_rows"][2].erase("force"); },
          "output/plot_rows/2/force: missing (an incomplete checkpoint)");
  refused([](Json& j) { j["output"]["plot_rows"][0]["force"] = packed(std::vector<double>(3, 1.0)); },
          "output/plot_rows/0/force: must be 6 numbers packed as a byte string of 48 bytes (little-endian doubles)");
  refused([](Json& j) { j["output"]["plot_rows"][0]["force"] = std::vector<double>(6, 1.0); },
          "output/plot_rows/0/force: must be 6 numbers packed as a byte string of 48 bytes (little-endian doubles)");
  refused([](Json& j) { j["output"]["last_row"]["force"][4] = std::numeric_limits<double>::infinity(); },
          "output/last_row/force: holds a value that is not a finite number");
  // A scene without measured solids refuses rows with forces.
  scene.contactSolids = 0;
  refused([](Json&) {}, "output/last_row/force: must be a list of 0 numbers");
}

TEST_CASE("run checkpoint: a field edited by hand is refused with its name") {
  const CheckpointScene scene = fourVertices();
  const Json saved = toJson(afterFiveSteps(), scene);
  REQUIRE_NOTHROW(runCheckpointFromJson(saved, scene, "c.cbor"));
  const auto refused = [&](const std::function<void(Json&)>& edit, const std::string& message) {
    Json j = saved;
    edit(j);
    INFO(message);
    CHECK_THROWS_WITH(runCheckpointFromJson(j, scene, "c.cbor"), "c.cbor: " + message);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // The last frame is read back for final.png: only frame files inside the output directory.
  refused([](Json& j) { j["output"]["last_frame"] = {"/etc/hostname"}; },
          "output/last_frame: must name files frames/NAME.vtu (letters, digits and _) inside the output directory");
  refused([](Json& j) { j["output"]["last_frame"] = {"frames/../../../dev/zero.vtu"}; },
          "output/last_frame: must name files frames/NAME.vtu (letters, digits and _) inside the output directory");
  refused(
      [](Json& j) {
        j["output"]["last_frame"] = {"frames/a.vtu", "frames/b.vtu"};
      },
      "output/last_frame: holds 2 entries (at most 1)");
  // Probe rows become probes.csv and summary.json: one value per probe and axis, steps in order.
  refused([](Json& j) { j["output"]["plot_rows"][0]["u"] = Json::array(); },
          "output/plot_rows/0/u: must be 3 numbers packed as a byte string of 24 bytes (little-endian doubles)");
  refused([&](Json& j) { j["output"]["plot_rows"][1]["u"] = packed({0.0, nan, 0.0}); },
          "output/plot_rows/1/u: holds a value that is not a finite number");
  refused([](Json& j) { j["output"]["last_row"]["u"] = std::vector<double>(30000, 1e300); },
          "output/last_row/u: must be a list of 3 numbers");
  refused([](Json& j) { j["output"]["plot_rows"][4]["step"] = 1; },
          "output/plot_rows/4/step: must increase row by row up to the last row's");
  refused([](Json& j) { j["output"]["last_row"]["step"] = 4; },
          "output/last_frame_step: must be a whole number in [-1, 4]");
  refused(
      [](Json& j) {
        j["output"]["last_row"]["step"] = 4;
        j["output"]["last_frame_step"] = 4;
      },
      "output/plot_rows/5/step: must increase row by row up to the last row's");
  refused([&](Json& j) { j["output"]["plot_rows"][1]["time"] = nan; },
          "output/plot_rows/1/time: must lie in [0, duration]");
  refused([](Json& j) { j["output"]["last_row"] = Json::object(); },
          "output/last_row/step: missing (an incomplete checkpoint)");
  const std::string plotRule = "output/plot_rows: do not match plot_stride and recorded_rows (every stride-th of the "
                               "recorded rows, at most 2048, the stride a power of two, the last row recorded)";
  refused([](Json& j) { j["output"]["plot_rows"].erase(2); }, plotRule);
  refused([](Json& j) { j["output"]["plot_stride"] = 3; }, plotRule);
  // A bucket's range holds its first row, value by value.
  refused([](Json& j) { j["output"]["plot_rows"][1].erase("u_low"); },
          "output/plot_rows/1/u_low: missing (an incomplete checkpoint)");
  refused([](Json& j) { j["output"]["plot_rows"][3]["force_high"] = packed({1.0}); },
          "output/plot_rows/3/force_high: must be 0 numbers packed as a byte string of 0 bytes (little-endian doubles)");
  refused([](Json& j) { j["output"]["plot_rows"][2]["u_high"] = packed({0.0, 0.0, -5.0}); },
          "output/plot_rows/2: u_low <= u <= u_high and force_low <= force <= force_high must hold value by value");
  refused([](Json& j) { j["output"]["recorded_rows"] = 5; }, plotRule);
  refused([](Json& j) { j["output"]["last_row"] = nullptr; }, "output/last_row: must be an object");
  refused(
      [](Json& j) {
        j["output"]["plot_rows"] = Json::array();
        j["output"]["recorded_rows"] = 0;
      },
      plotRule);
  refused([](Json& j) { j["output"]["recorded_rows"] = 1000000000; },
          "output/recorded_rows: must be a whole number in [0, 6]");
  refused([](Json& j) { j["output"]["plot_rows"] = std::vector<Json>(2049, Json::object()); },
          "output/plot_rows: holds 2049 entries (at most 2048)");
  refused([](Json& j) { j["output"]["last_row_offset"] = 225; },
          "output/last_row_offset: must be a whole number in [0, 224]");
  refused([](Json& j) { j["output"]["frames"] = -7; }, "output/frames: must be a whole number in [0, 6]");
  refused([](Json& j) { j["output"]["pvd_bytes"] = -1; },
          "output/pvd_bytes: must be a whole number in [0, 1125899906842624]");
  // Counts: whole numbers in range (a float or an unsigned beyond int was cut or wrapped when converted).
  refused([](Json& j) { j["newton_iterations"] = 4294967301ull; },
          "newton_iterations: must be a whole number in [0, 1000000000]");
  refused([](Json& j) { j["solver"]["steps"] = 1e300; }, "solver/steps: must be a whole number in [0, 10000000]");
  refused([](Json& j) { j["solver"]["steps"] = 2.5; }, "solver/steps: must be a whole number in [0, 10000000]");
  refused([](Json& j) { j["checkpoint_every"] = 0; }, "checkpoint_every: must be a whole number in [1, 10000000]");
  refused([](Json& j) { j["steps_at_iteration_cap"] = 6; }, "steps_at_iteration_cap: must be a whole number in [0, 5]");
  refused([](Json& j) { j["safeguards"]["accepted_at_cap"] = -5; },
          "safeguards/accepted_at_cap: must be a whole number in [0, 1000000000]");
  refused([&](Json& j) { j["safeguards"]["largest_shift"] = nan; },
          "safeguards/largest_shift: must be finite and >= 0");
  refused(
      [](Json& j) {
        j["safeguards"]["cuts"] = {{"k0", 1}};
      },
      "safeguards/cuts: a reason must be one of the reasons a step is cut for (iteration_cap, line_search_failure, "
      "linear_solver_failure, non_finite, stalled)");
  refused(
      [](Json& j) {
        j["safeguards"]["cuts"] = {{"iteration_cap", -1}};
      },
      "safeguards/cuts/iteration_cap: must be a whole number in [0, 1000000000]");
  // The solver's state: 3N finite numbers each.
  refused([](Json& j) { j["solver"]["x"] = std::vector<double>(13, 0.0); }, "solver/x: must be a list of 12 numbers");
  refused([&](Json& j) { j["solver"]["v"][5] = nan; }, "solver/v: holds a value that is not a finite number");
  refused([](Json& j) { j["solver"]["history_valid"] = true; }, "solver/x_prev: must be a list of 12 numbers");
  refused([](Json& j) { j["solver"]["history_valid"] = 1; }, "solver/history_valid: must be true or false");
  refused([](Json& j) { j["solver"]["t"] = 1e308; }, "solver/t: must lie in [0, duration]");
  refused([](Json& j) { j.erase("output"); }, "output: missing (an incomplete checkpoint)");
  refused([](Json& j) { j["safeguards"] = 3; }, "safeguards: must be an object");
  // Another scene (or the scene file changed).
  refused([](Json& j) { j["vertices"] = 5; }, "written for another scene (or the scene file changed since)");
  refused([](Json& j) { j["scene_fingerprint"] = "another"; },
          "written for another scene (or the scene file changed since)");
}

TEST_CASE("run checkpoint: bytes that are not a checkpoint of this version are refused") {
  CHECK_THROWS_WITH(parseCheckpoint("", "c.cbor"), "c.cbor: not a jetshell checkpoint");
  CHECK_THROWS_WITH(parseCheckpoint(std::string(200, '\x81') + std::string(1, '\0'), "c.cbor"),
                    "c.cbor: not a jetshell checkpoint");
  const auto cbor = [](const Json& j) {
    const std::vector<std::uint8_t> b = Json::to_cbor(j);
    return std::string(b.begin(), b.end());
  };
  // Version 1 held every probe row, twice (the rows and a plot history); version 2 the plot rows without ranges.
  CHECK_THROWS_WITH(parseCheckpoint(cbor({{kCheckpointVersionKey, 1}}), "c.cbor"),
                    "c.cbor: checkpoint version 1 (this build reads 3)");
  CHECK_THROWS_WITH(parseCheckpoint(cbor({{kCheckpointVersionKey, 2}}), "c.cbor"),
                    "c.cbor: checkpoint version 2 (this build reads 3)");
  CHECK_THROWS_WITH(parseCheckpoint(cbor({{kCheckpointVersionKey, std::string(100000, 'x')}}), "c.cbor"),
                    "c.cbor: checkpoint version (not a number) (this build reads 3)");
  CHECK(parseCheckpoint(cbor({{kCheckpointVersionKey, 3}, {"a", 2}}), "c.cbor").at("a") == 2);
}

TEST_CASE("run checkpoint: the fuzz harness's seeds are checkpoints of its scene") {
  // Seeds that the reader refuses would start the fuzzer outside the fields it should explore.
  int seeds = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(JETSHELL_SOURCE_DIR) + "/tests/fuzz/corpus/checkpoint")) {
    INFO(entry.path().string());
    std::ifstream in(entry.path(), std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    CHECK_NOTHROW(runCheckpointFromJson(parseCheckpoint(bytes.str(), "seed"), fuzz::checkpointScene(), "seed"));
    ++seeds;
  }
  CHECK(seeds >= 3);
}
