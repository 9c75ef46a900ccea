#include "core/mesh_generators.h"
#include "tools/output/atomic_file.h"
#include "tools/output/interrupt.h"
#include "tools/output/progress.h"
#include "tools/output/vtu.h"
#include "tools/render/image.h"
#include "tools/render/plot.h"
#include "tools/render/render_frames.h"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "jetshell_output_tests";
  fs::create_directories(dir);
  return dir / name;
}

VtuFrame hemisphereFrame() {
  const TriMesh m = makeHemisphere(1.0, 6, 16);
  VtuFrame f;
  f.points = m.V;
  f.triangles = m.F;
  VtuFrame::Array& u = f.pointData["displacement"];
  u.components = 3;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) u.values.insert(u.values.end(), {0.0, 0.0, 0.1 * m.V(v, 2) + 1.0 / 3.0});
  f.cellData["actor"].values.assign(static_cast<std::size_t>(m.F.rows()), 0.0);
  return f;
}

}  // namespace

TEST_CASE("output: a .vtu frame reads back exactly") {
  const VtuFrame a = hemisphereFrame();
  const std::string path = scratch("roundtrip.vtu").string();
  writeFileAtomically(path, [&](std::ostream& out) { writeVtu(out, a); });
  const VtuFrame b = readVtu(path);
  CHECK(b.points == a.points);
  CHECK(b.triangles == a.triangles);
  REQUIRE(b.pointData.count("displacement") == 1);
  CHECK(b.pointData.at("displacement").components == 3);
  CHECK(b.pointData.at("displacement").values == a.pointData.at("displacement").values);
  CHECK(b.cellData.at("actor").values.size() == static_cast<std::size_t>(a.triangles.rows()));
  CHECK(!fs::exists(path + ".tmp" + std::to_string(::getpid())));
}

TEST_CASE("output: shortest round-trip numbers") {
  CHECK(formatDouble(0.1) == "0.1");
  CHECK(formatDouble(1.0 / 3.0) == "0.3333333333333333");
  CHECK(std::stod(formatDouble(1e-300 / 3)) == 1e-300 / 3);
}

TEST_CASE("output: broken .vtu files are named") {
  const std::string path = scratch("broken.vtu").string();
  writeFileAtomically(path, "<VTKFile type=\"PolyData\"></VTKFile>");
  CHECK_THROWS_WITH(readVtu(path), path + ": not a VTK XML UnstructuredGrid (.vtu) file");
  CHECK_THROWS_WITH(readVtu(scratch("none.vtu").string()), scratch("none.vtu").string() + ": cannot open");
}

TEST_CASE("output: the .pvd series lists every frame with its time") {
  PvdSeries s;
  s.add(0.0, "frames/frame_00000.vtu");
  s.add(0.5, "frames/frame_00001.vtu");
  s.add(0.5, "volumes.vtu", 1);
  const std::string path = scratch("series.pvd").string();
  s.write(path);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  CHECK(text.str().find("<DataSet timestep=\"0.5\" group=\"\" part=\"1\" file=\"volumes.vtu\"/>") != std::string::npos);
  CHECK(text.str().find("type=\"Collection\"") != std::string::npos);
}

TEST_CASE("output: an atomic write to a missing directory fails with the path") {
  CHECK_THROWS_WITH(writeFileAtomically("/nonexistent/dir/f.txt", "x"),
                    Catch::StartsWith("/nonexistent/dir/f.txt: cannot write"));
}

TEST_CASE("output: the interrupt flag is set by a request and cleared on install") {
  installInterruptHandler();
  CHECK(!interruptRequested());
  requestInterrupt();
  CHECK(interruptRequested());
  removeInterruptHandler();
  CHECK(!interruptRequested());
}

TEST_CASE("output: progress prints plain lines when not on a terminal") {
  std::ostringstream out;
  Progress p(out, false);
  p.update(0.5, "step 5");
  p.log("step 5: ok");
  p.finish();
  CHECK(out.str() == "step 5: ok\n");
  CHECK(Progress::formatDuration(125) == "2 min 05 s");
  CHECK(Progress::formatDuration(3.25) == "3.2 s");
}

TEST_CASE("render: a frame becomes a PNG with the mesh in the middle") {
  const std::string vtu = scratch("render.vtu").string(), png = scratch("render.png").string();
  const VtuFrame f = hemisphereFrame();
  writeFileAtomically(vtu, [&](std::ostream& out) { writeVtu(out, f); });
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.supersample = 2;
  const std::string note = renderVtuFiles({vtu}, "displacement", o, png);
  CHECK(note.rfind("colour: |displacement| from 0.3333 to 0.4333", 0) == 0);
  int w = 0, h = 0;
  const std::vector<std::uint8_t> rgb = readPngRgb(png, w, h);
  REQUIRE(w == 160);
  REQUIRE(h == 120);
  auto pixel = [&](int x, int y) {
    const std::size_t k = 3 * (static_cast<std::size_t>(y) * w + x);
    return std::array<int, 3>{rgb[k], rgb[k + 1], rgb[k + 2]};
  };
  // The corner is background (grey: r ≈ g ≈ b); the centre is the coloured shell (viridis: not grey).
  const auto corner = pixel(2, 2), centre = pixel(80, 60);
  CHECK(std::abs(corner[0] - corner[1]) < 8);
  CHECK(std::abs(centre[0] - centre[1]) + std::abs(centre[1] - centre[2]) > 30);
  CHECK_THROWS_WITH(renderVtuFiles({vtu}, "velocity", o, png),
                    vtu + ": no point array 'velocity' to colour by (known: displacement)");
}

