// `jetshell render`: a shaded PNG of an output frame (.vtu), of the last frame (or frame K) of a series (.pvd), or
// of a run's output directory.
#include "core/input_limits.h"
#include "core/mesh.h"
#include "tools/output/vtu.h"
#include "tools/render/render_frames.h"
#include "tools/subcommand.h"

#include <filesystem>
#include <iostream>

namespace jetshell::cli {
namespace {

/// The .vtu files to draw: each series (a .pvd, or a run's output directory) gives the files of its frame
/// `frame` (kLastFrame: its last), each .vtu itself. A frame asked of inputs that hold no series is refused.
std::vector<std::string> resolveInputs(const std::vector<std::string>& inputs, long frame) {
  std::vector<std::string> files;
  bool series = false;
  for (const std::string& input : inputs) {
    std::string path = input;
    if (std::filesystem::is_directory(path)) path = (std::filesystem::path(path) / "frames.pvd").string();
    if (std::filesystem::path(path).extension() == ".pvd") {
      series = true;
      for (const std::string& f : readPvdFrame(path, frame)) files.push_back(f);
    } else {
      files.push_back(path);
    }
  }
  if (frame != kLastFrame && !series)
    throw CLI::ValidationError("--frame", "applies to a series (.pvd) or a run's output directory; none was given");
  return files;
}

Eigen::Vector3d axisFromName(const std::string& name) {
  const bool negative = !name.empty() && name[0] == '-';
  const char axis = name.empty() ? 'z' : name.back();
  Eigen::Vector3d up = axis == 'x' ? Eigen::Vector3d::UnitX() : axis == 'y' ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  return negative ? Eigen::Vector3d(-up) : up;
}

const RegisterSubcommand registerRender("render", [](CLI::App& app, int& exitCode) {
  struct Args {
    std::vector<std::string> inputs;
    std::string png;
    std::string color = "displacement";
    std::string up = "z";
    std::string edges = "auto";
    std::vector<double> range;
    long frame = kLastFrame;
    RenderOptions options;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("render", "Draw an output frame as a shaded PNG (software rasterizer)");
  cmd->add_option("frames", args->inputs,
                  "A frame (.vtu), a series (.pvd: its last step, or --frame) or a run's output directory; more .vtu "
                  "files (e.g. volumes.vtu) are drawn in grey")
      ->required();
  cmd->add_option("--png", args->png, "Output PNG file")->required()->check(outputFile());
  cmd->add_option("--frame", args->frame,
                  "With a series (.pvd) or a run's output directory: draw its frame K (0 = the first, numbered as "
                  "frames/frame_K.vtu) with the moving volumes of that frame, instead of the last")
      ->check(CLI::Range(0L, static_cast<long>(inputLimits().maxSteps)));
  cmd->add_option("--width", args->options.width, "Image width in pixels")
      ->check(CLI::Range(kMinImageSize, kMaxImageSize))
      ->capture_default_str();
  cmd->add_option("--height", args->options.height, "Image height in pixels")
      ->check(CLI::Range(kMinImageSize, kMaxImageSize))
      ->capture_default_str();
  cmd->add_option("--azimuth", args->options.azimuthDegrees, "Camera angle around the up axis, degrees")
      ->check(finiteRange(-360.0, 360.0))
      ->capture_default_str();
  cmd->add_option("--elevation", args->options.elevationDegrees, "Camera angle above the horizon, degrees")
      ->check(finiteRange(-90.0, 90.0))
      ->capture_default_str();
  cmd->add_option("--up", args->up, "Up axis")->check(CLI::IsMember({"x", "y", "z", "-x", "-y", "-z"}))->capture_default_str();
  cmd->add_option("--color", args->color, "Point array whose magnitude colours the first frame, or 'none'")->capture_default_str();
  cmd->add_option("--range", args->range, "Colour range: MIN MAX (default: the data's range)")
      ->expected(2)
      ->check(finiteRange(-1e300, 1e300));
  cmd->add_option("--edges", args->edges, "Draw mesh edges")->check(CLI::IsMember({"auto", "on", "off"}))->capture_default_str();
  cmd->add_option("--supersample", args->options.supersample, "Samples per pixel along each axis")
      ->check(CLI::Range(1, kMaxSupersample))->capture_default_str();
  cmd->callback([args, &exitCode] {
    RenderOptions o = args->options;
    const long long samples = static_cast<long long>(o.width) * o.height * o.supersample * o.supersample;
    if (samples > kMaxImageSamples)
      throw CLI::ValidationError("--supersample", "width x height x supersample^2 = " + std::to_string(samples) +
                                                      " samples, too many (at most " +
                                                      std::to_string(kMaxImageSamples) + ")");
    o.up = axisFromName(args->up);
    o.edges = args->edges == "on" ? RenderOptions::Edges::On : args->edges == "off" ? RenderOptions::Edges::Off : RenderOptions::Edges::Auto;
    if (args->range.size() == 2) {
      if (!(args->range[0] < args->range[1]))
        throw CLI::ValidationError("--range", "MIN must be below MAX (got " + std::to_string(args->range[0]) + " " +
                                                  std::to_string(args->range[1]) + ")");
      o.scalarMin = args->range[0], o.scalarMax = args->range[1];
    }
    const std::vector<std::string> files = resolveInputs(args->inputs, args->frame);
    const std::string note = renderVtuFiles(files, args->color, o, args->png);
    std::cout << "wrote " << args->png << " (" << o.width << "x" << o.height << ", " << files.size() << " file"
              << (files.size() > 1 ? "s" : "") << ")\n";
    if (!note.empty()) std::cout << note << "\n";
    exitCode = kOk;
  });
});

}  // namespace
}  // namespace jetshell::cli
