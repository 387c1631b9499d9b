// The image output that `render` and `reference` share: `-o` names the format by its extension (.exr: the EXR
// plus a PNG preview beside it; .png: the preview alone), `--png PATH|none` moves or drops the preview. The plan
// is checked before any work, so a bad combination is a usage error (std::invalid_argument, exit 2).
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>

#include "host/io/exr.h"
#include "host/io/image.h"
#include "host/io/image_rows.h"

namespace penumbra::cli {

struct ImageOutput {
  std::string path;                    // -o: out.exr or out.png
  std::string png;                     // --png: empty = the EXR path with .png, "none" = no preview
  std::string exrCompression = "zip";  // --exr-compression
};

// What will be written: at least one of the two.
struct ImageOutputPlan {
  std::optional<std::filesystem::path> exr, png;
  ExrOptions exrOptions;
};

inline void addImageOutputOptions(CLI::App* sub, ImageOutput& output) {
  sub->add_option("-o,--output", output.path,
                  "Output: .exr (EXR with every channel, plus the PNG preview) or .png "
                  "(the preview alone)")
      ->capture_default_str();
  sub->add_option("--png", output.png,
                  "PNG preview of an .exr output: PATH, or none (default: the EXR path with .png)");
  sub->add_option("--exr-compression", output.exrCompression,
                  "The EXR's lossless compression: zip (smallest), zips, piz, rle or none (fastest to write; the "
                  "pixels are the same whichever)")
      ->capture_default_str();
}

// Throws std::invalid_argument for an extension other than .exr/.png, --png with a .png output, a --png path that is
// the EXR's own, or an unknown --exr-compression.
ImageOutputPlan planImageOutput(const ImageOutput& output);

// Writes what the plan says (creating folders; the PNG before the EXR) and returns the "wrote A and B" message.
std::string writeImageOutput(const ImageOutputPlan& plan, const Image& image);
// The same, read band by band (a frame whose channels stay on the device).
std::string writeImageOutput(const ImageOutputPlan& plan, const ImageRows& image);

}  // namespace penumbra::cli
