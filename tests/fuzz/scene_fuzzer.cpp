// libFuzzer harness: any bytes as a scene file, read and resolved onto its unknowns (nothing is solved). Only
// InputError may come out; anything else (a crash, a sanitizer report, another exception, a hang, memory beyond
// libFuzzer's -rss_limit_mb) is a defect. Mesh paths resolve against a directory that does not exist.
#include "core/input_limits.h"
#include "core/mesh.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace jetshell;
  // Smaller meshes than the program allows keep every input cheap (the bounds themselves are what is tested:
  // a generator beyond them must be rejected before it allocates).
  static const bool lowered = [] {
    inputLimits().maxVertices = 20000;
    inputLimits().maxFaces = 40000;
    return true;
  }();
  (void)lowered;
  try {
    const nlohmann::json document = json::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    buildSceneModel(sceneFromJson(document, "/nonexistent/fuzz"));
  } catch (const InputError&) {
  }
  return 0;
}
