// Hostile OBJ input: every malformed file gets one clear line naming the file and line (exit code 3 in the
// program), and reading stays bounded in memory and time.
#include "core/input_limits.h"
#include "core/mesh_io.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace jetshell;

namespace {

std::string errorOf(const std::string& text) {
  std::istringstream in(text);
  try {
    parseObj(in, "m.obj");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string fileErrorOf(const std::string& path) {
  try {
    readObj(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

/// Lowers one limit for the scope of a test (keeps the test's input small).
struct LimitOverride {
  InputLimits saved = inputLimits();
  ~LimitOverride() { inputLimits() = saved; }
};

const std::string kSquare = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

std::string tempPath(const std::string& name) {
  const auto dir = test::scratchDirectory("obj_hostile");
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

}  // namespace

TEST_CASE("obj hostile: indices that are zero, out of range, relative or not numbers", "[obj][hostile]") {
  CHECK(errorOf(kSquare + "f 0 1 2\n") == "m.obj:5: face index 0 is invalid (OBJ indices start at 1)");
  CHECK(errorOf(kSquare + "f 1 2 5\n") == "m.obj:5: face index 5 is out of range (the file has 4 vertices)");
  CHECK(errorOf(kSquare + "f -1 -2 -5\n") ==
        "m.obj:5: face index -5 is out of range (the file has 4 vertices, 4 before this line)");
  // Relative indices count back from the line: -1 is the last vertex defined above it.
  CHECK(errorOf("v 0 0 0\nv 1 0 0\nf -2 -1 3\nv 0 1 0\n") == "no error");
  CHECK(errorOf(kSquare + "f 1 2 99999999999999999999\n") ==
        "m.obj:5: face corner '99999999999999999999' is not an index (i, i/t, i//n or i/t/n)");
  CHECK(errorOf(kSquare + "f 1 2 3.0\n") == "m.obj:5: face corner '3.0' is not an index (i, i/t, i//n or i/t/n)");
  CHECK(errorOf(kSquare + "f 1 2 +\n") == "m.obj:5: face corner '+' is not an index (i, i/t, i//n or i/t/n)");
  CHECK(errorOf(kSquare + "f /1 2 3\n") == "m.obj:5: face corner '/1' is not an index (i, i/t, i//n or i/t/n)");
}

TEST_CASE("obj hostile: missing parts", "[obj][hostile]") {
  CHECK(errorOf("") == "m.obj: no vertices ('v' lines)");
  CHECK(errorOf("# only a comment\n\n   \n") == "m.obj: no vertices ('v' lines)");
  CHECK(errorOf(kSquare + "vn 0 0 1\n") == "m.obj: no faces ('f' lines)");
  CHECK(errorOf(kSquare + "f\n") == "m.obj:5: a face needs at least 3 corners");
  CHECK(errorOf("v 1 2\n") == "m.obj:1: a vertex needs 3 coordinates (x y z, optionally w or a colour r g b)");
  CHECK(errorOf("v 1 2 3 4 5\n") == "m.obj:1: a vertex needs 3 coordinates (x y z, optionally w or a colour r g b)");
}

TEST_CASE("obj hostile: non-manifold edges, flipped and repeated faces", "[obj][hostile]") {
  CHECK(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n") ==
        "m.obj:8: face uses the non-manifold edge between vertices 1 and 2, also used by the face on line 6 and the "
        "face on line 7 (an edge joins at most two faces)");
  CHECK(errorOf(kSquare + "f 1 2 3\nf 1 3 4\nf 1 3 4\n") == "m.obj:7: face duplicates the face on line 6");
  CHECK(errorOf(kSquare + "f 1 2 3\nf 2 3 1\n") == "m.obj:6: face duplicates the face on line 5");
  CHECK(errorOf(kSquare + "f 1 2 3\nf 1 3 2\n") ==
        "m.obj:6: face is the face on line 5 reversed (two faces on the same three vertices)");
  // One face wound the other way round: both run along the shared edge 1-3 in the same direction.
  CHECK(errorOf(kSquare + "f 1 2 3\nf 1 4 3\n") ==
        "m.obj:6: face is oriented against the face on line 5 (both run from vertex 3 to vertex 1 along their shared "
        "edge; neighbours must run it in opposite directions)");
}

TEST_CASE("obj hostile: a face folded flat onto its neighbour is named with both lines", "[obj][hostile]") {
  // Vertex 4 lies on the far side of edge 1-3, folded back over face 1: the normals are 180 degrees apart.
  CHECK(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0.5 0.2 0\nf 1 2 3\nf 1 3 4\n") ==
        "m.obj:6: face is folded flat onto the face on line 5 across the edge between vertices 1 and 3 (normals "
        "180.000 degrees apart, at most 179.9: the rest curvature is undefined there)");
  // A hinge along the x axis folded by phi: just below the bound a sharp but valid fold, just above rejected.
  auto hinge = [](double degrees) {
    const double phi = degrees * 3.14159265358979323846 / 180.0;
    std::ostringstream s;
    s.precision(17);
    s << "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 " << -std::cos(phi) << ' ' << std::sin(phi) << "\nf 1 2 3\nf 2 1 4\n";
    return errorOf(s.str());
  };
  CHECK(hinge(90.0) == "no error");
  CHECK(hinge(179.8) == "no error");
  CHECK(hinge(179.95) ==
        "m.obj:6: face is folded flat onto the face on line 5 across the edge between vertices 1 and 2 (normals "
        "179.950 degrees apart, at most 179.9: the rest curvature is undefined there)");
}

TEST_CASE("obj hostile: numbers", "[obj][hostile]") {
  CHECK(errorOf("v 0 nan 0\n") == "m.obj:1: vertex coordinate 'nan' is not finite");
  CHECK(errorOf("v 0 -inf 0\n") == "m.obj:1: vertex coordinate '-inf' is not finite");
  CHECK(errorOf("v 1e400 0 0\n") == "m.obj:1: vertex coordinate '1e400' is not finite");
  CHECK(errorOf("v 0x1p3 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n") == "no error");  // strtod's hex floats are numbers
  CHECK(errorOf("v 1,5 0 0\n") == "m.obj:1: '1,5' is not a number");
  CHECK(errorOf("v 0 0 0 1 0 nan\n") == "m.obj:1: vertex coordinate 'nan' is not finite");  // colours are checked too
  CHECK(errorOf("v 0 0 0\nv 1e-200 0 0\nv 0 1e-200 0\nf 1 2 3\n").rfind("m.obj:4: face is degenerate (area ", 0) == 0);
  // Finite coordinates whose area overflows: once called degenerate, "area inf".
  CHECK(errorOf("v 0 0 0\nv 1e200 0 0\nv 0 1e200 0\nf 1 2 3\n") ==
        "m.obj:4: face is too large to measure (its area overflows a double)");
}

TEST_CASE("obj hostile: line ends, byte-order mark and vertex colours are accepted", "[obj][hostile]") {
  const std::string crlf = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n";
  CHECK(errorOf(crlf) == "no error");
  CHECK(errorOf("\xEF\xBB\xBF" + crlf) == "no error");
  CHECK(errorOf("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n") == "no error");
  CHECK(errorOf("v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\nf 1 2 3\n") == "no error");
  CHECK(errorOf("v 0 0 0 1 0.5 0.5 0.5\nv 1 0 0\nv 0 1 0\nf 1 2 3 # triangle\n") == "no error");
  CHECK(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\ng Ärmel\nf 1 2 3\n") == "no error");  // UTF-8 names
  // Without a newline at the end, and with old Mac line ends (one long line with no 'v').
  CHECK(errorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3") == "no error");
}

TEST_CASE("obj hostile: binary data and very long lines", "[obj][hostile]") {
  CHECK(errorOf(kSquare + std::string("f 1 2 3\0\x01\x02", 10) + "\n") ==
        "m.obj:5: binary data (byte 0x00): not an OBJ text file");
  CHECK(errorOf("\x7f" "ELF\x02\x01\x01\n") == "m.obj:1: binary data (byte 0x02): not an OBJ text file");
  CHECK(errorOf("v 0 0 0\nv 1 0 0\rv 0 1 0\n") == "m.obj:2: binary data (byte 0x0d): not an OBJ text file");
  const std::string longLine = "# " + std::string(100000, 'x') + "\n";
  CHECK(errorOf(kSquare + longLine) == "m.obj:5: line is too long (at most 65536 bytes)");
  LimitOverride restore;
  inputLimits().maxObjBytes = 100;
  CHECK(errorOf(kSquare + kSquare + kSquare + kSquare + kSquare) == "m.obj:13: the file is too large (at most 100 bytes)");
}

TEST_CASE("obj hostile: vertex and face counts are bounded", "[obj][hostile]") {
  LimitOverride restore;
  inputLimits().maxVertices = 3;
  CHECK(errorOf(kSquare + "f 1 2 3\n") == "m.obj:4: too many vertices (at most 3)");
  inputLimits().maxVertices = 100;
  inputLimits().maxFaces = 1;
  CHECK(errorOf(kSquare + "f 1 2 3 4\n") == "m.obj:5: too many faces (at most 1 triangles)");
}

TEST_CASE("obj hostile: only regular files are read (no FIFO, device or directory)", "[obj][hostile]") {
  CHECK(fileErrorOf("/dev/zero") == "/dev/zero: not a regular file (a directory, FIFO or device): cannot read it as a "
                                    "mesh file");
  const std::string fifo = tempPath("mesh.fifo");
  std::filesystem::remove(fifo);
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK(fileErrorOf(fifo) == fifo + ": not a regular file (a directory, FIFO or device): cannot read it as a mesh file");
  std::filesystem::remove(fifo);
  const std::string dir = std::filesystem::path(tempPath("x")).parent_path().string();
  CHECK(fileErrorOf(dir) == dir + ": not a regular file (a directory, FIFO or device): cannot read it as a mesh file");
  const std::string big = tempPath("big.obj");
  std::ofstream(big) << kSquare << "f 1 2 3\n";
  LimitOverride restore;
  inputLimits().maxObjBytes = 10;
  CHECK(fileErrorOf(big) == big + ": mesh file of 40 bytes is too large (at most 10)");
  std::filesystem::remove(big);
}
