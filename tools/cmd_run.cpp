// `jetshell run SCENE.json --out DIR`: solve a scene and write its frames, probes, summary and pictures.
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/mesh.h"
#include "tools/output/checkpoint.h"
#include "tools/output/interrupt.h"
#include "tools/output/progress.h"
#include "tools/scene/run_scene.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/support_check.h"
#include "tools/subcommand.h"

#include <unistd.h>

#include <filesystem>
#include <iostream>

namespace jetshell::cli {
namespace {

const RegisterSubcommand registerRun("run", [](CLI::App& app, int& exitCode) {
  struct Args {
    std::string scene;
    std::string out;
    int steps = 0;
    bool quiet = false;
    bool noPictures = false;
    bool checkOnly = false;
    int checkpointEvery = 0;
    std::string resume;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("run", "Solve a scene (SCENES.md) and write frames, probes.csv, summary.json and pictures");
  cmd->add_option("scene", args->scene, "Scene file (JSON)")->required();
  cmd->add_option("--out,-o", args->out, "Output directory (default: out/<scene name>)")
      ->check(CLI::Validator(
          [](std::string& s) { return s.empty() ? std::string("must not be empty") : std::string(); }, "DIR"));
  cmd->add_option("--steps", args->steps, "Stop after this many steps (a quick look)")
      ->check(CLI::Range(1, static_cast<int>(inputLimits().maxSteps)));
  cmd->add_flag("--check", args->checkOnly, "Only read and check the scene (and its meshes), then exit");
  cmd->add_flag("--quiet,-q", args->quiet, "No log lines, only the final report");
  cmd->add_flag("--no-pictures", args->noPictures, "Skip final.png and probes.png");
  cmd->add_option("--checkpoint-every", args->checkpointEvery,
                  "Dynamics: write checkpoint.cbor into the output directory every N steps (a resumed run: "
                  "the interrupted run's N unless given)")
      ->check(CLI::Range(1, static_cast<int>(inputLimits().maxSteps)));
  cmd->add_option("--resume", args->resume,
                  "Dynamics: continue the run whose output directory DIR holds a checkpoint (same scene file), "
                  "checkpointing as it did; it ends bit for bit as an uninterrupted run");
  cmd->callback([args, &exitCode] {
    // Read once: the run is built from, and its checkpoints fingerprint, the same text.
    const std::string sceneText = readInputFile(args->scene, inputLimits().maxJsonBytes, "scene file");
    const Scene scene = sceneFromText(sceneText, args->scene);
    if (args->checkOnly) {
      const SceneModel model = buildSceneModel(scene);
      checkRigidModes(scene, model);
      std::cout << args->scene << ": ok (" << scene.shells.size() << " shell actor(s), " << scene.volumes.size()
                << " volume actor(s), " << model.numVertices() << " vertices, " << model.prescribed.size()
                << " prescribed coordinates, " << model.probes.size() << " probe(s), " << toString(scene.analysis.type)
                << " analysis)\n";
      for (const std::string& note : unsupportedFeatures(scene)) std::cout << "note: " << note << "\n";
      for (const std::string& w : model.warnings) std::cout << "warning: " << w << "\n";
      exitCode = kOk;
      return;
    }
    RunOptions o;
    o.scenePath = args->scene;
    if (!args->resume.empty() && !args->out.empty() &&
        std::filesystem::weakly_canonical(args->resume) != std::filesystem::weakly_canonical(args->out))
      throw InputError("--resume " + args->resume + " and --out " + args->out + ": a resumed run writes into its own directory");
    o.outputDirectory = !args->resume.empty() ? args->resume
                        : args->out.empty()
                            ? (std::filesystem::path("out") / std::filesystem::path(args->scene).stem()).string()
                            : args->out;
    o.checkpointEvery = args->checkpointEvery;
    o.resume = !args->resume.empty();
    o.sceneFingerprint = fingerprint(sceneText);
    o.stepLimit = args->steps;
    o.pictures = !args->noPictures;
    o.log = args->quiet ? nullptr : &std::cerr;
    o.progressBar = !args->quiet && Progress::isTerminal(STDERR_FILENO);
    installInterruptHandler();
    RunResult r;
    try {
      r = runScene(scene, o);
    } catch (...) {
      removeInterruptHandler();
      throw;
    }
    removeInterruptHandler();
    const RunSummary& s = r.summary;
    // Steps accepted at the iteration cap are the scene's choice (solver.acceptIterationCap): the run completed
    // and says how many did not converge; anything else unconverged fails.
    const bool movedOn = s.termination == "completed_with_unconverged_steps";
    const char* outcome = r.interrupted           ? "interrupted"
                          : s.converged           ? "done"
                          : movedOn               ? "done, not every step converged"
                          : r.stepLimitReached    ? "stopped"
                                                  : "not converged";
    std::cout << outcome << ": " << s.termination
              << " after " << s.steps << " steps, " << s.newtonIterations << " Newton iterations, "
              << Progress::formatDuration(s.wallSeconds) << "\n";
    for (const std::string& note : r.notes) std::cout << "note: " << note << "\n";
    for (const std::string& warning : r.warnings) std::cout << "warning: " << warning << "\n";
    const std::filesystem::path dir = o.outputDirectory;
    std::cout << "outputs in " << dir.string() << "/: summary.json";
    if (scene.outputs.vtu) std::cout << ", frames.pvd (ParaView)";
    if (scene.outputs.probesCsv) std::cout << ", probes.csv";
    if (scene.outputs.obj) std::cout << ", obj/";
    std::cout << "\n";
    if (!r.finalPng.empty()) std::cout << "picture: " << r.finalPng << "\n";
    if (!r.probesPng.empty()) std::cout << "plot: " << r.probesPng << "\n";
    if (!r.contactForcesPng.empty()) std::cout << "plot: " << r.contactForcesPng << "\n";
    exitCode = r.interrupted ? kInterrupted : (s.converged || movedOn || r.stepLimitReached) ? kOk : kFailed;
  });
});

}  // namespace
}  // namespace jetshell::cli
