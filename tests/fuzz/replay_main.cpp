// The corpus replayed without libFuzzer: calls a harness's LLVMFuzzerTestOneInput on every file named on the
// command line (folders: every file inside, sorted), so plain g++ builds run the corpus as ordinary ctest entries.
// Exit 0 when every input came back; a harness aborts on a finding. PENUMBRA_FUZZ_VERDICTS and PENUMBRA_FUZZ_IN_PLACE:
// fuzz_support.h.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputs(int argc, char** argv) {
  std::vector<fs::path> out;
  for (int i = 1; i < argc; ++i) {
    if (!fs::is_directory(argv[i])) {
      out.emplace_back(argv[i]);
      continue;
    }
    for (const auto& entry : fs::recursive_directory_iterator(argv[i]))
      if (entry.is_regular_file()) out.push_back(entry.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<fs::path> files = inputs(argc, argv);
  if (files.empty()) {
    std::fprintf(stderr, "replay: no inputs (usage: %s FILE_OR_FOLDER...)\n", argv[0]);
    return 2;
  }
  const bool verdicts = std::getenv("PENUMBRA_FUZZ_VERDICTS") != nullptr;
  const bool inPlace = std::getenv("PENUMBRA_FUZZ_IN_PLACE") != nullptr;
  for (const fs::path& file : files) {
    if (verdicts) std::printf("input: %s\n", file.string().c_str());
    const std::string name = file.string();
    if (inPlace) penumbra::fuzz::inPlacePath() = name.c_str();
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    std::fflush(stdout);
  }
  std::printf("replayed %zu inputs\n", files.size());
  return 0;
}
