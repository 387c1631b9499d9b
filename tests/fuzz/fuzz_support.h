// What the fuzz harnesses share: a scratch folder of their own for the file-based loaders, the loader limits a
// harness runs under (small, so that a fuzzer's input cannot exhaust memory by design), and the rule that an
// input's only allowed failure is the error type its API documents: anything else aborts, and libFuzzer (or the
// replay driver, replay_main.cpp) reports it.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/scene/load_options.h"

namespace penumbra::fuzz {

// A folder under the temporary directory, made once per process.
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() / ("penumbra_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::string writeScratch(const std::string& name, const uint8_t* data, size_t size) {
  const std::filesystem::path path = scratch() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

// Set by the replay driver under PENUMBRA_FUZZ_IN_PLACE: the input's own path, so that a harness of a file loader
// reads it where it lies, beside its external buffers and images (compare_validator.py); null under libFuzzer.
inline const char*& inPlacePath() {
  static const char* path = nullptr;
  return path;
}

inline LoadOptions fuzzLimits() {
  LoadOptions o;
  o.maxFileBytes = o.maxTotalBytes = uint64_t{1} << 24;
  o.maxTriangles = o.maxVertices = uint64_t{1} << 20;
  o.maxJsonValues = uint64_t{1} << 20;
  o.maxParseBytes = uint64_t{1} << 27;
  o.maxTextureBytes = uint64_t{1} << 22;
  o.warn = [](const std::string&) {};
  return o;
}

// Runs fn(); an exception of type Allowed is a verdict on the input, anything else a finding. With
// PENUMBRA_FUZZ_VERDICTS set, prints "verdict: accepted" or "verdict: refused: MESSAGE" (compare_validator.py).
template <class Allowed, class Fn>
void expectOnly(const char* harness, Fn&& fn) {
  static const bool verdicts = std::getenv("PENUMBRA_FUZZ_VERDICTS") != nullptr;
  try {
    fn();
    if (verdicts) std::printf("verdict: accepted\n");
  } catch (const Allowed& e) {
    if (verdicts) std::printf("verdict: refused: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: unexpected exception: %s\n", harness, e.what());
    std::abort();
  }
}

}  // namespace penumbra::fuzz
