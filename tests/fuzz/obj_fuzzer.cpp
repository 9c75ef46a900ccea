// libFuzzer harness: any bytes as an OBJ file. Only InputError may come out; anything else (a crash, a
// sanitizer report, another exception, a hang, memory beyond libFuzzer's -rss_limit_mb) is a defect.
#include "core/input_limits.h"
#include "core/mesh_io.h"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace jetshell;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    parseObj(in, "fuzz.obj");
  } catch (const InputError&) {
  }
  return 0;
}
