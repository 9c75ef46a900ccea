// libFuzzer harness: any bytes as a .vtu frame and as a .pvd collection (what `jetshell render` reads). A frame
// that parses has its triangles checked against its points. Only InputError may come out; anything else (a
// crash, a sanitizer report, another exception, a hang, memory beyond libFuzzer's -rss_limit_mb) is a defect.
#include "core/mesh.h"
#include "tools/output/vtu.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace jetshell;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const VtuFrame frame = parseVtu(text, "fuzz.vtu");
    for (Eigen::Index k = 0; k < frame.triangles.size(); ++k)
      if (frame.triangles.data()[k] < 0 || frame.triangles.data()[k] >= frame.points.rows()) std::abort();
  } catch (const InputError&) {
  }
  for (const long frame : {kLastFrame, 0L, 2L}) {
    try {
      for (const std::string& file : pvdFrame(text, "fuzz.pvd", frame))
        if (file.empty()) std::abort();
    } catch (const InputError&) {
    }
  }
  return 0;
}
