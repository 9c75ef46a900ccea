#include "tools/scene/run_scene.h"
#include "tools/scene/safeguard_report.h"
#include "tools/scene/scene_json.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <functional>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

TEST_CASE("safeguards: every kind of safeguard is counted by what fired", "[safeguards]") {
  SafeguardReport r;
  SolverSummary lineSearch;
  lineSearch.reason = TerminationReason::LineSearchFailure;
  lineSearch.nonFiniteTrials = 3;
  r.add(lineSearch, false);  // cut and retried
  SolverSummary regularized;
  regularized.reason = TerminationReason::Converged;
  regularized.regularizations = 2;
  IterationRecord rec;
  rec.shift = 1e-6;
  regularized.trace.push_back(rec);
  r.add(regularized, true);
  SolverSummary capped;
  capped.reason = TerminationReason::IterationCap;
  r.add(capped, true);   // moved on
  r.add(capped, false);  // cut
  SolverSummary discarded = capped;
  discarded.discarded = true;  // ended above its step's previous positions: solved again from them
  r.add(discarded, true);
  const nlohmann::json j = r.toJson("move_on");
  CHECK(j["step_cuts"] == 2);
  CHECK(j["step_cuts_by_reason"]["line_search_failure"] == 1);
  CHECK(j["step_cuts_by_reason"]["iteration_cap"] == 1);
  CHECK(j["non_finite_trials_rejected"] == 3);
  CHECK(j["regularized_solves"] == 1);
  CHECK(j["regularization_retries"] == 2);
  CHECK(j["largest_shift"] == 1e-6);
  CHECK(j["iteration_cap_outcome"] == "move_on");
  CHECK(j["steps_accepted_at_iteration_cap"] == 1);
  CHECK(j["steps_solved_again_from_previous_positions"] == 1);
  SafeguardReport copy;
  copy.restore(r.state());
  CHECK(copy.toJson("move_on") == j);
}

namespace {

nlohmann::json readSummary(const std::string& name) {
  std::ifstream in(test::scratchDirectory("safeguard_tests") / name / "summary.json");
  std::stringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str());
}

// A 1 m cloth hanging from two corners for 0.3 s in steps of 0.1 s; `edit` changes the scene before it runs.
nlohmann::json runCloth(const nlohmann::json& solver, const std::string& name, std::ostream* log = nullptr,
                        RunResult* result = nullptr, const std::function<void(nlohmann::json&)>& edit = {}) {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "gravity": [0, 0, -9.81],
    "actors": [{"type": "shell", "shape": {"generator": "rectangle", "width": 1, "height": 1, "nx": 5, "ny": 5},
                "material": {"youngsModulus": 1e6, "poissonRatio": 0.3, "thickness": 0.0005, "volumeDensity": 300},
                "colliderType": "None", "fixed": [{"select": [{"nearest": [0, 1, 0]}, {"nearest": [1, 1, 0]}]}]}],
    "analysis": {"type": "dynamic", "timeStep": 0.1, "duration": 0.3},
    "outputs": {"png": false, "plots": false}})");
  scene["solver"] = solver;
  if (edit) edit(scene);
  RunOptions o;
  o.outputDirectory = (test::scratchDirectory("safeguard_tests") / name).string();
  fs::remove_all(o.outputDirectory);
  o.pictures = false;
  o.log = log;
  const RunResult r = runScene(sceneFromJson(scene, "."), o);
  if (result) *result = r;
  return readSummary(name)["safeguards"];
}

int countLines(const std::string& text, const std::string& mark) {
  int n = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.find(mark) != std::string::npos) ++n;
  return n;
}

}  // namespace

TEST_CASE("safeguards: summary.json states the cuts and the iteration-cap outcome a run chose", "[safeguards]") {
  // Two Newton iterations per step are too few at 0.1 s: by default the step is cut and retried ...
  const nlohmann::json cut = runCloth({{"maxIterations", 2}, {"threads", 1}}, "cut");
  CHECK(cut["iteration_cap_outcome"] == "cut_step");
  CHECK(cut["step_cuts"].get<int>() > 0);
  CHECK(cut["step_cuts_by_reason"]["iteration_cap"].get<int>() > 0);
  CHECK(cut["steps_accepted_at_iteration_cap"] == 0);
  // ... or, as the page's engine does, the last iterate is taken and the run moves on.
  std::ostringstream log;
  RunResult result;
  const nlohmann::json moveOn =
      runCloth({{"maxIterations", 2}, {"acceptIterationCap", true}, {"threads", 1}}, "move_on", &log, &result);
  CHECK(moveOn["iteration_cap_outcome"] == "move_on");
  CHECK(moveOn["step_cuts"] == 0);
  const int movedOn = moveOn["steps_accepted_at_iteration_cap"].get<int>();
  CHECK(movedOn > 0);
  // The log marks each such step, and the run's notes count them.
  CHECK(countLines(log.str(), "(moved on at the iteration cap, not converged)") == movedOn);
  const std::string note = std::to_string(movedOn) + " of 3 steps moved on at the iteration cap without converging";
  CHECK(std::count_if(result.notes.begin(), result.notes.end(),
                      [&](const std::string& n) { return n.rfind(note, 0) == 0; }) == 1);
}

TEST_CASE("safeguards: a step taken in parts counts as moved on when any part moved on, though its last converged",
          "[safeguards]") {
  // A ball rising at 6 m/s into the hanging cloth and lifting it: each 0.1 s step is taken in 16 parts (the ball
  // may move only a fraction of its radius near the shell per part), some parts end at the cap of 5 Newton
  // iterations, and the last part of most steps converges. Counting only the last part's outcome said 1 of 4
  // steps had moved on while the log marked all 4.
  std::ostringstream log;
  RunResult result;
  runCloth({{"maxIterations", 5}, {"acceptIterationCap", true}, {"threads", 1}}, "parts_move_on", &log, &result,
           [](nlohmann::json& scene) {
             scene["actors"][0]["shape"]["nx"] = 10;
             scene["actors"][0]["shape"]["ny"] = 10;
             scene["actors"].push_back(nlohmann::json::parse(
                 R"({"type": "sphere", "name": "ball", "center": [0.5, 0.5, -0.3], "radius": 0.1,
                     "velocity": [0, 0, 6]})"));
             scene["analysis"]["duration"] = 0.4;
           });
  const nlohmann::json summary = readSummary("parts_move_on");
  const int steps = summary["steps_at_iteration_cap"].get<int>();
  CHECK(countLines(log.str(), "parts: a moving solid") == 4);
  CHECK(countLines(log.str(), "(moved on at the iteration cap, not converged)") == steps);
  CHECK(steps >= 2);
  CHECK(summary["termination"] == "completed_with_unconverged_steps");
  const std::string note = std::to_string(steps) + " of 4 steps moved on at the iteration cap without converging";
  CHECK(std::count_if(result.notes.begin(), result.notes.end(),
                      [&](const std::string& n) { return n.rfind(note, 0) == 0; }) == 1);
}
