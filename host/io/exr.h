// OpenEXR output and input of Image: lossless compression (ZIP unless asked otherwise), 32-bit float channels (half
// on request), string attributes for provenance (technique, parameters, device), double and m44f attributes for
// numbers and matrices.
// Writes are all-or-nothing (temp file + rename). Every failure is a std::runtime_error that starts with the path and
// says why.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "host/io/atomic_file.h"
#include "host/io/image.h"
#include "host/io/image_rows.h"

namespace penumbra {

// The lossless compressions a penumbra EXR may be written with (the lossy ones, pxr24/b44/dwa, would change the
// visibility a batch job is checked by). ZIP is the default: the smallest files of the five on our channels; none
// writes fastest (a CPU device shares its cores with the compression, docs/batch.md#throughput).
enum class ExrCompression { None, Rle, Zips, Zip, Piz };

// "none", "rle", "zips", "zip", "piz"; throws std::invalid_argument naming the choices for anything else.
ExrCompression parseExrCompression(const std::string& name);
const char* exrCompressionName(ExrCompression compression);

struct ExrOptions {
  ExrCompression compression = ExrCompression::Zip;
  // Channels stored as 16-bit half instead of 32-bit float (e.g. previews of "R", "G", "B").
  // Values beyond +-65504 become +-Inf and small ones lose precision; every name must be a channel
  // of the image (a typo is an error, not a silent float channel).
  std::set<std::string> halfChannels;
  // The pixel memory of a write: whole 16-row blocks of every channel in about this many bytes (tests make it small).
  size_t bandBytes = size_t{32} << 20;
  // When set, the written and synced file is renamed into place by the group's commit() (with the files written
  // beside it, an EXR and its PNG preview) instead of at once.
  CommitGroup* commitGroup = nullptr;
};

// Writes every channel of `image` (which must be non-empty and have at least one channel) and
// each of its attributes as an EXR string attribute, its numbers() as double and its matrices() as
// m44f attributes. Attribute names that EXR reserves for its own header fields (channels,
// compression, dataWindow, ...), and a name given in two of the maps, are refused.
void writeExr(const std::filesystem::path& path, const Image& image, const ExrOptions& options = {});
// The same, the channels read in bands of whole 16-row blocks (options.bandBytes), so a frame whose channels stay on
// the device (ImageRows' deferred channels) is never whole on the host.
void writeExr(const std::filesystem::path& path, const ImageRows& image, const ExrOptions& options = {});

// Reads every channel of a flat (non-deep) EXR, whatever its pixel type (half, float, uint), as
// float, plus every string attribute, every double, float and int attribute (as numbers()) and
// every m44f attribute (as matrices()). The image covers the data window: its row 0 is the data
// window's top row, wherever the window sits (readExrInfo() tells where). Part 0 of multi-part
// files. Subsampled channels are refused. image.source() is set to `path`.
Image readExr(const std::filesystem::path& path);

enum class ExrPixelType { Uint, Half, Float };

struct ExrWindow {  // inclusive pixel bounds, as in the EXR header
  int minX = 0, minY = 0, maxX = -1, maxY = -1;
  int width() const { return maxX - minX + 1; }
  int height() const { return maxY - minY + 1; }
};

struct ExrChannelInfo {
  std::string name;
  ExrPixelType type = ExrPixelType::Float;
};

// What an EXR header says, without reading pixels: for checks of how a file was written and for
// tools that print file summaries.
struct ExrInfo {
  ExrWindow dataWindow;
  ExrWindow displayWindow;
  std::string compression;  // "none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"
  bool tiled = false;
  std::vector<ExrChannelInfo> channels;           // sorted by name, as EXR stores them
  std::map<std::string, std::string> attributes;  // the string attributes (penumbra:version, penumbra:job-id, ...)
};

ExrInfo readExrInfo(const std::filesystem::path& path);

const char* exrPixelTypeName(ExrPixelType type);  // "uint", "half", "float"

}  // namespace penumbra
