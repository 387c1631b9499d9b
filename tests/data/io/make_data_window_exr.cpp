// Generator of data_window.exr, the fixture for readExr's data-window handling: written straight
// with the OpenEXR C++ API, independently of host/io/exr.cpp. Not part of the build; regenerate with
//   g++ -std=c++17 -I/usr/include/OpenEXR -I/usr/include/Imath make_data_window_exr.cpp
//       -lOpenEXR -lImath -o /tmp/mk && /tmp/mk data_window.exr
#include <ImfChannelList.h>
#include <ImfFloatAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <half.h>

#include <cstdint>
#include <vector>

// Pixel (x, y) in absolute EXR coordinates (data window (5, 3) - (11, 7), 7x5, inside a 16x12
// display window) holds Y = x + 100 y (float), H = (x - y) / 4 (half, exact), I = x y (uint).
int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(15, 11));
  const Imath::Box2i data(Imath::V2i(5, 3), Imath::V2i(11, 7));
  const int width = data.max.x - data.min.x + 1, height = data.max.y - data.min.y + 1;
  Imf::Header header(display, data);
  header.compression() = Imf::PIZ_COMPRESSION;
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  header.channels().insert("H", Imf::Channel(Imf::HALF));
  header.channels().insert("I", Imf::Channel(Imf::UINT));
  header.insert("comment", Imf::StringAttribute("data window fixture"));
  header.insert("exposure", Imf::FloatAttribute(1.5f));  // not a string: readExr skips it
  std::vector<float> y(width * height);
  std::vector<half> h(width * height);
  std::vector<uint32_t> u(width * height);
  for (int row = 0; row < height; ++row)
    for (int col = 0; col < width; ++col) {
      const int x = data.min.x + col, yy = data.min.y + row, i = row * width + col;
      y[i] = static_cast<float>(x + 100 * yy);
      h[i] = half(0.25f * static_cast<float>(x - yy));
      u[i] = static_cast<uint32_t>(x * yy);
    }
  Imf::FrameBuffer frame;
  frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, y.data(), data));
  frame.insert("H", Imf::Slice::Make(Imf::HALF, h.data(), data));
  frame.insert("I", Imf::Slice::Make(Imf::UINT, u.data(), data));
  Imf::OutputFile file(argv[1], header);
  file.setFrameBuffer(frame);
  file.writePixels(height);
  return 0;
}
