#include "tools/output/earlier_run_files.h"

#include "core/mesh.h"
#include "tests/scratch_directory.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace jetshell;
namespace fs = std::filesystem;

namespace {

void touchRunFile(const fs::path& p) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << "x";
}

}  // namespace

TEST_CASE("earlier run files: the files a run writes go, everything else stays", "[output][hostile]") {
  const fs::path dir = test::scratchDirectory("earlier_run_files") / "out";
  fs::remove_all(dir);
  const fs::path outside = test::scratchDirectory("earlier_run_files") / "outside";
  fs::remove_all(outside);
  const std::vector<std::string> runs = {
      "summary.json", "frames.pvd", "probes.csv", "final.png", "probes.png", "contact_forces.png", "volumes.vtu",
      "checkpoint.cbor", "summary.json.tmp4242", "frames/frame_00000.vtu", "frames/frame_00060.vtu",
      "frames/volumes_00007.vtu", "frames/frame_123456.vtu", "frames/frame_00003.vtu.tmp17",
      "obj/frame_00002.obj", "obj/volumes_00002.obj", "obj/volumes.obj"};
  const std::vector<std::string> others = {
      "notes.txt", "summary.json.bak", "summary.json.tmp", "final.png.tmpx", "frames/frame_1.vtu",
      "frames/frame_00001.vtk", "frames/my_frame_00001.vtu", "frames/frame_00001.vtu.old", "frames/notes.txt",
      "obj/volumes.obj.bak", "obj/frame_00002.vtu", "sub/summary.json", "sub/frames/frame_00001.vtu"};
  for (const std::string& f : runs) touchRunFile(dir / f);
  for (const std::string& f : others) touchRunFile(dir / f);
  // A link named like a run's picture goes; what it points to stays.
  touchRunFile(outside / "picture.png");
  fs::remove(dir / "final.png");
  fs::create_symlink(outside / "picture.png", dir / "final.png");
  CHECK(removeEarlierRunFiles(dir.string()) == static_cast<int>(runs.size()));
  for (const std::string& f : runs) CHECK_FALSE(fs::exists(fs::symlink_status(dir / f)));
  for (const std::string& f : others) CHECK(fs::exists(dir / f));
  CHECK(fs::exists(outside / "picture.png"));
  // Nothing left to remove, and a directory that does not exist holds nothing.
  CHECK(removeEarlierRunFiles(dir.string()) == 0);
  CHECK(removeEarlierRunFiles((dir / "none").string()) == 0);
}

TEST_CASE("earlier run files: frames/ as a link is not entered", "[output][hostile]") {
  const fs::path dir = test::scratchDirectory("earlier_run_files") / "linked";
  fs::remove_all(dir);
  const fs::path elsewhere = test::scratchDirectory("earlier_run_files") / "elsewhere";
  fs::remove_all(elsewhere);
  touchRunFile(elsewhere / "frame_00001.vtu");
  fs::create_directories(dir);
  fs::create_directory_symlink(elsewhere, dir / "frames");
  CHECK(removeEarlierRunFiles(dir.string()) == 0);
  CHECK(fs::exists(elsewhere / "frame_00001.vtu"));
}
