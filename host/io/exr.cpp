// EXR I/O through the OpenEXR 3 C++ API (Imf::Header / FrameBuffer / OutputFile / InputFile).
// Reading uses FLOAT slices and lets InputFile convert from any file type; OutputFile does not
// convert, so half channels go through half buffers. OpenEXR's Iex exceptions are caught here and
// rethrown as std::runtime_error with the path in front.
#include "host/io/exr.h"

#include <IexBaseExc.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfDoubleAttribute.h>
#include <ImfFloatAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfIntAttribute.h>
#include <ImfMatrixAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <ImfTestFile.h>
#include <fmt/format.h>
#include <half.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstring>
#include <fstream>
#include <memory>
#include <new>
#include <set>
#include <span>
#include <stdexcept>
#include <string_view>

#include "host/io/atomic_file.h"

namespace penumbra {
namespace {

// Header fields OpenEXR defines with non-string types or a fixed meaning; a user string attribute
// of the same name would be refused by Imf::Header or corrupt the file's layout.
constexpr std::array<std::string_view, 14> kReservedAttributes = {
    "channels",           "compression",       "dataWindow", "displayWindow", "lineOrder", "pixelAspectRatio",
    "screenWindowCenter", "screenWindowWidth", "tiles",      "type",          "name",      "version",
    "chunkCount",         "maxSamplesPerPixel"};

// The first four bytes of every EXR file (20000630 little-endian).
constexpr std::array<unsigned char, 4> kExrMagic = {0x76, 0x2f, 0x31, 0x01};

[[noreturn]] void fail(const std::filesystem::path& path, std::string_view what) {
  throw std::runtime_error(fmt::format("{}: {}", path.string(), what));
}

Imf::Compression toImf(ExrCompression compression) {
  switch (compression) {
    case ExrCompression::None:
      return Imf::NO_COMPRESSION;
    case ExrCompression::Rle:
      return Imf::RLE_COMPRESSION;
    case ExrCompression::Zips:
      return Imf::ZIPS_COMPRESSION;
    case ExrCompression::Piz:
      return Imf::PIZ_COMPRESSION;
    case ExrCompression::Zip:
      break;
  }
  return Imf::ZIP_COMPRESSION;
}

constexpr std::array<ExrCompression, 5> kCompressions = {
    ExrCompression::None, ExrCompression::Rle, ExrCompression::Zips, ExrCompression::Zip, ExrCompression::Piz};

Imf::Header makeHeader(const std::filesystem::path& path, const ImageRows& rows, const ExrOptions& options) {
  const Image& image = rows.header();
  if (image.empty()) fail(path, fmt::format("cannot write an empty {}x{} image", image.width(), image.height()));
  if (rows.channelNames().empty()) fail(path, "cannot write an image without channels");
  for (const std::string& name : options.halfChannels)
    if (!rows.has(name)) fail(path, fmt::format("half channel '{}' is not in the image", name));

  Imf::Header header(image.width(), image.height());
  header.compression() = toImf(options.compression);
  for (const std::string& name : rows.channelNames()) {
    const bool half = options.halfChannels.count(name) != 0;
    header.channels().insert(name, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
  }
  std::set<std::string> names;
  auto check = [&](const std::string& name) {
    if (name.empty()) fail(path, "attribute with an empty name");
    if (std::find(kReservedAttributes.begin(), kReservedAttributes.end(), name) != kReservedAttributes.end())
      fail(path, fmt::format("attribute name '{}' is reserved by OpenEXR", name));
    if (!names.insert(name).second)
      fail(path, fmt::format("attribute '{}' is given twice (text, number, matrix)", name));
  };
  for (const auto& [name, value] : image.attributes()) check(name), header.insert(name, Imf::StringAttribute(value));
  for (const auto& [name, value] : image.numbers()) check(name), header.insert(name, Imf::DoubleAttribute(value));
  for (const auto& [name, m] : image.matrices()) {
    check(name);
    header.insert(name, Imf::M44fAttribute(Imath::M44f(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9],
                                                       m[10], m[11], m[12], m[13], m[14], m[15])));
  }
  return header;
}

// Opens the file ourselves first so that "no such file" and "permission denied" come with the
// system's reason, and so that a non-EXR file is named as such instead of as a parse error.
void checkReadable(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) fail(path, "no such file");
  if (std::filesystem::is_directory(status)) fail(path, "is a directory, not an EXR file");
  errno = 0;
  std::ifstream probe(path, std::ios::binary);
  if (!probe) fail(path, fmt::format("cannot open: {}", std::strerror(errno)));
  std::array<unsigned char, 8> head{};
  probe.read(reinterpret_cast<char*>(head.data()), head.size());
  if (probe.gcount() < 4 || !std::equal(kExrMagic.begin(), kExrMagic.end(), head.begin()))
    fail(path, "not an OpenEXR file (bad magic number)");
  // The version field: format version 2 and only the flags the format defines (tiled 0x200, long names 0x400,
  // non-image 0x800, multi-part 0x1000); anything else is junk after the magic number, not a deep image.
  const uint32_t version =
      uint32_t{head[4]} | uint32_t{head[5]} << 8 | uint32_t{head[6]} << 16 | uint32_t{head[7]} << 24;
  if (probe.gcount() < 8 || (version & 0xff) != 2 || (version & ~uint32_t{0x1eff}) != 0)
    fail(path, fmt::format("not a readable OpenEXR file (its version field is {:#010x}: format 2 with flags 0x200, "
                           "0x400, 0x800 or 0x1000 expected)",
                           version));
  bool tiled = false, deep = false, multiPart = false;
  if (!Imf::isOpenExrFile(path.c_str(), tiled, deep, multiPart)) fail(path, "not a readable OpenEXR file");
  if (!deep) return;
  try {  // a deep image only if its header reads as one
    const Imf::MultiPartInputFile file(path.c_str());
  } catch (const std::exception& e) {
    fail(path, fmt::format("cannot read EXR header: {}", e.what()));
  }
  fail(path, "deep EXR images are not supported");
}

ExrWindow toWindow(const Imath::Box2i& box) { return {box.min.x, box.min.y, box.max.x, box.max.y}; }

ExrPixelType toPixelType(Imf::PixelType type) {
  switch (type) {
    case Imf::UINT:
      return ExrPixelType::Uint;
    case Imf::HALF:
      return ExrPixelType::Half;
    default:
      return ExrPixelType::Float;
  }
}

const char* compressionName(Imf::Compression compression) {
  switch (compression) {
    case Imf::NO_COMPRESSION:
      return "none";
    case Imf::RLE_COMPRESSION:
      return "rle";
    case Imf::ZIPS_COMPRESSION:
      return "zips";
    case Imf::ZIP_COMPRESSION:
      return "zip";
    case Imf::PIZ_COMPRESSION:
      return "piz";
    case Imf::PXR24_COMPRESSION:
      return "pxr24";
    case Imf::B44_COMPRESSION:
      return "b44";
    case Imf::B44A_COMPRESSION:
      return "b44a";
    case Imf::DWAA_COMPRESSION:
      return "dwaa";
    case Imf::DWAB_COMPRESSION:
      return "dwab";
    default:
      return "unknown";
  }
}

std::vector<ImageChannel> readChannels(const std::filesystem::path& path, Imf::InputFile& input, int width,
                                       int height) {
  const Imf::Header& header = input.header();
  const Imath::Box2i dataWindow = header.dataWindow();
  std::vector<ImageChannel> channels;
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
    if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
      fail(path, fmt::format("channel '{}' is subsampled ({}x{}), which is not supported", it.name(),
                             it.channel().xSampling, it.channel().ySampling));
    channels.push_back({it.name(), std::vector<float>(static_cast<size_t>(width) * height)});
  }
  Imf::FrameBuffer frame;
  for (ImageChannel& channel : channels)
    frame.insert(channel.name,
                 Imf::Slice::Make(Imf::FLOAT, channel.data.data(), dataWindow, sizeof(float), sizeof(float) * width));
  input.setFrameBuffer(frame);
  if (!channels.empty()) input.readPixels(dataWindow.min.y, dataWindow.max.y);
  return channels;
}

// The attribute types Image carries; others (box2i, chlist, v2f, ...) and the header's own fields
// (pixelAspectRatio, screenWindowWidth, ...) stay in the file, so that an image read can be written again.
void readAttribute(const std::string& name, const Imf::Attribute& attribute, Image& image) {
  if (std::find(kReservedAttributes.begin(), kReservedAttributes.end(), name) != kReservedAttributes.end()) return;
  if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&attribute))
    image.attributes()[name] = text->value();
  else if (const auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&attribute))
    image.numbers()[name] = d->value();
  else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&attribute))
    image.numbers()[name] = f->value();
  else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&attribute))
    image.numbers()[name] = i->value();
  else if (const auto* m = dynamic_cast<const Imf::M44fAttribute*>(&attribute)) {
    Matrix44& out = image.matrices()[name];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) out[r * 4 + c] = m->value()[r][c];
  }
}

}  // namespace

ExrCompression parseExrCompression(const std::string& name) {
  for (ExrCompression compression : kCompressions)
    if (name == exrCompressionName(compression)) return compression;
  throw std::invalid_argument(
      fmt::format("EXR compression '{}': use none, rle, zips, zip or piz (the lossless ones)", name));
}

const char* exrCompressionName(ExrCompression compression) { return compressionName(toImf(compression)); }

const char* exrPixelTypeName(ExrPixelType type) {
  switch (type) {
    case ExrPixelType::Uint:
      return "uint";
    case ExrPixelType::Half:
      return "half";
    case ExrPixelType::Float:
      return "float";
  }
  return "unknown";
}

void writeExr(const std::filesystem::path& path, const Image& image, const ExrOptions& options) {
  writeExr(path, ImageRows(image), options);
}

void writeExr(const std::filesystem::path& path, const ImageRows& image, const ExrOptions& options) {
  const Imf::Header header = makeHeader(path, image, options);
  const std::vector<std::string>& names = image.channelNames();
  const size_t width = static_cast<size_t>(image.width());
  // Whole ZIP blocks (16 rows) of every channel: the band is all the pixel memory a write needs.
  const int band = std::min(bandRows(image.width(), names.size(), options.bandBytes), image.height());
  const size_t bandValues = width * static_cast<size_t>(band);
  // A FLOAT channel the image holds is written from its own rows; a deferred one is read into a band here (allocated
  // only for such channels: fresh pages cost a fault each, as much as the copy). OutputFile converts nothing: a HALF
  // channel needs a HALF slice, so those are converted here.
  std::vector<std::vector<float>> floats(names.size());
  std::vector<std::vector<half>> halves(names.size());
  auto file = std::make_unique<PendingFile>(path);
  try {
    // The stream is named after the target so OpenEXR's own messages do not mention the temp file.
    Imf::StdOFStream stream(file->stream(), path.c_str());
    Imf::OutputFile output(stream, header);
    for (int first = 0; first < image.height(); first += band) {
      const int rows = std::min(band, image.height() - first);
      const size_t n = width * static_cast<size_t>(rows);
      Imf::FrameBuffer frame;
      for (size_t c = 0; c < names.size(); ++c) {
        std::span<const float> values = image.stored(names[c], first, rows);
        if (values.empty()) {
          floats[c].resize(bandValues);
          image.read(names[c], first, rows, std::span<float>(floats[c].data(), n));
          values = std::span<const float>(floats[c].data(), n);
        }
        const bool isHalf = options.halfChannels.count(names[c]) != 0;
        const void* pixels = values.data();
        if (isHalf) {
          halves[c].assign(values.begin(), values.end());
          pixels = halves[c].data();
        }
        const size_t pixelSize = isHalf ? sizeof(half) : sizeof(float);
        // The slice's first element is pixel (0, first): OpenEXR addresses rows by their number in the file.
        frame.insert(names[c], Imf::Slice::Make(isHalf ? Imf::HALF : Imf::FLOAT, pixels, Imath::V2i(0, first),
                                                image.width(), rows, pixelSize, pixelSize * width));
      }
      output.setFrameBuffer(frame);
      output.writePixels(rows);
    }
  } catch (const Iex::BaseExc& e) {  // the destructor of OutputFile has written the offset table
    const int error = errno;         // the failed write's, which OpenEXR's message spells out
    throw OutputError(fmt::format("{}: cannot write EXR: {}", path.string(), e.what()), error);
  }
  commitOrDefer(std::move(file), options.commitGroup);
}

Image readExr(const std::filesystem::path& path) {
  checkReadable(path);
  try {
    Imf::InputFile input(path.c_str());
    const ExrWindow window = toWindow(input.header().dataWindow());
    const long long width = static_cast<long long>(window.maxX) - window.minX + 1;
    const long long height = static_cast<long long>(window.maxY) - window.minY + 1;
    if (width <= 0 || height <= 0 || width > INT_MAX || height > INT_MAX)
      fail(path,
           fmt::format("invalid data window ({}, {}) - ({}, {})", window.minX, window.minY, window.maxX, window.maxY));
    Image image(static_cast<int>(width), static_cast<int>(height), path.string());
    for (ImageChannel& channel : readChannels(path, input, image.width(), image.height()))
      image.add(std::move(channel.name), std::move(channel.data));
    for (auto it = input.header().begin(); it != input.header().end(); ++it)
      readAttribute(it.name(), it.attribute(), image);
    return image;
  } catch (const Iex::BaseExc& e) {
    fail(path, fmt::format("cannot read EXR: {}", e.what()));
  } catch (const std::bad_alloc&) {
    fail(path, "cannot read EXR: out of memory for its data window");
  } catch (const std::length_error&) {
    fail(path, "cannot read EXR: data window too large");
  }
}

ExrInfo readExrInfo(const std::filesystem::path& path) {
  checkReadable(path);
  try {
    Imf::InputFile input(path.c_str());
    const Imf::Header& header = input.header();
    ExrInfo info;
    info.dataWindow = toWindow(header.dataWindow());
    info.displayWindow = toWindow(header.displayWindow());
    info.compression = compressionName(header.compression());
    info.tiled = header.hasTileDescription();
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
      info.channels.push_back({it.name(), toPixelType(it.channel().type)});
    for (auto it = header.begin(); it != header.end(); ++it)
      if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        info.attributes[it.name()] = text->value();
    return info;
  } catch (const Iex::BaseExc& e) {
    fail(path, fmt::format("cannot read EXR header: {}", e.what()));
  }
}

}  // namespace penumbra
