#include "core/mesh_generators.h"
#include "validation/line_load.h"
#include "validation/reference_table.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

using namespace jetshell;
using namespace jetshell::validation;

TEST_CASE("line load: consistent nodal forces keep the total and halve the end shares") {
  for (int ny : {1, 3, 8}) {
    const TriMesh mesh = makeRectangleGrid(10.0, 1.0, 4, ny);
    std::vector<int> chain;
    for (int j = 0; j <= ny; ++j) chain.push_back(j * 5 + 4);
    const Eigen::VectorXd f = consistentLineLoad(mesh, chain, Eigen::Vector3d(0, 0, 4.0));
    CHECK(f.sum() == Approx(4.0));
    CHECK(f[3 * chain.front() + 2] == Approx(2.0 / ny));
    CHECK(f[3 * chain[1] + 2] == Approx(ny == 1 ? 2.0 : 4.0 / ny));
  }
}

TEST_CASE("reference tables: the copied Sze tables load with their row counts") {
  const ReferenceTable plate =
      loadReferenceTable(referenceDirectory() + "/sze2004_3.3_slit_annular_plate.tsv", {"W_A", "W_B"});
  CHECK(plate.rows() == 23);
  CHECK(plate.lambda.back() == 1.0);
  CHECK(plate.value.back()[1] == 17.528);
  const ReferenceTable shear =
      loadReferenceTable(referenceDirectory() + "/sze2004_3.1_cantilever_end_shear.tsv", {"-u_tip", "w_tip"});
  CHECK(shear.rows() == 20);
  CHECK(shear.value[0][1] == 0.663);
  // Three printed decimals: 0.026 stands for [0.0255, 0.0265].
  REQUIRE(shear.halfUnit.size() == 20);
  CHECK(shear.halfUnit[0][0] == Approx(0.0005));
  CHECK(scaled(plate, 0.1).halfUnit.back()[1] == Approx(0.00005));
}

TEST_CASE("reference tables: each value keeps half a unit of its last printed digit") {
  const std::string path = "validation_digits_table.tsv";
  {
    std::ofstream out(path);
    out << "0.5 12 0.026 1.5e-3 2.50E2\n";
  }
  const ReferenceTable t = loadReferenceTable(path, {"a", "b", "c", "d"});
  std::remove(path.c_str());
  REQUIRE(t.halfUnit.size() == 1);
  CHECK(t.halfUnit[0][0] == Approx(0.5));
  CHECK(t.halfUnit[0][1] == Approx(0.0005));
  CHECK(t.halfUnit[0][2] == Approx(0.00005));
  CHECK(t.halfUnit[0][3] == Approx(0.5));
  // A zero with an exponent beyond any int loads (its half unit is bounded), it does not throw out_of_range.
  {
    std::ofstream out(path);
    out << "0.5 0e99999999999\n";
  }
  const ReferenceTable z = loadReferenceTable(path, {"a"});
  std::remove(path.c_str());
  REQUIRE(z.halfUnit.size() == 1);
  CHECK(std::isfinite(z.halfUnit[0][0]));
}

TEST_CASE("reference tables: malformed files are rejected naming the line") {
  const std::string path = "validation_bad_table.tsv";
  {
    std::ofstream out(path);
    out << "# comment\n0.1 1 2\n0.2 3\n";
  }
  try {
    loadReferenceTable(path, {"a", "b"});
    FAIL("no exception");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find(":3:") != std::string::npos);
  }
  std::remove(path.c_str());
}

TEST_CASE("end moment closed form: the strip closes into a circle at lambda = 1") {
  const ReferenceTable t = endMomentClosedForm(12.0, 20);
  CHECK(t.rows() == 20);
  CHECK(t.value.back()[0] == Approx(12.0));
  CHECK(t.value.back()[1] == Approx(0.0).margin(1e-12));
  // λ = 0.5: a half circle of radius L/π standing on the clamped end.
  CHECK(t.value[9][0] == Approx(12.0));
  CHECK(t.value[9][1] == Approx(24.0 / 3.14159265358979323846));
}
