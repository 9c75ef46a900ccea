// Contact samples too sparse for what they must catch (tools/scene/contact_coverage.h): a point cloud whose
// samples leave gaps another layer fits through, and a thin solid that fits between a shell's samples. The
// 8 × 8 cloth below let a rod of radius 1 cm lying between two columns of vertices through untouched. At most 20
// warnings are listed, the rest counted (a scene may hold 100,000 pairs).
#include "tools/scene/contact_coverage.h"
#include "core/mesh.h"
#include "energies/contact/sdf_grid.h"
#include "tools/scene/scene_json.h"
#include "tools/scene/scene_model.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace jetshell;
using Json = nlohmann::json;

namespace {

/// A 1 m cloth of n × n quads (mean edge 1.13/n m) falling onto `volume`.
Json clothOver(int n, const Json& volume) {
  Json cloth = {{"type", "shell"},
                {"name", "cloth"},
                {"shape", {{"generator", "rectangle"}, {"width", 1.0}, {"height", 1.0}, {"nx", n}, {"ny", n}}},
                {"material",
                 {{"youngsModulus", 1e5}, {"poissonRatio", 0.25}, {"thickness", 0.002}, {"volumeDensity", 1000}}},
                {"colliderType", "None"}};
  return {{"actors", {cloth, volume}}, {"analysis", {{"type", "dynamic"}, {"timeStep", 0.01}, {"duration", 0.1}}}};
}

const Json kRod = {{"type", "capsule"}, {"name", "rod"}, {"center", {0.5, 0.5, -0.1}}, {"radius", 0.01},
                   {"halfLength", 0.6}, {"rotation", {{"axis", {1, 0, 0}}, {"degrees", 90}}}};

std::vector<std::string> warningsOf(const Json& j, const std::string& directory = ".") {
  const Scene scene = sceneFromJson(j, directory);
  const SceneModel model = buildSceneModel(scene);
  CHECK(contactCoverageWarnings(scene, model.actors) == model.warnings);
  return model.warnings;
}

}  // namespace

TEST_CASE("contact coverage: a thin solid between a coarse shell's samples is named, not a fine mesh or a thick solid",
          "[contact]") {
  // 8 × 8: mean edge 0.141 m, a face's middle 0.0814 m from its corners, beyond the rod's 1 cm + 5 mm.
  const std::vector<std::string> coarse = warningsOf(clothOver(8, kRod));
  REQUIRE(coarse.size() == 1);
  CHECK(coarse[0] == "volume actor 'rod' (thinnest half-width 0.01 m) fits between the contact samples of shell "
                     "actor 'cloth' (at its vertices or face centroids, about 0.0814 m from a face's middle, "
                     "beyond its reach of 0.015 m): it can pass through the shell unfelt "
                     "(\"contactElementType\": \"FaceThreePoint\" or a finer mesh closes the gap)");
  Json threePoint = clothOver(8, kRod);
  threePoint["actors"][0]["contactElementType"] = "FaceThreePoint";
  const std::vector<std::string> three = warningsOf(threePoint);
  REQUIRE(three.size() == 1);
  CHECK_THAT(three[0], Catch::Contains("(three points a face, about 0.0407 m") &&
                           Catch::EndsWith("(a finer mesh closes the gap)"));
  // 64 × 64: a face's middle 0.0102 m from its corners, within reach. A ball of 10 cm under the coarse cloth and a
  // floor are not thin.
  CHECK(warningsOf(clothOver(64, kRod)).empty());
  CHECK(warningsOf(clothOver(8, {{"type", "sphere"}, {"center", {0.5, 0.5, -0.2}}, {"radius", 0.1}})).empty());
  CHECK(warningsOf(clothOver(8, {{"type", "plane"}})).empty());
}

TEST_CASE("contact coverage: point-cloud samples too small for their mesh leave gaps, and say what closes them",
          "[contact]") {
  Json j = clothOver(8, {{"type", "plane"}});
  j["actors"][0]["colliderType"] = "PointCloud";
  j["actors"][0]["pointCloudCollider"] = {{"radius", 0.02}, {"selfContact", true}};
  const std::vector<std::string> w = warningsOf(j);
  REQUIRE(w.size() == 1);
  CHECK(w[0] == "shell actor 'cloth': point-cloud samples of radius 0.02 m at vertices a mean edge of 0.141 m apart "
                "leave a gap 0.0814 m from the corners in the middle of a face, which a sample of radius 0.02 m passes "
                "through untouched (radii that add up to 0.0814 m, or a finer mesh, close it)");
  // Radii of 5 cm close it; without self-contact a single cloud meets no other.
  j["actors"][0]["pointCloudCollider"]["radius"] = 0.05;
  CHECK(warningsOf(j).empty());
  j["actors"][0]["pointCloudCollider"] = {{"radius", 0.02}, {"selfContact", false}};
  CHECK(warningsOf(j).empty());
}

TEST_CASE("contact coverage: the warnings of many pairs are bounded, the rest counted", "[contact]") {
  Json j = clothOver(8, kRod);
  for (int k = 1; k < 30; ++k) {
    Json rod = kRod;
    rod["name"] = "rod" + std::to_string(k);
    j["actors"].push_back(rod);
  }
  const std::vector<std::string> w = warningsOf(j);
  REQUIRE(w.size() == 21);
  CHECK_THAT(w[19], Catch::StartsWith("volume actor 'rod19' "));
  CHECK(w[20] == "and 10 more contact pairs whose samples are as sparse");
}

namespace {

/// An SDF grid file of a rod of `radius` along x, 1.2 m long, sampled every `spacing` m with its axis on the
/// samples (so its deepest sample is `radius` inside).
std::string sampledRod(const std::string& name, double radius, double spacing) {
  const std::filesystem::path file = test::scratchDirectory("coverage_sdf") / name;
  const int nx = static_cast<int>(std::lround(1.2 / spacing)) + 1;
  const int half = static_cast<int>(std::ceil(2.0 * radius / spacing)), n = 2 * half + 1;
  std::ofstream out(file);
  out << "dims " << nx << ' ' << n << ' ' << n << "\norigin -0.6 " << -half * spacing << ' ' << -half * spacing
      << "\nspacing " << spacing << "\n";
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x = -0.6 + i * spacing, y = (j - half) * spacing, z = (k - half) * spacing;
        const double beyond = std::max(0.0, std::abs(x) - 0.5);  // the capsule's segment: |x| <= 0.5
        out << std::sqrt(beyond * beyond + y * y + z * z) - radius << (i + 1 < nx ? ' ' : '\n');
      }
  return file.filename().string();
}

/// The signed distance of the box of half extents `b` centred at `c`.
double boxDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& c, const Eigen::Vector3d& b) {
  const Eigen::Vector3d q = (p - c).cwiseAbs() - b;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// An SDF grid file of a 20 cm cube at the origin and, with `fin`, a plate 2 cm thick along y standing out of its
/// +x face to x = 0.45 m (the union's distance is the smaller of the two), sampled every 1 cm.
std::string sampledBlock(const std::string& name, bool fin) {
  const std::filesystem::path file = test::scratchDirectory("coverage_sdf") / name;
  const double h = 0.01;
  const int nx = 61, n = 31;  // x in [-0.15, 0.45], y and z in [-0.15, 0.15]
  std::ofstream out(file);
  out << "dims " << nx << ' ' << n << ' ' << n << "\norigin -0.15 -0.15 -0.15\nspacing " << h << "\n";
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < nx; ++i) {
        const Eigen::Vector3d p(-0.15 + i * h, -0.15 + j * h, -0.15 + k * h);
        double d = boxDistance(p, Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.1));
        if (fin) d = std::min(d, boxDistance(p, {0.275, 0.0, 0.0}, {0.175, 0.01, 0.1}));
        out << d << (i + 1 < nx ? ' ' : '\n');
      }
  return file.filename().string();
}

}  // namespace

TEST_CASE("contact coverage: an SDF grid thin everywhere between a coarse shell's samples is named, a thick one not",
          "[contact]") {
  const std::string directory = test::scratchDirectory("coverage_sdf").string();
  // A rod of radius 1 cm sampled every 5 mm: no point lies more than 0.01 + 0.0043 m inside it, within the 8 × 8
  // cloth's gap of 0.0814 m with the 5 mm activation distance.
  const Json rod = {{"type", "sdfGrid"}, {"name", "rod"}, {"file", sampledRod("rod.sdf", 0.01, 0.005)},
                    {"center", {0.5, 0.5, -0.1}}};
  const std::vector<std::string> coarse = warningsOf(clothOver(8, rod), directory);
  REQUIRE(coarse.size() == 1);
  CHECK(coarse[0] == "volume actor 'rod' (an SDF grid, thinnest half-width at most 0.0143 m) fits between the "
                     "contact samples of shell actor 'cloth' (at its vertices or face centroids, about 0.0814 m from "
                     "a face's middle, beyond its reach of 0.0193 m): it can pass through the shell unfelt "
                     "(\"contactElementType\": \"FaceThreePoint\" or a finer mesh closes the gap)");
  // The analytic capsule of the same radius is named alike; the fine cloth closes the gap; a rod of 10 cm is
  // thicker than the coarse cloth's gap.
  CHECK(warningsOf(clothOver(8, kRod)).size() == 1);
  CHECK(warningsOf(clothOver(64, rod), directory).empty());
  const Json thick = {{"type", "sdfGrid"}, {"name", "log"}, {"file", sampledRod("log.sdf", 0.1, 0.02)},
                      {"center", {0.5, 0.5, -0.2}}};
  CHECK(warningsOf(clothOver(8, thick), directory).empty());
}

TEST_CASE("contact coverage: a thin part of a thick SDF grid is named, the thick solid alone not", "[contact]") {
  const std::string directory = test::scratchDirectory("coverage_sdf").string();
  // The cube's centre lies 10 cm inside, beyond the 8 × 8 cloth's gap; the fin's middle 1 cm, on the samples: its
  // ridge gives 0.01 m plus half a cell's diagonal, 0.0187 m.
  const auto block = [&](bool fin) {
    return Json{{"type", "sdfGrid"}, {"name", "block"}, {"file", sampledBlock(fin ? "fin.sdf" : "cube.sdf", fin)},
                {"center", {0.5, 0.5, -0.2}}};
  };
  const std::vector<std::string> finned = warningsOf(clothOver(8, block(true)), directory);
  REQUIRE(finned.size() == 1);
  CHECK_THAT(finned[0], Catch::StartsWith("volume actor 'block' (an SDF grid, thinnest half-width at most 0.0187 m) "
                                          "fits between the contact samples of shell actor 'cloth'"));
  CHECK(warningsOf(clothOver(8, block(false)), directory).empty());
  // The bound itself: the cube's centre sample, 0.1 m deep, plus half a cell's diagonal.
  SdfGrid cube;
  cube.nx = cube.ny = cube.nz = 21;
  cube.spacing = 0.01;
  for (int k = 0; k < 21; ++k)
    for (int j = 0; j < 21; ++j)
      for (int i = 0; i < 21; ++i)
        cube.values.push_back(boxDistance(0.01 * Eigen::Vector3d(i, j, k), Eigen::Vector3d::Constant(0.1),
                                          Eigen::Vector3d::Constant(0.1)));
  CHECK(sdfGridThinnestHalfWidth(cube) == Approx(0.1 + 0.005 * std::sqrt(3.0)));
  cube.values.pop_back();  // a grid whose values do not fill its dims is refused, not read past its end
  CHECK_THROWS_AS(sdfGridThinnestHalfWidth(cube), InputError);
}
