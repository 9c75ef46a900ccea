// `jetshell fit FIT.json --out DIR`: fit material parameters to observations (FITTING.md) and write fit.json
// and plots.
#include "core/mesh.h"
#include "tools/fit/fit_file.h"
#include "tools/fit/fit_report.h"
#include "tools/fit/fit_setup.h"
#include "tools/output/interrupt.h"
#include "tools/subcommand.h"

#include <filesystem>
#include <iostream>

namespace jetshell::cli {
namespace {

const RegisterSubcommand registerFit("fit", [](CLI::App& app, int& exitCode) {
  struct Args {
    std::string fit;
    std::string out;
    std::string algorithm;
    bool checkOnly = false;
    bool noPlots = false;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("fit", "Fit material parameters to observations (FITTING.md): fit.json and plots");
  cmd->add_option("fit", args->fit, "Fit file (JSON)")->required();
  cmd->add_option("--out,-o", args->out, "Output directory (default: out/<fit file name>)");
  cmd->add_option("--algorithm", args->algorithm,
                  "Override the file's algorithm: bobyqa | nelder-mead | lbfgs | mma | levenberg-marquardt");
  cmd->add_flag("--check", args->checkOnly, "Only read and check the fit file (scene, meshes, CSV), then exit");
  cmd->add_flag("--no-plots", args->noPlots, "Skip the PNG plots");
  cmd->callback([args, &exitCode] {
    FitFile file = loadFitFile(args->fit);
    if (!args->algorithm.empty()) file.options.algorithm = fitAlgorithmFromString(args->algorithm);
    FitSetup setup(file);
    if (args->checkOnly) {
      std::cout << args->fit << ": ok (" << file.parameters.size() << " parameter(s), " << file.observations.size()
                << " observation(s), " << setup.problem().numResiduals() << " observed coordinates at "
                << setup.problem().levels().size() << " " << setup.problem().levelName() << "(s))\n";
      exitCode = kOk;
      return;
    }
    // Ctrl-C stops the fit before its next forward evaluation; the report then holds the best values so far.
    file.options.stopRequested = interruptRequested;
    installInterruptHandler();
    FitResult result;
    try {
      result = runFit(setup.problem(), setup.variables(), file.options);
    } catch (...) {
      removeInterruptHandler();
      throw;
    }
    removeInterruptHandler();
    FitReportInputs in;
    in.problem = &setup.problem();
    in.result = &result;
    in.groupLabels = setup.groupLabels();
    in.fitFile = args->fit;
    in.description = file.description;
    const std::string dir = args->out.empty()
                                ? (std::filesystem::path("out") / std::filesystem::path(args->fit).stem()).string()
                                : args->out;
    std::vector<std::string> notes;
    const std::vector<std::string> files = writeFitReport(in, dir, file.plots && !args->noPlots, notes);
    std::cout << fitSummaryText(in);
    for (const std::string& n : notes) std::cout << "note: " << n << "\n";
    std::cout << "outputs:";
    for (const std::string& f : files) std::cout << " " << f;
    std::cout << "\n";
    exitCode = result.interrupted ? kInterrupted : result.success ? kOk : kFailed;
  });
});

}  // namespace
}  // namespace jetshell::cli
