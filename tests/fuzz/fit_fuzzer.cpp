// libFuzzer harness: any bytes as a fit file, read and its scene resolved onto its unknowns (nothing is solved or
// fitted), and the same bytes as a curve observation's CSV text. Only InputError may come out; anything else (a
// crash, a sanitizer report, another exception, a hang, memory beyond libFuzzer's -rss_limit_mb) is a defect.
// Paths (scene, target shapes, CSV curves) resolve against a directory that does not exist.
#include "core/mesh.h"
#include "tests/fuzz/lowered_limits.h"
#include "tools/fit/fit_file.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/scene_model.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace jetshell;
  fuzz::lowerMeshLimits();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    ObservationSpec curve;
    readCurveRows(text, "fuzz.csv", 0, 1, 2, 1e-3, curve);
  } catch (const InputError&) {
  }
  try {
    const nlohmann::json document = json::parse(text, "fuzz.json");
    const FitFile f = fitFromJson(document, "/nonexistent/fuzz", "fuzz.json");
    buildSceneModel(f.scene);
  } catch (const InputError&) {
  }
  return 0;
}
