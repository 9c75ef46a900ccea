// VTK XML unstructured grids (.vtu, triangles only, ASCII) and ParaView collections (.pvd) of time series: the
// writers (vtu.cpp) and the readers (vtu_reader.cpp).
//
// ASCII with shortest round-trip numbers keeps frames lossless, diffable and readable by our own renderer;
// ParaView opens both the frames and the .pvd series.
#pragma once

#include "core/mesh.h"

#include <Eigen/Core>

#include <iosfwd>
#include <map>
#include <string>
#include <vector>

namespace jetshell {

/// A triangle mesh with named per-point and per-cell arrays. Point arrays have N·components values,
/// cell arrays F·components, both point- (cell-) major.
struct VtuFrame {
  Positions points;
  Faces triangles;
  struct Array {
    int components = 1;
    std::vector<double> values;
  };
  std::map<std::string, Array> pointData;
  std::map<std::string, Array> cellData;
};

/// Writes a VTK XML UnstructuredGrid file (version 1.0, ASCII). Arrays whose name is "displacement" or
/// "velocity" are marked as the active vectors.
void writeVtu(std::ostream& out, const VtuFrame& frame);

/// Reads an ASCII .vtu of triangles (as written by writeVtu or by ParaView with ASCII output). Throws
/// InputError naming the file on anything else (binary or appended data, non-triangle cells, missing arrays,
/// more than the scene limits' points or cells). tools/output/vtu_reader.cpp.
VtuFrame readVtu(const std::string& path);
/// The same from the file's text; `path` names it in messages.
VtuFrame parseVtu(const std::string& xml, const std::string& path);

/// The files of one time step of a .pvd collection's text, as written in it (relative to its directory): frame
/// k ≥ 0 is the k-th time step in the file's order (a run's frame k, frames/frame_k.vtu), kLastFrame the last.
/// InputError naming `path` when it has no <DataSet>, a <DataSet> of that step names no file, or it has no frame k.
constexpr long kLastFrame = -1;
std::vector<std::string> pvdFrame(const std::string& xml, const std::string& path, long frame = kLastFrame);
/// The same, read from the file at `path`, as paths (joined to its directory).
std::vector<std::string> readPvdFrame(const std::string& path, long frame = kLastFrame);

/// A .pvd collection: one entry per (time, part, file). File names are relative to the .pvd's directory.
class PvdSeries {
 public:
  /// name: the part's block name in ParaView (any text; escaped), or "" for none.
  void add(double time, const std::string& file, int part = 0, const std::string& name = "") {
    entries_.push_back({time, part, file, name});
  }
  /// Rewrites the whole collection atomically (so it is valid after every frame).
  void write(const std::string& path) const;
  std::size_t size() const { return entries_.size(); }

  /// The file's parts, for writers that append entries one by one (tools/output/append_file.h): the text before
  /// the first entry, one entry, and the closing text after the last.
  static std::string head();
  static std::string entry(double time, const std::string& file, int part = 0, const std::string& name = "");
  static std::string tail();

 private:
  struct Entry {
    double time;
    int part;
    std::string file;
    std::string name;
  };
  std::vector<Entry> entries_;
};

/// The shortest text that reads back as exactly v.
std::string formatDouble(double v);

}  // namespace jetshell
