// Replays inputs through a libFuzzer harness without libFuzzer: `obj_replay FILE|DIR...` runs every file given
// (and every regular file of every directory given) once through LLVMFuzzerTestOneInput. CTest replays the
// committed corpus this way in every build, so the main build checks that the harnesses link and the sanitizer
// build runs the corpus under ASan + UBSan with g++. Exit 0 when every input passed, 1 otherwise.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

bool replay(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::cerr << file.string() << ": cannot be read\n";
    return false;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string bytes = buffer.str();
  try {
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  } catch (const std::exception& e) {  // the harness lets only InputError through quietly: this is a defect
    std::cerr << file.string() << ": uncaught exception: " << e.what() << "\n";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " FILE|DIR...\n";
    return 1;
  }
  std::size_t passed = 0;
  std::size_t failed = 0;
  for (int i = 1; i < argc; ++i) {
    const std::filesystem::path arg(argv[i]);
    std::vector<std::filesystem::path> files;
    if (std::filesystem::is_directory(arg)) {
      for (const auto& entry : std::filesystem::directory_iterator(arg))
        if (entry.is_regular_file()) files.push_back(entry.path());
    } else {
      files.push_back(arg);
    }
    for (const auto& file : files) (replay(file) ? passed : failed) += 1;
  }
  std::cout << passed << " inputs replayed, " << failed << " failed\n";
  return failed == 0 && passed > 0 ? 0 : 1;
}
