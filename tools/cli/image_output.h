// The EXR + PNG preview output that `render` and `reference` share: the options, and writing both (the EXR's
// folder created, the PNG beside the EXR unless named).
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>

#include "host/io/exr.h"
#include "host/io/image.h"
#include "host/io/png.h"

namespace penumbra::cli {

struct ImageOutput {
  std::string exr, png;  // png empty: the EXR path with .png
};

inline void addImageOutputOptions(CLI::App* sub, ImageOutput& output) {
  sub->add_option("-o,--output", output.exr, "Output EXR")->capture_default_str();
  sub->add_option("--png", output.png, "PNG preview (default: the EXR path with .png)");
}

// Writes both files and returns the "wrote A and B" message.
inline std::string writeImageOutput(const ImageOutput& output, const Image& image) {
  const std::filesystem::path exr = output.exr;
  if (exr.has_parent_path()) std::filesystem::create_directories(exr.parent_path());
  writeExr(exr, image);
  const std::filesystem::path png =
      output.png.empty() ? std::filesystem::path(exr).replace_extension(".png") : std::filesystem::path(output.png);
  writePngPreview(png, image);
  return "wrote " + exr.string() + " and " + png.string();
}

}  // namespace penumbra::cli
