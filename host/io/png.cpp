// PNG previews: exposure, un-premultiply, sRGB encode, 8-bit quantise; libpng encodes row by row into a PendingFile,
// so a preview is never whole in memory (its channels are read in bands, from device buffers for a frame). Viridis is
// every 8th entry of matplotlib's 256-entry _viridis_data plus the last, interpolated linearly: within two 8-bit codes
// of the full table.
#include "host/io/png.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host/io/atomic_file.h"

namespace penumbra {
namespace {

struct ViridisKnot {
  int index;  // position in the 256-entry table, i.e. t = index / 255
  float r, g, b;
};

constexpr ViridisKnot kViridis[] = {
    {0, 0.267004f, 0.004874f, 0.329415f},   {8, 0.277018f, 0.050344f, 0.375715f},
    {16, 0.282327f, 0.094955f, 0.417331f},  {24, 0.282884f, 0.135920f, 0.453427f},
    {32, 0.278826f, 0.175490f, 0.483397f},  {40, 0.270595f, 0.214069f, 0.507052f},
    {48, 0.258965f, 0.251537f, 0.524736f},  {56, 0.244972f, 0.287675f, 0.537260f},
    {64, 0.229739f, 0.322361f, 0.545706f},  {72, 0.214298f, 0.355619f, 0.551184f},
    {80, 0.199430f, 0.387607f, 0.554642f},  {88, 0.185556f, 0.418570f, 0.556753f},
    {96, 0.172719f, 0.448791f, 0.557885f},  {104, 0.160665f, 0.478540f, 0.558115f},
    {112, 0.149039f, 0.508051f, 0.557250f}, {120, 0.137770f, 0.537492f, 0.554906f},
    {128, 0.127568f, 0.566949f, 0.550556f}, {136, 0.120565f, 0.596422f, 0.543611f},
    {144, 0.120638f, 0.625828f, 0.533488f}, {152, 0.132268f, 0.655014f, 0.519661f},
    {160, 0.157851f, 0.683765f, 0.501686f}, {168, 0.196571f, 0.711827f, 0.479221f},
    {176, 0.246070f, 0.738910f, 0.452024f}, {184, 0.304148f, 0.764704f, 0.419943f},
    {192, 0.369214f, 0.788888f, 0.382914f}, {200, 0.440137f, 0.811138f, 0.340967f},
    {208, 0.515992f, 0.831158f, 0.294279f}, {216, 0.595839f, 0.848717f, 0.243329f},
    {224, 0.678489f, 0.863742f, 0.189503f}, {232, 0.762373f, 0.876424f, 0.137064f},
    {240, 0.845561f, 0.887322f, 0.099702f}, {248, 0.926106f, 0.897330f, 0.104071f},
    {255, 0.993248f, 0.906157f, 0.143936f},
};
constexpr int kViridisKnots = static_cast<int>(std::size(kViridis));
static_assert(kViridisKnots == 33 && kViridis[kViridisKnots - 1].index == 255,
              "knots every 8 entries, ending at t = 1");

std::uint8_t quantise(float encoded) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(encoded, 0.0f, 1.0f) * 255.0f));
}

// libpng row by row into a PendingFile. libpng reports errors by longjmp: the error handler keeps the message and
// jumps back into one of the small wrappers below (start, writeRow, end), whose frames hold no object with a
// destructor, and the wrapper's caller throws.
class PngRowWriter {
 public:
  PngRowWriter(const std::filesystem::path& path, int width, int height, int components)
      : target_(path), file_(std::make_unique<PendingFile>(path)), width_(width), components_(components) {
    png_.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, this, onError, onWarning);
    if (png_.png != nullptr) png_.info = png_create_info_struct(png_.png);
    if (png_.png == nullptr || png_.info == nullptr) fail("cannot create the PNG encoder (out of memory)");
    png_set_write_fn(png_.png, this, onWrite, onFlush);
    if (!start(png_.png, png_.info, width, height, components == 4 ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB))
      fail(message_);
  }
  PngRowWriter(const PngRowWriter&) = delete;
  PngRowWriter& operator=(const PngRowWriter&) = delete;

  int rowBytes() const { return width_ * components_; }
  // One row of width * components bytes, top row first.
  void row(const std::uint8_t* pixels) {
    if (!writeRow(png_.png, pixels)) fail(message_);
  }
  // After the last row: the file's end, then the rename over the target (now, or by `group`'s commit).
  void finish(CommitGroup* group = nullptr) {
    if (!end(png_.png, png_.info)) fail(message_);
    commitOrDefer(std::move(file_), group);
  }

 private:
  [[noreturn]] void fail(const char* why) const {
    throw OutputError(fmt::format("{}: cannot write PNG: {}", target_.string(), why), writeErrno_);
  }
  static PngRowWriter& self(png_structp png) { return *static_cast<PngRowWriter*>(png_get_error_ptr(png)); }
  static void onError(png_structp png, png_const_charp message) {
    std::snprintf(self(png).message_, sizeof(message_), "%s", message);
    png_longjmp(png, 1);
  }
  static void onWarning(png_structp, png_const_charp) {}
  static void onWrite(png_structp png, png_bytep data, size_t size) {
    PendingFile& file = *static_cast<PngRowWriter*>(png_get_io_ptr(png))->file_;
    if (!file.write(data, size)) {
      const int error = errno;
      static_cast<PngRowWriter*>(png_get_io_ptr(png))->writeErrno_ = error;
      char why[160];
      std::snprintf(why, sizeof(why), "write failed: %s", error != 0 ? std::strerror(error) : "stream error");
      png_error(png, why);
    }
  }
  static void onFlush(png_structp) {}
  static bool start(png_structp png, png_infop info, int width, int height, int colourType) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, colourType,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    return true;
  }
  static bool writeRow(png_structp png, const std::uint8_t* pixels) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_write_row(png, pixels);
    return true;
  }
  static bool end(png_structp png, png_infop info) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_write_end(png, info);
    return true;
  }

  struct Encoder {  // released however the constructor or a write ends
    png_structp png = nullptr;
    png_infop info = nullptr;
    ~Encoder() { png_destroy_write_struct(&png, &info); }
  };

  std::filesystem::path target_;
  std::unique_ptr<PendingFile> file_;
  int writeErrno_ = 0;  // errno of a failed write, for OutputError
  int width_, components_;
  Encoder png_;
  char message_[256] = "unknown libpng error";
};

// The channels a preview reads: R, G, B and A when present, or the grey channel three times (opaque). An absent one
// is named with the output being written.
struct PreviewSources {
  std::string r, g, b, a;  // a empty: opaque
};

PreviewSources previewSources(const std::filesystem::path& path, const ImageRows& image, const PngOptions& options) {
  auto require = [&](const std::string& name) {
    if (!image.has(name))
      throw std::runtime_error(fmt::format("{}: cannot preview: {}: no channel '{}' (channels: {})", path.string(),
                                           image.header().source().empty() ? "image" : image.header().source(), name,
                                           fmt::join(image.channelNames(), ", ")));
    return name;
  };
  if (!options.greyChannel.empty()) {
    const std::string grey = require(options.greyChannel);
    return {grey, grey, grey, {}};
  }
  return {require("R"), require("G"), require("B"), image.has("A") ? "A" : ""};
}

// Writes 3 or 4 bytes at `out`. Colour is premultiplied (EXR convention); PNG wants straight alpha.
void encodePixel(float r, float g, float b, float a, bool hasAlpha, float scale, std::uint8_t* out) {
  if (std::isnan(r) || std::isnan(g) || std::isnan(b) || std::isnan(a)) {
    out[0] = kNanColour[0], out[1] = kNanColour[1], out[2] = kNanColour[2];
    if (hasAlpha) out[3] = 255;
    return;
  }
  const float unpremultiply = hasAlpha && a > 0.0f ? 1.0f / a : 1.0f;
  out[0] = srgbByte(r * unpremultiply * scale);
  out[1] = srgbByte(g * unpremultiply * scale);
  out[2] = srgbByte(b * unpremultiply * scale);
  if (hasAlpha) out[3] = unormByte(a);
}

}  // namespace

float srgbEncode(float linear) {
  if (std::isnan(linear)) return linear;
  const float x = std::clamp(linear, 0.0f, 1.0f);
  if (x <= 0.0031308f) return 12.92f * x;
  return 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

std::uint8_t srgbByte(float linear) {
  if (std::isnan(linear)) return 0;
  return quantise(srgbEncode(linear));
}

std::uint8_t unormByte(float value) {
  if (std::isnan(value)) return 0;
  return quantise(value);
}

Rgb8 viridis(float t) {
  if (std::isnan(t)) return kNanColour;
  const float position = std::clamp(t, 0.0f, 1.0f) * 255.0f;
  // The knots are 8 entries apart except the last interval (248..255).
  const int knot = std::min(static_cast<int>(position) / 8, kViridisKnots - 2);
  const ViridisKnot& a = kViridis[knot];
  const ViridisKnot& b = kViridis[knot + 1];
  const float f = (position - static_cast<float>(a.index)) / static_cast<float>(b.index - a.index);
  return {quantise(a.r + f * (b.r - a.r)), quantise(a.g + f * (b.g - a.g)), quantise(a.b + f * (b.b - a.b))};
}

Rgb8 falseColour(float value, float lo, float hi) {
  if (std::isnan(value)) return kNanColour;
  if (!(hi > lo)) return viridis(value > hi ? 1.0f : 0.0f);  // degenerate range: a step at hi
  // In double so that a range as wide as [-FLT_MAX, FLT_MAX] does not overflow.
  const double t = (static_cast<double>(value) - lo) / (static_cast<double>(hi) - lo);
  return viridis(static_cast<float>(std::clamp(t, 0.0, 1.0)));
}

void writePngPreview(const std::filesystem::path& path, const Image& image, const PngOptions& options) {
  writePngPreview(path, ImageRows(image), options);
}

void writePngPreview(const std::filesystem::path& path, const ImageRows& image, const PngOptions& options) {
  if (image.empty())
    throw std::invalid_argument(
        fmt::format("{}: cannot write an empty {}x{} image", path.string(), image.width(), image.height()));
  if (!std::isfinite(options.exposure))
    throw std::invalid_argument(fmt::format("{}: exposure {} is not finite", path.string(), options.exposure));
  const PreviewSources src = previewSources(path, image, options);
  const bool hasAlpha = !src.a.empty();
  const int components = hasAlpha ? 4 : 3;
  const float scale = std::exp2(options.exposure);
  const size_t width = static_cast<size_t>(image.width());
  const int band = bandRows(image.width(), 4, options.bandBytes, 1);
  std::vector<float> r, g, b, a;
  std::vector<std::uint8_t> row(width * static_cast<size_t>(components));
  PngRowWriter png(path, image.width(), image.height(), components);
  for (int first = 0; first < image.height(); first += band) {
    const int rows = std::min(band, image.height() - first);
    const size_t n = width * static_cast<size_t>(rows);
    auto fetch = [&](const std::string& channel, std::vector<float>& values) {
      values.resize(n);
      image.read(channel, first, rows, values);
    };
    fetch(src.r, r);
    if (src.g == src.r) {  // a grey preview reads its channel once
      g = r;
      b = r;
    } else {
      fetch(src.g, g);
      fetch(src.b, b);
    }
    if (hasAlpha) fetch(src.a, a);
    for (int y = 0; y < rows; ++y) {
      for (size_t x = 0; x < width; ++x) {
        const size_t i = static_cast<size_t>(y) * width + x;
        encodePixel(r[i], g[i], b[i], hasAlpha ? a[i] : 1.0f, hasAlpha, scale, &row[x * components]);
      }
      png.row(row.data());
    }
  }
  png.finish(options.commitGroup);
}

void writePngFalseColour(const std::filesystem::path& path, int width, int height, std::span<const float> values,
                         float lo, float hi) {
  if (width <= 0 || height <= 0 || values.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw std::invalid_argument(
        fmt::format("{}: {} values for a {}x{} false-colour image", path.string(), values.size(), width, height));
  if (std::isnan(lo) || std::isnan(hi) || lo > hi)
    throw std::invalid_argument(fmt::format("{}: invalid false-colour range [{}, {}]", path.string(), lo, hi));
  std::vector<std::uint8_t> row(static_cast<size_t>(width) * 3);
  PngRowWriter png(path, width, height, 3);
  for (size_t y = 0; y < static_cast<size_t>(height); ++y) {
    for (size_t x = 0; x < static_cast<size_t>(width); ++x) {
      const Rgb8 colour = falseColour(values[y * static_cast<size_t>(width) + x], lo, hi);
      std::copy(colour.begin(), colour.end(), row.begin() + static_cast<std::ptrdiff_t>(x * 3));
    }
    png.row(row.data());
  }
  png.finish();
}

}  // namespace penumbra
