// `jetshell stress [--quick] [--json FILE]`: the stress matrix of tools/stress/stress_cells.h. Each cell runs in
// a child process with a wall-clock budget, so a crash or a hang is reported as such instead of ending the sweep.
// Exit 0 when every cell is ok or failed_cleanly, 1 when any is a defect. STABILITY.md holds the table.
#include "core/mesh.h"
#include "tools/output/atomic_file.h"
#include "tools/output/directories.h"
#include "tools/stress/isolated_run.h"
#include "tools/stress/stress_cells.h"
#include "tools/subcommand.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

namespace jetshell::cli {
namespace {

struct StressArgs {
  bool quick = false;
  std::string json;
  std::string only;
  std::string out;
  double budget = 60.0;
};

int runStress(const StressArgs& a) {
  namespace fs = std::filesystem;
  const std::vector<StressCell> cells = stressCells(a.quick);
  // Without --out, a fresh private directory (tools/output/directories.h), removed at the end.
  std::unique_ptr<TemporaryDirectory> temporary;
  fs::path root;
  std::error_code ec;
  if (a.out.empty()) {
    temporary = std::make_unique<TemporaryDirectory>("jetshell_stress_");
    root = temporary->path();
  } else {
    root = a.out;
    createOutputDirectory(a.out, "--out");
  }
  checkOutputOption(a.json, "--json");  // here, not on the command line: it may go in the --out directory
  nlohmann::json all = nlohmann::json::array();
  int ok = 0, clean = 0, defects = 0;
  std::printf("%-34s %-15s %8s  %s\n", "cell", "outcome", "wall [s]", "reason");
  for (const StressCell& cell : cells) {
    if (!a.only.empty() && cell.name.find(a.only) == std::string::npos) continue;
    std::string dirName = cell.name;
    for (char& ch : dirName)
      if (ch == '/' || ch == '=') ch = '_';
    const std::string dir = (root / dirName).string();
    fs::remove_all(dir, ec);
    const IsolatedResult r = runIsolated([&] { return runStressCell(cell, dir); }, a.budget);
    nlohmann::json j;
    if (r.status == IsolatedResult::Status::Finished) {
      j = r.value;
    } else {
      j = {{"name", cell.name}, {"what", cell.what}, {"outcome", "defect"},
           {"reason", (r.status == IsolatedResult::Status::TimedOut ? "hang: " : "crash: ") + r.what}};
    }
    j["wall_seconds"] = r.wallSeconds;
    j["budget_seconds"] = a.budget;
    const std::string outcome = j["outcome"];
    if (outcome == "ok") ++ok;
    else if (outcome == "failed_cleanly") ++clean;
    else ++defects;
    std::string reason = j["reason"];
    if (reason.size() > 110) reason.replace(107, std::string::npos, "...");
    std::printf("%-34s %-15s %8.2f  %s\n", cell.name.c_str(), outcome.c_str(), r.wallSeconds, reason.c_str());
    std::fflush(stdout);
    all.push_back(std::move(j));
  }
  std::printf("\n%zu cells: %d ok, %d failed cleanly, %d defects\n", all.size(), ok, clean, defects);
  if (!a.json.empty()) {
    writeFileAtomically(a.json, nlohmann::json{{"cells", all},
                                               {"summary", {{"cells", all.size()}, {"ok", ok}, {"failed_cleanly", clean}, {"defects", defects}}}}
                                        .dump(2) + "\n");
    std::printf("wrote %s\n", a.json.c_str());
  }
  return defects == 0 ? kOk : kFailed;
}

const RegisterSubcommand registerStress("stress", [](CLI::App& app, int& exitCode) {
  auto a = std::make_shared<StressArgs>();
  CLI::App* cmd = app.add_subcommand("stress", "Run the stress matrix (STABILITY.md): every cell must end ok or failed_cleanly");
  cmd->add_flag("--quick", a->quick, "The reduced matrix (a few seconds; run by CTest)");
  cmd->add_option("--json", a->json, "Write every cell (name, outcome, reason, wall_seconds, ...) to this JSON file");
  cmd->add_option("--only", a->only, "Only the cells whose name contains this text");
  cmd->add_option("--out", a->out, "Keep each cell's run outputs under this directory (default: a temporary one, removed)");
  cmd->add_option("--budget", a->budget, "Wall-clock budget per cell in seconds (a cell over it is a hang)")
      ->check(finiteRange(0.1, 3600.0));
  cmd->callback([a, &exitCode] { exitCode = runStress(*a); });
});

}  // namespace
}  // namespace jetshell::cli
