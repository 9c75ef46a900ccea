#include "core/mesh_generators.h"
#include "core/mesh_io.h"
#include "core/topology.h"

#include <catch2/catch.hpp>

#include <sstream>

using namespace jetshell;

namespace {

ObjMesh parse(const std::string& text) {
  std::istringstream in(text);
  return parseObj(in, "m.obj");
}

std::string objErrorOf(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

const char* kSquareObj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

}  // namespace

TEST_CASE("obj: reads triangles, polygons, slashed corners and relative indices") {
  const ObjMesh m = parse(std::string("# square\n") + kSquareObj + "vt 0 0\nvn 0 0 1\ng top\nf 1/1/1 2//1 3\nf -4 -2 -1\n");
  REQUIRE(m.mesh.numVertices() == 4);
  REQUIRE(m.mesh.numFaces() == 2);
  CHECK(m.mesh.F.row(1) == Eigen::RowVector3i(0, 2, 3));
  CHECK(m.faceLine == std::vector<int>{9, 10});
  const ObjMesh quad = parse(std::string(kSquareObj) + "f 1 2 3 4\n");
  CHECK(quad.mesh.numFaces() == 2);
  CHECK(quad.faceLine == std::vector<int>{5, 5});
}

TEST_CASE("obj: write then read reproduces the mesh bit for bit") {
  const TriMesh a = makeSlitAnnulus(0.6, 1.0, 3, 9);
  std::stringstream s;
  writeObj(s, a.V, a.F);
  const ObjMesh b = parseObj(s, "roundtrip.obj");
  CHECK(b.mesh.V == a.V);
  CHECK(b.mesh.F == a.F);
}

TEST_CASE("obj: broken files name the file and line") {
  CHECK(objErrorOf(std::string(kSquareObj) + "f 1 2 9\n") ==
        "m.obj:5: face index 9 is out of range (the file has 4 vertices)");
  CHECK(objErrorOf(std::string(kSquareObj) + "f 1 2 -7\n").rfind("m.obj:5: face index -7 is out of range", 0) == 0);
  CHECK(objErrorOf(std::string(kSquareObj) + "f 0 1 2\n") == "m.obj:5: face index 0 is invalid (OBJ indices start at 1)");
  CHECK(objErrorOf(std::string(kSquareObj) + "f 1 2 2\n") == "m.obj:5: face repeats a vertex");
  CHECK(objErrorOf(std::string(kSquareObj) + "f 1 2\n") == "m.obj:5: a face needs at least 3 corners");
  CHECK(objErrorOf(std::string(kSquareObj) + "f 1 x 3\n") ==
        "m.obj:5: face corner 'x' is not an index (i, i/t, i//n or i/t/n)");
  for (const char* corner : {"2/x/", "2/", "2//", "2/1/", "2//7x", "2/1/1/1", "/2", "2/+/1"})
    CHECK(objErrorOf(std::string(kSquareObj) + "f 1 " + corner + " 3\n") ==
          std::string("m.obj:5: face corner '") + corner + "' is not an index (i, i/t, i//n or i/t/n)");
  CHECK(objErrorOf("v 0 0\n") == "m.obj:1: a vertex needs 3 coordinates (x y z, optionally w or a colour r g b)");
  CHECK(objErrorOf("v 0 nan 0\n") == "m.obj:1: vertex coordinate 'nan' is not finite");
  CHECK(objErrorOf("v 0 1e999 0\n") == "m.obj:1: vertex coordinate '1e999' is not finite");
  CHECK(objErrorOf("v 0 1.5q 0\n") == "m.obj:1: '1.5q' is not a number");
  CHECK(objErrorOf("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n") == "m.obj:4: face is degenerate (area 0)");
  CHECK(objErrorOf(std::string(kSquareObj) + "f 1 2 3\nf 1 2 4\n").rfind("m.obj:6: face is oriented against the face on line 5",
                                                                   0) == 0);
  CHECK(objErrorOf("") == "m.obj: no vertices ('v' lines)");
  CHECK(objErrorOf(kSquareObj) == "m.obj: no faces ('f' lines)");
  CHECK(objErrorOf(std::string(kSquareObj) + "l 1 2\n").rfind("m.obj:5: 'l' elements are not supported", 0) == 0);
}

TEST_CASE("obj: an edge shared by three faces is reported with all three lines") {
  const std::string fin = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
  CHECK(objErrorOf(fin) == "m.obj:8: face uses the non-manifold edge between vertices 1 and 2, also used by the face on line 6 and "
                      "the face on line 7 (an edge joins at most two faces)");
}

TEST_CASE("obj: a missing file is named") {
  try {
    readObj("/nonexistent/dir/mesh.obj");
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()) == "/nonexistent/dir/mesh.obj: cannot open mesh file");
  }
}
