// The frame image's header as other tools read it: OpenEXR's standard worldToCamera and worldToNDC (m44f, row
// vectors) read back through OpenEXR itself project a pixel's world position onto that pixel, and the version
// matches `penumbra --version`'s.
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "host/io/exr.h"
#include "host/io/image_rows.h"
#include "host/pipeline/renderer.h"
#include "host/scene/light.h"
#include "host/techniques/technique.h"
#include "host/version.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/analytic_scenes.h"

namespace penumbra {
namespace frame_image_test {

namespace fs = std::filesystem;

constexpr float kPixelTolerance = 1e-2f;   // pixels: float round-off of a world position rasterised and re-projected
constexpr float kCameraTolerance = 1e-4f;  // world units on a camera 8.6 units from its target

class FrameImage : public test::ClTest {};

// Two lights over the square under sm, the point light "Bulb" first (the first light's debug channels are the
// frame's: its cubeFace.Y), a top-down camera of width x height that sees them and the same camera looking up, at
// nothing.
struct TwoLights {
  Scene scene = test::squareOverPlane();
  std::vector<FrameLight> lights;
  Camera camera = test::topDown(), away;
  TwoLights(int width, int height) {
    const TechniqueInfo& sm = findTechnique("sm");
    Light point = parseLight("point:0.3,3,0.2");
    point.name = "Bulb";
    lights = {{point, &sm, Params(sm.params)}, {test::pointAbove(), &sm, Params(sm.params)}};
    camera.width = width, camera.height = height;
    away = camera;
    away.target = camera.eye + (camera.eye - camera.target);
  }
};

TEST_F(FrameImage, CameraMatricesReadBackThroughOpenExrProjectOntoThePixel) {
  const Camera camera = test::topDown();
  const TechniqueInfo& sm = findTechnique("sm");
  const Scene scene = test::squareOverPlane();  // the renderer keeps a reference: it must outlive it
  Renderer renderer(ctx(), scene);
  const RenderResult r = renderer.render(camera, test::pointAbove(), sm, Params(sm.params));
  const fs::path path = fs::temp_directory_path() / ("penumbra-frame-image-" + std::to_string(getpid()) + ".exr");
  writeExr(path, r.image);
  Imf::InputFile file(path.c_str());
  const Imf::Header& header = file.header();
  ASSERT_TRUE(Imf::hasWorldToCamera(header));
  ASSERT_TRUE(Imf::hasWorldToNDC(header));
  const Imath::M44f toCamera = Imf::worldToCamera(header), toNdc = Imf::worldToNDC(header);
  const auto* version = header.findTypedAttribute<Imf::StringAttribute>("penumbra:version");
  ASSERT_NE(version, nullptr);
  EXPECT_EQ(version->value(), std::string(penumbra::version()));
  EXPECT_EQ(readExr(path).matrices(), r.image.matrices());
  fs::remove(path);

  // The camera sits at the origin of camera space and looks down -Z at its target.
  Imath::V3f eye, target;
  toCamera.multVecMatrix(Imath::V3f(camera.eye.x, camera.eye.y, camera.eye.z), eye);
  toCamera.multVecMatrix(Imath::V3f(camera.target.x, camera.target.y, camera.target.z), target);
  EXPECT_LT(eye.length(), kCameraTolerance);
  const float distance = glm::length(camera.target - camera.eye);
  EXPECT_NEAR(target.x, 0.0f, kCameraTolerance);
  EXPECT_NEAR(target.y, 0.0f, kCameraTolerance);
  EXPECT_NEAR(target.z, -distance, kCameraTolerance);

  // Every seen pixel's world position (P.*) lands on the pixel's centre: x right, y up in NDC, rows top-down.
  const auto &px = r.image.require("P.X").data, &py = r.image.require("P.Y").data, &pz = r.image.require("P.Z").data;
  const auto& seen = r.image.require("A").data;
  int checked = 0;
  for (int y = 0; y < camera.height; y += 7)
    for (int x = 0; x < camera.width; x += 5) {
      const size_t i = static_cast<size_t>(y) * camera.width + x;
      if (seen[i] == 0.0f) continue;
      Imath::V3f ndc;
      toNdc.multVecMatrix(Imath::V3f(px[i], py[i], pz[i]), ndc);  // with the divide by w
      EXPECT_NEAR((ndc.x + 1.0f) * 0.5f * camera.width, x + 0.5f, kPixelTolerance) << x << "," << y;
      EXPECT_NEAR((1.0f - ndc.y) * 0.5f * camera.height, y + 0.5f, kPixelTolerance) << x << "," << y;
      EXPECT_GT(ndc.z, -1.0f);
      EXPECT_LT(ndc.z, 1.0f);
      ++checked;
    }
  double sum = 0;
  for (float a : seen) sum += a;
  EXPECT_GT(checked, 100) << "A sum " << sum << " of " << seen.size() << " P.Y[0] " << py[0];
}

// The float4 buffers come down in bands of 65,536 pixels (frame_image.cpp): at 400x300 the frame spans two, and
// every ground pixel's P.X must still grow along its row (a band read to the wrong place breaks the order) with its
// normal straight up.
TEST_F(FrameImage, ChannelsStayInPlaceAcrossDownloadBands) {
  Camera camera = test::topDown();
  camera.width = 400, camera.height = 300;
  const TechniqueInfo& sm = findTechnique("sm");
  const Scene scene = test::squareOverPlane();
  Renderer renderer(ctx(), scene);
  const Image image = renderer.render(camera, test::pointAbove(), sm, Params(sm.params)).image;
  const auto& px = image.require("P.X").data;
  const auto& py = image.require("P.Y").data;
  const auto& ny = image.require("N.Y").data;
  const auto& alpha = image.require("A").data;
  size_t ground[2] = {0, 0};  // before and after the first band's end
  for (int y = 0; y < camera.height; ++y) {
    float last = -INFINITY;
    for (int x = 0; x < camera.width; ++x) {
      const size_t i = static_cast<size_t>(y) * camera.width + x;
      if (alpha[i] != 1.0f || std::abs(py[i]) > 1e-3f) continue;  // the ground plane y = 0 alone
      ++ground[i >= 65536];
      EXPECT_GT(px[i], last) << x << "," << y;
      EXPECT_NEAR(std::abs(ny[i]), 1.0f, 1e-4f) << x << "," << y;
      last = px[i];
    }
  }
  EXPECT_GT(ground[0], 1000u);  // both bands were checked
  EXPECT_GT(ground[1], 1000u);
}

// FrameDownload::Deferred: the same channels, header and warnings as the whole Image, bit for bit, read in bands that
// are no multiple of the height; with two lights (one a point light: its cubeFace.Y debug channel stays a host
// channel) and for a frame that sees nothing.
TEST_F(FrameImage, DeferredChannelsEqualTheWholeImage) {
  const TwoLights frame(97, 61);
  const Scene& scene = frame.scene;
  const Camera &camera = frame.camera, &away = frame.away;
  const std::vector<FrameLight>& lights = frame.lights;
  for (const bool seesScene : {true, false}) {
    const Camera& view = seesScene ? camera : away;
    Renderer whole(ctx(), scene), deferred(ctx(), scene);
    const RenderResult a = whole.render(view, lights);
    const RenderResult b = deferred.render(view, lights, FrameDownload::Deferred);
    EXPECT_EQ(a.warnings, b.warnings);
    EXPECT_EQ(a.warnings.empty(), seesScene);
    EXPECT_EQ(a.image.attributes(), b.image.attributes());
    EXPECT_EQ(a.image.matrices(), b.image.matrices());
    EXPECT_EQ(b.image.channelNames(), std::vector<std::string>{"cubeFace.Y"});
    const ImageRows rows(b.image, b.deferred);
    std::vector<std::string> names = rows.channelNames(), expected = a.image.channelNames();
    std::sort(names.begin(), names.end());
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(names, expected);
    for (const ImageChannel& channel : a.image.channels()) {
      std::vector<float> values(a.image.pixelCount());
      for (int first = 0; first < camera.height; first += 16) {
        const int count = std::min(16, camera.height - first);
        rows.read(channel.name, first, count,
                  std::span<float>(values).subspan(static_cast<size_t>(first) * camera.width,
                                                   static_cast<size_t>(count) * camera.width));
      }
      EXPECT_EQ(std::memcmp(values.data(), channel.data.data(), values.size() * sizeof(float)), 0) << channel.name;
    }
  }
}

// FrameOutputs: a frame of the visibility alone (bench's) has each light's visibility bit for bit as the whole frame
// has it, and nothing else: no R, G, B, A (and no shading pass), no P, N, depth, no debug channels (the point light's
// cubeFace.Y); the same whether downloaded whole or deferred; a frame that sees nothing still warns.
TEST_F(FrameImage, OutputsLeaveOutWhatTheCallerDoesNotRead) {
  const TwoLights frame(53, 40);
  const Scene& scene = frame.scene;
  const Camera &camera = frame.camera, &away = frame.away;
  const std::vector<FrameLight>& lights = frame.lights;
  for (const bool seesScene : {true, false}) {
    const Camera& view = seesScene ? camera : away;
    Renderer whole(ctx(), scene), bare(ctx(), scene), deferred(ctx(), scene);
    const RenderResult a = whole.render(view, lights);
    std::vector<std::string> visibility;  // visibility.Y and each light's layer
    for (const std::string& name : a.image.channelNames())
      if (name.starts_with("visibility.")) visibility.push_back(name);
    std::sort(visibility.begin(), visibility.end());
    ASSERT_EQ(visibility.size(), 3u);
    const RenderResult b = bare.render(view, lights, FrameDownload::Image, FrameOutputs::visibilityOnly());
    const RenderResult c = deferred.render(view, lights, FrameDownload::Deferred, FrameOutputs::visibilityOnly());
    EXPECT_EQ(a.warnings, b.warnings);
    EXPECT_EQ(a.warnings, c.warnings);
    EXPECT_EQ(a.image.attributes(), b.image.attributes());
    EXPECT_TRUE(b.preview.empty());
    EXPECT_TRUE(c.preview.empty());
    std::vector<std::string> names = b.image.channelNames();
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, visibility);
    EXPECT_TRUE(c.image.channelNames().empty());
    names = ImageRows(c.image, c.deferred).channelNames();
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, visibility);
    for (const std::string& name : visibility) {
      const std::vector<float>&ours = b.image.require(name).data, &full = a.image.require(name).data;
      ASSERT_EQ(ours.size(), full.size()) << name;
      EXPECT_EQ(std::memcmp(ours.data(), full.data(), ours.size() * sizeof(float)), 0) << name;
    }
    for (const RenderResult* r : {&a, &b}) {
      bool shaded = false;
      for (const PassTime& pass : r->passes) shaded |= pass.name.starts_with("shade/shade_");
      EXPECT_EQ(shaded, r == &a) << "seesScene " << seesScene;
    }
  }
  // The preview alone left out keeps the surfaces and the debug channels.
  Renderer renderer(ctx(), scene);
  const RenderResult d = renderer.render(camera, lights, FrameDownload::Image, {false, true, true});
  EXPECT_EQ(d.image.find("R"), nullptr);
  EXPECT_NE(d.image.find("P.X"), nullptr);
  EXPECT_NE(d.image.find("cubeFace.Y"), nullptr);
}

}  // namespace frame_image_test
}  // namespace penumbra
