// libFuzzer harness: any bytes as a scene file, read and resolved onto its unknowns (nothing is solved). Only
// InputError may come out; anything else (a crash, a sanitizer report, another exception, a hang, memory beyond
// libFuzzer's -rss_limit_mb) is a defect. Mesh paths resolve against a directory that does not exist.
#include "core/mesh.h"
#include "tests/fuzz/lowered_limits.h"
#include "tools/scene/json_reader.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace jetshell;
  fuzz::lowerMeshLimits();
  try {
    const nlohmann::json document = json::parse(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    buildSceneModel(sceneFromJson(document, "/nonexistent/fuzz"));
  } catch (const InputError&) {
  }
  return 0;
}
