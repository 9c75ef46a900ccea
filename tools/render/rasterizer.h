// A small software rasterizer for looking at shells: perspective camera that frames everything, z-buffer,
// two-sided Lambert + headlight shading with smooth normals, optional colouring by a per-vertex scalar
// (viridis), optional mesh edges, supersampled for smooth edges.
#pragma once

#include "core/mesh.h"
#include "tools/render/image.h"

#include <Eigen/Core>

#include <vector>

namespace jetshell {

struct RenderMesh {
  Positions V;
  Faces F;
  std::vector<double> scalar;          // per vertex, or empty for the flat colours below
  Rgb front{0.30f, 0.45f, 0.75f};      // linear RGB of the side the normals point to
  Rgb back{0.80f, 0.45f, 0.20f};       // and of the other side
};

/// Image sizes renderMeshes accepts, and the most samples (width × height × supersample²) it draws: each costs
/// about 16 bytes, so 2^26 of them about 1 GB.
constexpr int kMinImageSize = 16, kMaxImageSize = 8192, kMaxSupersample = 8;
constexpr long long kMaxImageSamples = 1LL << 26;

struct RenderOptions {
  int width = 1200, height = 900;
  int supersample = 3;                 // rendered at supersample × size, then box-filtered
  double azimuthDegrees = 35.0;        // around the up axis; 0 looks from the "front"
  double elevationDegrees = 25.0;      // above the horizon
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fieldOfViewDegrees = 30.0;
  enum class Edges { Auto, On, Off } edges = Edges::Auto;  // Auto: on when triangles are large on screen
  double scalarMin = 0.0, scalarMax = -1.0;                // colour range; max < min: the data's range
};

/// Renders the meshes from a camera placed by the options that frames all of them. Throws InputError when
/// there is nothing to draw or the size is unusable.
Image renderMeshes(const std::vector<RenderMesh>& meshes, const RenderOptions& options);

/// The viridis colour map (linear RGB) at s in [0, 1].
Rgb viridis(double s);

}  // namespace jetshell
