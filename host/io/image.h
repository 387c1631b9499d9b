// Image: the project's multi-channel float picture for outputs and comparisons (EXR, PNG, tests).
// Layout: every channel is width*height floats, row-major, row 0 = the TOP row of the picture (file
// order, as in EXR with INCREASING_Y). Renderers that produce bottom-up rows call flipRows() first.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace penumbra {

// A 4x4 matrix in OpenEXR's layout and convention (Imath::M44f): m[row * 4 + col], points as row vectors
// (p' = p M). A glm::mat4 for column vectors (p' = M p) has exactly this memory layout, so glm::value_ptr copies.
using Matrix44 = std::array<float, 16>;

struct ImageChannel {
  std::string name;         // EXR layer convention: "R", "visibility.Y", "P.X", "depth.Z"
  std::vector<float> data;  // width*height values, row 0 at the top
};

class Image {
 public:
  Image() = default;
  // Throws std::invalid_argument for a negative size. `source` names the image in error messages
  // (the file it came from or will go to); it may be empty.
  Image(int width, int height, std::string source = {});

  int width() const { return width_; }
  int height() const { return height_; }
  size_t pixelCount() const { return static_cast<size_t>(width_) * static_cast<size_t>(height_); }
  bool empty() const { return pixelCount() == 0; }

  const std::string& source() const { return source_; }
  void setSource(std::string source) { source_ = std::move(source); }

  // Channels in the order they were added (readExr: the file's order, which EXR sorts by name).
  const std::vector<ImageChannel>& channels() const { return channels_; }
  std::vector<std::string> channelNames() const;

  // Free-form provenance (technique, parameters, device, ...): written as EXR string attributes.
  std::map<std::string, std::string>& attributes() { return attributes_; }
  const std::map<std::string, std::string>& attributes() const { return attributes_; }
  // Typed header attributes: numbers (EXR double) and matrices (EXR m44f, e.g. the standard worldToCamera and
  // worldToNDC). A name is in at most one of attributes(), numbers() and matrices() (writeExr checks).
  std::map<std::string, double>& numbers() { return numbers_; }
  const std::map<std::string, double>& numbers() const { return numbers_; }
  std::map<std::string, Matrix44>& matrices() { return matrices_; }
  const std::map<std::string, Matrix44>& matrices() const { return matrices_; }

  // Throws std::invalid_argument naming the image and channel when `data` is not width*height
  // values, the name is empty, or a channel of that name exists already.
  void add(std::string name, std::vector<float> data);
  // A channel of width*height copies of `value`.
  void addFilled(std::string name, float value);

  // nullptr when absent. Pointers stay valid until the next add().
  const ImageChannel* find(std::string_view name) const;
  ImageChannel* find(std::string_view name);
  // Like find(), but a missing channel throws std::runtime_error naming the image, the channel and
  // the channels it does have.
  const ImageChannel& require(std::string_view name) const;

  // Flips every channel upside down (bottom-up rows <-> top-down rows).
  void flipRows();

 private:
  int width_ = 0;
  int height_ = 0;
  std::string source_;
  std::vector<ImageChannel> channels_;
  std::map<std::string, std::string> attributes_;
  std::map<std::string, double> numbers_;
  std::map<std::string, Matrix44> matrices_;
};

// Reverses the row order of one width*height plane in place; for renderer output (bottom row
// first, as OpenGL/OpenCL framebuffers come out) before it goes into an Image. Throws
// std::invalid_argument when data.size() != width*height.
void flipRows(std::span<float> data, int width, int height);

}  // namespace penumbra
