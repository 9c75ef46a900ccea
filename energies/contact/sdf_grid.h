// A signed distance sampled on a regular grid, read from a text file, as a volume shape.
//
// File format (whitespace separated; lines starting with '#' are comments):
//   dims nx ny nz          2 <= n_i, nx·ny·nz <= 16,777,216
//   origin ox oy oz        local position of sample (0,0,0) [m]
//   spacing h              grid spacing [m], > 0
//   then nx·ny·nz finite distances [m], x fastest, then y, then z (negative inside the solid).
// Inside the grid the distance is trilinear (its gradient and Hessian are those of the trilinear cell, so the
// Hessian has no diagonal); outside, the distance at the nearest grid point plus the distance to it.
// Errors name the file and line (InputError).
#pragma once

#include "energies/contact/volume_shapes.h"

#include <Eigen/Geometry>

#include <istream>
#include <string>
#include <vector>

namespace jetshell {

struct SdfGrid {
  int nx = 0, ny = 0, nz = 0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double spacing = 1.0;
  std::vector<double> values;  // x fastest
};

/// Reads a grid file (a regular file of at most inputLimits().maxSdfBytes); throws InputError "<path>:<line>: ..."
/// for malformed or out-of-bounds content.
SdfGrid readSdfGrid(const std::string& path);
/// The same from a stream, `name` standing for the path in messages.
SdfGrid parseSdfGrid(std::istream& in, const std::string& name);
/// The grid as a shape (validated: sizes and finite values).
VolumeShapePtr makeSdfGridShape(SdfGrid grid);
/// The box the grid's samples span, in its local coordinates.
Eigen::AlignedBox3d sdfGridBox(const SdfGrid& grid);
/// A bound on the half-width of the solid's thinnest part that the grid resolves: the smaller of the largest depth
/// (the deepest sample's depth plus half a cell's diagonal: no point lies deeper) and, over the samples inside the
/// solid and inside the grid whose depth is at least each of their 26 neighbours' (a ridge: the middle of a plate,
/// the axis of a rod, the centre of a ball), the least depth plus half a cell's diagonal. Half a diagonal is as far
/// as such a sample can lie from the middle of a plate or a rod (a neighbour nearer the middle would be deeper), so
/// the part there is no wider than that. A part that thickens along its length (a wedge, a neck) has no ridge of
/// its own and is not seen: the bound errs towards the wide.
/// Throws InputError for a grid whose dims and values disagree, as makeSdfGridShape does.
double sdfGridThinnestHalfWidth(const SdfGrid& grid);

}  // namespace jetshell
