// Pictures of output frames: .vtu files to a shaded PNG (used by `jetshell render` and by `jetshell run` for
// its final.png).
#pragma once

#include "tools/render/rasterizer.h"

#include <string>
#include <vector>

namespace jetshell {

/// Renders the .vtu files into one PNG. Every file with the point array `colorBy` (the first one must have it;
/// each shell actor's frame does) is coloured by its magnitude on one shared scale ("" or "none": flat
/// two-sided colours); the others (e.g. volumes.vtu) are drawn in grey.
/// Returns a one-line description of the colour scale ("colour: |displacement| from 0 to 0.123 m") or "".
/// Throws InputError for unreadable files or an unknown array name (listing the known ones).
std::string renderVtuFiles(const std::vector<std::string>& vtuFiles, const std::string& colorBy,
                           const RenderOptions& options, const std::string& pngPath);

}  // namespace jetshell
