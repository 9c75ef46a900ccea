#include "core/input_limits.h"
#include "core/mesh_generators.h"
#include "tools/output/append_file.h"
#include "tools/output/atomic_file.h"
#include "tools/output/interrupt.h"
#include "tools/output/progress.h"
#include "tools/output/run_output.h"
#include "tools/output/directories.h"
#include "tools/output/vtu.h"
#include "tools/render/image.h"
#include "tools/render/plot.h"
#include "tools/render/render_frames.h"
#include "tools/scene/scene_json.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = test::scratchDirectory("output_tests");
  fs::create_directories(dir);
  return dir / name;
}

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
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
  CHECK_THROWS_WITH(readVtu(scratch("none.vtu").string()), scratch("none.vtu").string() + ": cannot open frame file");
}

TEST_CASE("output: a .vtu with a non-finite number, a bad component count or a fractional index is refused") {
  std::ostringstream text;
  writeVtu(text, hemisphereFrame());
  const std::string good = text.str();
  // The file with the first token after `tag` replaced by `token` (or `token` put before it).
  auto edited = [&](const std::string& name, const std::string& tag, const std::string& token, bool replace) {
    std::string s = good;
    std::size_t at = s.find(tag);
    REQUIRE(at != std::string::npos);
    at = s.find_first_not_of(" \n", at + tag.size());
    const std::size_t end = replace ? s.find_first_of(" \n", at) : at;
    s.replace(at, end - at, replace ? token : token + " ");
    const std::string path = scratch(name).string();
    writeFileAtomically(path, s);
    return path;
  };
  const std::string nan = edited("nan.vtu", "Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">", "nan", true);
  CHECK_THROWS_WITH(readVtu(nan), nan + ": array 'Points' has a non-finite entry (NaN or inf)");
  const std::string inf = edited("inf.vtu", "Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">", "inf",
                                 true);
  CHECK_THROWS_WITH(readVtu(inf), inf + ": array 'displacement' has a non-finite entry (NaN or inf)");
  std::string components = good;
  components.replace(components.find("NumberOfComponents=\"3\""), 22, "NumberOfComponents=\"-5\"");
  const std::string negative = scratch("components.vtu").string();
  writeFileAtomically(negative, components);
  CHECK_THROWS_WITH(readVtu(negative),
                    negative + ": array 'displacement': NumberOfComponents=\"-5\" is not an integer from 1 to 9");
  // Read like the counts: digits alone (strtol took " 3" and "+3").
  components = good;
  components.replace(components.find("NumberOfComponents=\"3\""), 22, "NumberOfComponents=\"+3\"");
  const std::string signed3 = scratch("components_plus.vtu").string();
  writeFileAtomically(signed3, components);
  CHECK_THROWS_WITH(readVtu(signed3),
                    signed3 + ": array 'displacement': NumberOfComponents=\"+3\" is not an integer from 1 to 9");
  const std::string fraction = edited("fraction.vtu", "Name=\"connectivity\" format=\"ascii\">", "0.5", true);
  CHECK_THROWS_WITH(readVtu(fraction), fraction + ": connectivity entry 0 is not an integer");
}

TEST_CASE("output: a .vtu's point and cell counts are bounded integers, and so are its arrays' lengths") {
  std::ostringstream text;
  writeVtu(text, hemisphereFrame());
  // The frame with the values of the Piece's attributes replaced, written to scratch file `name`.
  auto withCounts = [&](const std::string& name, const std::string& points, const std::string& cells) {
    std::string s = text.str();
    for (const auto& [key, value] : {std::pair{"NumberOfPoints=\"", points}, std::pair{"NumberOfCells=\"", cells}}) {
      const std::size_t at = s.find(key) + std::strlen(key);
      s.replace(at, s.find('"', at) - at, value);
    }
    const std::string path = scratch(name).string();
    writeFileAtomically(path, s);
    return path;
  };
  const std::string maxPoints = std::to_string(inputLimits().maxVertices);
  const std::string maxCells = std::to_string(inputLimits().maxFaces);
  // 3 × this count overflowed a long before it was compared with the array's length.
  const std::string huge = withCounts("huge.vtu", "9223372036854775807", "1");
  CHECK_THROWS_WITH(readVtu(huge),
                    huge + ": NumberOfPoints=\"9223372036854775807\" is not an integer from 0 to " + maxPoints);
  const std::string negative = withCounts("negative.vtu", "1", "-3");
  CHECK_THROWS_WITH(readVtu(negative), negative + ": NumberOfCells=\"-3\" is not an integer from 0 to " + maxCells);
  const std::string word = withCounts("word.vtu", "12abc", "1");
  CHECK_THROWS_WITH(readVtu(word), word + ": NumberOfPoints=\"12abc\" is not an integer from 0 to " + maxPoints);
  // A frame of 1 point and 1 cell holds at most 9 numbers in any array: a longer one is refused as it is read.
  const std::string tooLong = withCounts("long.vtu", "1", "1");
  CHECK_THROWS_WITH(readVtu(tooLong), Catch::Contains("has more than 9 values (9 per point or cell at most)"));
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
  // Read back: the last time step's files, joined to the collection's directory.
  const fs::path directory = fs::path(path).parent_path();
  CHECK(readPvdFrame(path) == std::vector<std::string>{(directory / "frames/frame_00001.vtu").string(),
                                                          (directory / "volumes.vtu").string()});
}

TEST_CASE("output: a .pvd's last step is read with its names decoded, and an empty one is refused") {
  std::ostringstream text;
  text << PvdSeries::head() << PvdSeries::entry(0.0, "a&b.vtu") << PvdSeries::entry(1.0, "c\"d<.vtu", 0, "x & y")
       << PvdSeries::tail();
  CHECK(pvdFrame(text.str(), "s.pvd") == std::vector<std::string>{"c\"d<.vtu"});
  CHECK_THROWS_WITH(pvdFrame(PvdSeries::head() + PvdSeries::tail(), "s.pvd"), "s.pvd: no <DataSet> entries");
  CHECK_THROWS_WITH(pvdFrame("<DataSet timestep=\"0\" file=\"\"/>", "s.pvd"),
                    "s.pvd: a <DataSet> of the last time step names no file");
  // Entries without '>' were each copied to the end of the file: 200,000 of them took 24 s.
  const std::string entry = "<DataSet timestep=\"0\" file=\"x.vtu\"";
  std::string open;
  for (int k = 0; k < 200000; ++k) open += entry;
  CHECK_THROWS_WITH(pvdFrame(open, "s.pvd"),
                    "s.pvd: the tag at byte " + std::to_string(open.size() - entry.size()) + " has no closing '>'");
}

TEST_CASE("output: a .pvd's frame k is its k-th time step, and a frame it does not have is refused") {
  std::ostringstream text;
  text << PvdSeries::head() << PvdSeries::entry(0.0, "f0.vtu") << PvdSeries::entry(0.0, "v0.vtu", 1)
       << PvdSeries::entry(0.5, "f1.vtu") << PvdSeries::entry(0.5, "v1.vtu", 1) << PvdSeries::entry(1.0, "f2.vtu")
       << PvdSeries::tail();
  CHECK(pvdFrame(text.str(), "s.pvd", 0) == std::vector<std::string>{"f0.vtu", "v0.vtu"});
  CHECK(pvdFrame(text.str(), "s.pvd", 1) == std::vector<std::string>{"f1.vtu", "v1.vtu"});
  CHECK(pvdFrame(text.str(), "s.pvd", 2) == pvdFrame(text.str(), "s.pvd"));
  CHECK_THROWS_WITH(pvdFrame(text.str(), "s.pvd", 3), "s.pvd: no frame 3: the series has 3 frames (0 to 2)");
  CHECK_THROWS_WITH(pvdFrame("<DataSet timestep=\"0\" file=\"a.vtu\"/><DataSet timestep=\"1\" file=\"\"/>", "s.pvd", 1),
                    "s.pvd: a <DataSet> of the time step of frame 1 names no file");
}

TEST_CASE("output: a .vtu of many arrays is refused by count, and read in one pass") {
  // 200,000 empty arrays: each searched the file backwards for its section, which took minutes.
  std::string xml = "<VTKFile type=\"UnstructuredGrid\"><Piece NumberOfPoints=\"1\" NumberOfCells=\"1\">";
  for (int k = 0; k < 200000; ++k) xml += "<DataArray Name=\"a\" format=\"ascii\"></DataArray>";
  CHECK_THROWS_WITH(parseVtu(xml, "many.vtu"), "many.vtu: more than 1024 <DataArray> elements");
  CHECK_THROWS_WITH(parseVtu("<VTKFile type=\"UnstructuredGrid\"><Piece NumberOfPoints=\"1\"", "open.vtu"),
                    "open.vtu: the tag at byte 33 has no closing '>'");
}

TEST_CASE("output: an atomic write to a missing directory fails with the path") {
  CHECK_THROWS_WITH(writeFileAtomically("/nonexistent/dir/f.txt", "x"),
                    "/nonexistent/dir/f.txt: cannot write (no directory '/nonexistent/dir')");
  // The same checks, made before a command's work (--json, --png): an empty name, a missing directory.
  CHECK_THROWS_WITH(checkOutputFile(""), "an output file name must not be empty");
  CHECK_THROWS_WITH(checkOutputFile("/nonexistent/f.json"),
                    "/nonexistent/f.json: cannot write (no directory '/nonexistent')");
  CHECK_NOTHROW(checkOutputFile((test::scratchDirectory("atomic_file") / "new.json").string()));
}

TEST_CASE("output: a temporary directory is private, fresh and removed with its contents") {
  std::filesystem::path kept;
  {
    const TemporaryDirectory a("jetshell-test-"), b("jetshell-test-");
    CHECK(a.path() != b.path());
    struct stat info {};
    REQUIRE(::stat(a.path().c_str(), &info) == 0);
    CHECK(S_ISDIR(info.st_mode));
    CHECK((info.st_mode & 0777) == 0700);
    std::ofstream(a.path() / "f.txt") << "x";
    kept = a.path();
  }
  CHECK(!std::filesystem::exists(kept));
  CHECK_THROWS_WITH(createOutputDirectory("/dev/null/x", "--plots"),
                    Catch::StartsWith("--plots: /dev/null/x: cannot create the directory ("));
}

TEST_CASE("output: an atomic write replaces only a regular file") {
  const std::filesystem::path dir = test::scratchDirectory("atomic_file");
  std::filesystem::create_directories(dir);
  const std::string fifo = (dir / "fifo").string(), link = (dir / "link").string(), file = (dir / "f.txt").string();
  std::filesystem::remove(fifo);
  std::filesystem::remove(link);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::filesystem::create_symlink("f.txt", link);
  for (const std::string& target : {fifo, link, dir.string()}) {
    CHECK_THROWS_WITH(writeFileAtomically(target, "x"),
                      target + ": not a regular file (a directory, device, FIFO or link): will not replace it");
  }
  CHECK(std::filesystem::is_fifo(fifo));
  CHECK(std::filesystem::is_symlink(link));
  // A link planted at the temporary file's name is removed, not written through.
  const std::string planted = file + ".tmp" + std::to_string(::getpid());
  std::filesystem::remove(planted);
  std::filesystem::create_symlink("elsewhere.txt", planted);
  writeFileAtomically(file, "content");
  CHECK(!std::filesystem::exists(dir / "elsewhere.txt"));
  std::ifstream in(file);
  std::string text;
  std::getline(in, text);
  CHECK(text == "content");
}

TEST_CASE("output: a failed atomic write leaves the old file as it was and no temporary file behind") {
  const std::string file = scratch("kept.txt").string();
  writeFileAtomically(file, "old");
  const auto keptAsItWas = [&] {
    CHECK(readText(file) == "old");
    CHECK(!fs::exists(file + ".tmp" + std::to_string(::getpid())));
  };
  // The stream fails part-way (as on a full disk): the write is reported and nothing replaces the file.
  CHECK_THROWS_WITH(writeFileAtomically(file,
                                        [](std::ostream& out) {
                                          out << "new, half";
                                          out.setstate(std::ios::badbit);
                                        }),
                    file + ": write failed (disk full?)");
  keptAsItWas();
  // A writer that throws: the exception comes through, and again the old file stays and no temporary is left.
  CHECK_THROWS_WITH(writeFileAtomically(file,
                                        [](std::ostream& out) {
                                          out << "new, half";
                                          throw std::runtime_error("the writer gave up");
                                        }),
                    "the writer gave up");
  keptAsItWas();
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
  CHECK(Progress::formatDuration(7265) == "2 h 01 min");
  // An ETA from a tiny fraction done: 1e10 s is more seconds than an int holds.
  CHECK(Progress::formatDuration(1e10) == "2.78e+06 h");
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

namespace {

ino_t inode(const fs::path& path) {
  struct stat st {};
  REQUIRE(::stat(path.c_str(), &st) == 0);
  return st.st_ino;
}

}  // namespace

TEST_CASE("output: an append-only file is complete after every append and cut back on reopen", "[append]") {
  const fs::path path = scratch("append.xml");
  AppendOnlyFile f;
  f.create(path.string(), "<a>\n", "</a>\n");
  CHECK(readText(path) == "<a>\n</a>\n");
  const ino_t first = inode(path);
  f.append("1\n");
  const std::uint64_t afterOne = f.size();
  f.append("2\n");
  CHECK(readText(path) == "<a>\n1\n2\n</a>\n");
  CHECK(inode(path) == first);  // grown in place, not rewritten
  CHECK(f.size() == fs::file_size(path));
  AppendOnlyFile again;
  again.reopen(path.string(), afterOne, "</a>\n");
  CHECK(readText(path) == "<a>\n1\n</a>\n");
  again.append("3\n");
  CHECK(readText(path) == "<a>\n1\n3\n</a>\n");
  AppendOnlyFile wrong;
  CHECK_THROWS_WITH(wrong.reopen(path.string(), 1000, "</a>\n"), Catch::Contains("shorter than at the checkpoint"));
  // What was appended last before the checkpoint must be there, or the file (replaced or edited) is left as it is.
  const std::uint64_t afterThree = fs::file_size(path);
  CHECK_THROWS_WITH(wrong.reopen(path.string(), afterThree, "</a>\n", "4\n"),
                    Catch::Contains("does not end as at the checkpoint"));
  CHECK_THROWS_WITH(wrong.reopen(path.string(), afterThree, "</a>\n", "<a>\n1\n3\n3\n"),
                    Catch::Contains("does not end as at the checkpoint"));
  CHECK(readText(path) == "<a>\n1\n3\n</a>\n");
  again.reopen(path.string(), afterThree, "</a>\n", "3\n");
  again.append("4\n");
  CHECK(readText(path) == "<a>\n1\n3\n4\n</a>\n");
  // A link in its place (an output directory unpacked from elsewhere) is not followed: reopening cut back and
  // wrote into whatever it pointed to. Nor is a FIFO opened as the file.
  const fs::path outside = scratch("outside.txt"), link = scratch("linked.xml"), fifo = scratch("fifo.xml");
  writeFileAtomically(outside.string(), "a file outside the output directory, longer than the cut\n");
  fs::remove(link);
  fs::create_symlink(outside, link);
  CHECK_THROWS_WITH(wrong.reopen(link.string(), afterOne, "</a>\n"), Catch::Contains("a symbolic link"));
  CHECK(readText(outside) == "a file outside the output directory, longer than the cut\n");
  fs::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_WITH(wrong.reopen(fifo.string(), afterOne, "</a>\n"), Catch::Contains("not a regular file"));
}

TEST_CASE("output: frames.pvd and probes.csv grow by appends and stay complete after every step", "[append]") {
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/hanging_cloth.json");
  scene.outputs.frameStride = 2;
  const SceneModel model = buildSceneModel(scene);
  const fs::path dir = scratch("appended_run");
  fs::remove_all(dir);
  RunOutput out(dir.string(), scene, model);
  Eigen::VectorXd x = flatten(model.world.V);
  out.record({0, 0.0, 1.0, &x, nullptr}, true);
  const ino_t pvd = inode(dir / "frames.pvd"), csv = inode(dir / "probes.csv");
  for (int step = 1; step <= 6; ++step) {
    x[2] += 0.01;
    out.record({step, 0.1 * step, 1.0, &x, nullptr});
    const std::string series = readText(dir / "frames.pvd");
    const std::string probes = readText(dir / "probes.csv");
    // Complete: the closing tags end the series, and it lists the frames written so far.
    CHECK(series.substr(series.size() - PvdSeries::tail().size()) == PvdSeries::tail());
    std::size_t entries = 0;
    for (std::size_t at = series.find("<DataSet"); at != std::string::npos; at = series.find("<DataSet", at + 1)) ++entries;
    CHECK(entries == static_cast<std::size_t>(out.framesWritten()));
    CHECK(probes.back() == '\n');
    CHECK(std::count(probes.begin(), probes.end(), '\n') == 1 + 1 + step);  // the header and a row a step
  }
  // A step recorded again with other values (a run's final state) is written over its row.
  const std::string before = readText(dir / "probes.csv");
  x[2] += 0.5;
  out.record({6, 0.6, 1.0, &x, nullptr}, true);
  const std::string after = readText(dir / "probes.csv");
  CHECK(std::count(after.begin(), after.end(), '\n') == 1 + 1 + 6);
  const std::size_t lastRow = before.rfind('\n', before.size() - 2) + 1;
  CHECK(after.compare(0, lastRow, before, 0, lastRow) == 0);
  CHECK(after.substr(lastRow) != before.substr(lastRow));
  CHECK(after.substr(lastRow, 6) == "6,0.6,");
  REQUIRE(out.lastRow());
  CHECK(out.plotRows().rows.back().u == out.lastRow()->u);
  CHECK(out.plotRows().ranges.back().uHigh == out.lastRow()->u);
  CHECK(inode(dir / "frames.pvd") == pvd);
  CHECK(inode(dir / "probes.csv") == csv);
  // frames/ as a link out of the output directory is refused: the frames would have gone where it points.
  const fs::path linked = scratch("linked_run"), elsewhere = scratch("elsewhere");
  fs::remove_all(linked);
  fs::remove_all(elsewhere);
  fs::create_directories(linked);
  fs::create_directories(elsewhere);
  fs::create_directory_symlink(elsewhere, linked / "frames");
  CHECK_THROWS_WITH(RunOutput(linked.string(), scene, model), Catch::Contains("frames: a symbolic link"));
  CHECK(fs::is_empty(elsewhere));
}

TEST_CASE("output: a long run keeps a bounded number of rows, and probes.csv every one", "[append]") {
  Scene scene = loadSceneFile(std::string(JETSHELL_SOURCE_DIR) + "/examples/hanging_cloth.json");
  scene.outputs.frameStride = 1'000'000;
  const SceneModel model = buildSceneModel(scene);
  const fs::path dir = scratch("long_run");
  fs::remove_all(dir);
  RunOutput out(dir.string(), scene, model);
  Eigen::VectorXd x = flatten(model.world.V);
  const int steps = 5000;
  const Eigen::VectorXd rest = x;
  for (int step = 0; step <= steps; ++step) {
    for (Eigen::Index i = 2; i < x.size(); i += 3) x[i] = rest[i] - 1e-4 * step;  // every vertex falls
    out.record({step, 0.01 * step, 1.0, &x, nullptr}, step == 0);
  }
  const std::string probes = readText(dir / "probes.csv");
  CHECK(std::count(probes.begin(), probes.end(), '\n') == 1 + steps + 1);
  // In memory and in a checkpoint: every 4th row (5,001 rows need a stride of 4 to fit 2,048), and the last.
  const OutputCheckpoint state = out.state();
  CHECK(state.plotRows.stride == 4);
  CHECK(state.plotRows.rows.size() == 1251);
  CHECK(state.plotRows.consistent());
  const PlotRows plot = out.plotRows();
  const std::vector<ProbeRow>& rows = plot.rows;
  REQUIRE(rows.size() == 1251);
  CHECK(rows.front().step == 0);
  CHECK(rows.back().step == steps);
  for (std::size_t k = 1; k < rows.size(); ++k) CHECK(rows[k].step - rows[k - 1].step == 4);
  CHECK(out.lastRow()->step == steps);
  // Each bucket spans its four rows: the probe falls by 1e-4 a step, from the bucket's first row's.
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
    CHECK(plot.ranges[k].uHigh[2] == rows[k].u[2]);
    CHECK(plot.ranges[k].uLow[2] == Approx(rows[k].u[2] - 3e-4).margin(1e-12));
  }
}
