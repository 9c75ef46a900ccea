#include "tools/render/render_frames.h"

#include "tools/output/vtu.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace jetshell {

std::string renderVtuFiles(const std::vector<std::string>& vtuFiles, const std::string& colorBy,
                           const RenderOptions& options, const std::string& pngPath) {
  if (vtuFiles.empty()) throw InputError("render: no input frame");
  std::vector<RenderMesh> meshes;
  std::string note;
  for (std::size_t k = 0; k < vtuFiles.size(); ++k) {
    const VtuFrame frame = readVtu(vtuFiles[k]);
    RenderMesh m;
    m.V = frame.points;
    m.F = frame.triangles;
    if (k == 0 && !colorBy.empty() && colorBy != "none") {
      const auto it = frame.pointData.find(colorBy);
      if (it == frame.pointData.end()) {
        std::string known;
        for (const auto& a : frame.pointData) known += (known.empty() ? "" : ", ") + a.first;
        throw InputError(vtuFiles[k] + ": no point array '" + colorBy + "' to colour by" +
                         (known.empty() ? " (the file has none; use --color none)" : " (known: " + known + ")"));
      }
      const VtuFrame::Array& a = it->second;
      m.scalar.resize(static_cast<std::size_t>(m.V.rows()));
      for (std::size_t v = 0; v < m.scalar.size(); ++v) {
        double sum = 0;
        for (int c = 0; c < a.components; ++c) sum += a.values[v * static_cast<std::size_t>(a.components) + c] * a.values[v * static_cast<std::size_t>(a.components) + c];
        m.scalar[v] = std::sqrt(sum);
      }
      double lo = options.scalarMin, hi = options.scalarMax;
      if (hi < lo) {
        lo = *std::min_element(m.scalar.begin(), m.scalar.end());
        hi = *std::max_element(m.scalar.begin(), m.scalar.end());
      }
      char buffer[160];
      std::snprintf(buffer, sizeof buffer, "colour: |%s| from %.4g to %.4g (viridis: dark purple = low, yellow = high)",
                    colorBy.c_str(), lo, hi);
      note = buffer;
    }
    if (k > 0) m.front = m.back = {0.55f, 0.55f, 0.55f};
    meshes.push_back(std::move(m));
  }
  writePng(pngPath, renderMeshes(meshes, options));
  return note;
}

}  // namespace jetshell
