#include "tools/render/render_frames.h"

#include "tools/output/vtu.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace jetshell {

std::string renderVtuFiles(const std::vector<std::string>& vtuFiles, const std::string& colorBy,
                           const RenderOptions& options, const std::string& pngPath) {
  if (vtuFiles.empty()) throw InputError("render: no input frame");
  const bool colour = !colorBy.empty() && colorBy != "none";
  std::vector<RenderMesh> meshes;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < vtuFiles.size(); ++k) {
    const VtuFrame frame = readVtu(vtuFiles[k]);
    RenderMesh m;
    m.V = frame.points;
    m.F = frame.triangles;
    const auto it = colour ? frame.pointData.find(colorBy) : frame.pointData.end();
    if (k == 0 && colour && it == frame.pointData.end()) {
      std::string known;
      for (const auto& a : frame.pointData) known += (known.empty() ? "" : ", ") + a.first;
      throw InputError(vtuFiles[k] + ": no point array '" + colorBy + "' to colour by" +
                       (known.empty() ? " (the file has none; use --color none)" : " (known: " + known + ")"));
    }
    if (it != frame.pointData.end()) {
      // Every file with the array (each shell actor's frame) is coloured on one shared scale.
      const VtuFrame::Array& a = it->second;
      m.scalar.resize(static_cast<std::size_t>(m.V.rows()));
      for (std::size_t v = 0; v < m.scalar.size(); ++v) {
        double sum = 0;
        for (int c = 0; c < a.components; ++c) {
          const double value = a.values[v * static_cast<std::size_t>(a.components) + c];
          sum += value * value;
        }
        m.scalar[v] = std::sqrt(sum);
        lo = std::min(lo, m.scalar[v]);
        hi = std::max(hi, m.scalar[v]);
      }
    } else if (k > 0) {
      m.front = m.back = {0.55f, 0.55f, 0.55f};  // volumes and files without the array: grey
    }
    meshes.push_back(std::move(m));
  }
  RenderOptions o = options;
  std::string note;
  if (colour) {
    if (o.scalarMax < o.scalarMin) {
      o.scalarMin = lo;
      o.scalarMax = hi;
    }
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "colour: |%s| from %.4g to %.4g (viridis: dark purple = low, yellow = high)",
                  colorBy.c_str(), o.scalarMin, o.scalarMax);
    note = buffer;
  }
  writePng(pngPath, renderMeshes(meshes, o));
  return note;
}

}  // namespace jetshell
