// The C++ API (header-only over the C API): handles that retain on copy and release on destruction, penumbra::Error
// with the C API's status and message, defaults equal to the C structs' initialisers (so the two layers cannot
// drift), and a frame whose device buffer feeds a stage, all on the caller's OpenCL objects.
#include <cmath>
#include <cstring>
#include <penumbra/penumbra.hpp>
#include <string>
#include <vector>

#include "tests/api/caller_cl.h"

namespace penumbra::test {
namespace cpp_api_test {

TEST(ApiCpp, ErrorsCarryTheStatusAndMessage) {
  try {
    Params params("nope");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), PN_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(e.what(), pn_last_error_message());
    EXPECT_NE(std::string(e.what()).find("unknown technique 'nope' (known: sm, pcf, pcss"), std::string::npos);
  }
  try {
    Scene scene("no/such/scene.json");
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.status(), PN_ERROR_SCENE);
  }
  EXPECT_EQ(version(), PN_VERSION_STRING);
}

TEST(ApiCpp, DefaultsAreTheCApis) {
  pn_camera c;
  pn_camera_init(&c);
  const pn_camera fromCpp = Camera().toC();
  EXPECT_EQ(std::memcmp(&c, &fromCpp, sizeof(c)), 0);
  pn_light l;
  pn_light_init(&l);
  const Light light;
  EXPECT_EQ(light.toC().size, l.size);
  EXPECT_EQ(light.type, LightType::Spot);
  EXPECT_EQ(light.fovDeg, l.fov_deg);
  EXPECT_EQ(light.position[1], l.position[1]);
  pn_moments_config m;
  pn_moments_config_init(&m);
  const pn_moments_config mc = MomentsConfig().toC();
  EXPECT_EQ(mc.kind, m.kind);
  EXPECT_EQ(mc.depth_far, m.depth_far);
  EXPECT_EQ(mc.evsm_positive, m.evsm_positive);
  EXPECT_EQ(mc.evsm_negative, m.evsm_negative);
  EXPECT_EQ(mc.esm_exponent, m.esm_exponent);
  pn_blur_config b;
  pn_blur_config_init(&b);
  const pn_blur_config bc = BlurConfig().toC();
  EXPECT_EQ(std::memcmp(&b, &bc, sizeof(b)), 0);
  pn_sat_config s;
  pn_sat_config_init(&s);
  const pn_sat_config sc = SatConfig().toC();
  // Field by field: the struct ends in padding (44 bytes of fields in 48) that no initialiser defines.
  EXPECT_EQ(sc.size, s.size);
  EXPECT_EQ(sc.precision, s.precision);
  EXPECT_EQ(sc.algorithm, s.algorithm);
  EXPECT_EQ(sc.fraction_bits, s.fraction_bits);
  EXPECT_EQ(sc.zero_mean, s.zero_mean);
  EXPECT_EQ(sc.has_offset, s.has_offset);
  EXPECT_EQ(std::memcmp(sc.offset, s.offset, sizeof(s.offset)), 0);
}

TEST(ApiCpp, HandlesRetainOnCopyAndReleaseOnDestruction) {
  CallerCl cl;
  const cl_uint context0 = references(cl.context);
  {
    Context ctx(cl.context, cl.device, cl.queue);
    Context copy = ctx;  // one pn_context, one retain of the caller's context
    EXPECT_EQ(copy.get(), ctx.get());
    EXPECT_EQ(settled(cl.context, context0 + 1), context0 + 1);
    Scene scene("builtin:single-triangle");
    Renderer renderer(copy, scene);
    Camera camera = scene.defaultCamera();
    camera.width = 32, camera.height = 24;
    Frame frame = renderer.render(camera, Params("sm"));
    EXPECT_EQ(frame.width(), 32);
    EXPECT_EQ(frame.attribute("penumbra:technique").value_or(""), "sm");
    EXPECT_FALSE(frame.attribute("nope").has_value());
  }
  clFinish(cl.queue);
  EXPECT_EQ(settled(cl.context, context0), context0);
}

// The frame's device buffer straight into a stage, on the caller's queue, with the caller waiting on the event.
// builtin:box on the caller's OpenCL objects, its default camera at 40x30.
class ApiCppBox : public ::testing::Test {
 protected:
  static Camera smallCamera(const Scene& scene) {
    Camera camera = scene.defaultCamera();
    camera.width = 40, camera.height = 30;
    return camera;
  }
  CallerCl cl;
  Context ctx{cl.context, cl.device, cl.queue};
  Scene scene{"builtin:box"};
  Renderer renderer{ctx, scene};
  Camera camera = smallCamera(scene);
};

TEST_F(ApiCppBox, AFramesBufferFeedsAStage) {
  Params params("pcf");
  params.set("pcf-radius", 1);
  EXPECT_EQ(params.value("pcf-radius"), 1.0);
  const Frame frame = renderer.render(camera, scene.lights().front(), params);
  const size_t n = 40 * 30;
  cl_mem table = cl.buffer<uint64_t>(n);
  SatConfig config;
  config.precision = SatPrecision::Fixed64;
  cl_event done = nullptr;
  sat(ctx, frame.visibilityBuffer(), {40, 30, 1}, config, table, nullptr, {}, &done);
  ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
  clReleaseEvent(done);
  // The same visibility unpacked with rows from the top by imageCopy: the host channel's order.
  cl_mem topDown = cl.buffer<float>(n);
  imageCopy(ctx, {frame.visibilityBuffer(), 0, 0, 0}, {topDown, 0, 0, 1}, 40, 30, 1, {}, &done);
  ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
  clReleaseEvent(done);
  EXPECT_EQ(std::memcmp(cl.read<float>(topDown, n).data(), frame.channel("visibility.Y"), n * sizeof(float)), 0);
  clReleaseMemObject(topDown);
  const std::vector<uint64_t> got = cl.read<uint64_t>(table, n);
  const float* visibility = frame.channel("visibility.Y");
  double sum = 0;
  for (size_t i = 0; i < n; ++i) sum += std::nearbyint(std::ldexp(double(visibility[i]), 32));
  EXPECT_EQ(double(got.back()), sum);  // the whole frame's sum, exact in fixed point (row order does not matter)
  clReleaseMemObject(table);
}

// penumbra::Shader on a frame's G-buffer and a map of the caller's: a map with nothing drawn lights every pixel, one
// drawn at its near plane in front of everything the light sees shadows every pixel inside its frustum.
TEST_F(ApiCppBox, AShaderShadesFromTheCallersMap) {
  const Frame frame = renderer.render(camera, Params("sm"));
  constexpr uint32_t kSize = 64;
  const size_t n = 40 * 30;
  ShadeDesc desc;
  pn_shade_desc c;
  pn_shade_desc_init(&c);
  EXPECT_EQ(std::memcmp(static_cast<const pn_shade_desc*>(&desc), &c, sizeof(c)), 0);
  // A sun straight down over the box: an orthographic map 40 units wide from y = 20 down to y = -20.
  const float view[16] = {1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, -20, 1};  // eye (0, 20, 0) looking down -y
  const float projection[16] = {0.05f, 0, 0, 0, 0, 0.05f, 0, 0, 0, 0, -0.05f, 0, 0, 0, -1, 1};  // glm::ortho, 0..40
  std::memcpy(desc.light_view, view, sizeof(view));
  std::memcpy(desc.light_projection, projection, sizeof(projection));
  desc.light_type = PN_LIGHT_DIRECTIONAL;
  desc.light_map_size = kSize;
  desc.width = 40, desc.height = 30;
  desc.positions.memory = frame.deviceBuffer(PN_FRAME_POSITION);
  cl_mem out = cl.buffer<float>(n, nullptr, NAN);
  desc.visibility.memory = out;
  const Shader shader(ctx);
  const Params sm("sm");
  for (const float texel : {1.0f, 0.0f}) {  // cleared (empty), then everything at the near plane
    cl_mem map = cl.buffer<float>(size_t(kSize) * kSize, nullptr, texel);
    desc.light_depth.memory = map;
    cl_event done = nullptr;
    shader.shade(sm, desc, {}, &done);
    ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
    clReleaseEvent(done);
    const std::vector<float> got = cl.read<float>(out, n);
    const float* seen = frame.channel("A");  // rows top-down; `got`'s from the bottom
    size_t wrong = 0;
    for (size_t i = 0; i < n; ++i) {
      const bool background = seen[(29 - i / 40) * 40 + i % 40] == 0.0f;
      wrong += got[i] != (texel == 1.0f || background ? 1.0f : 0.0f);
    }
    EXPECT_EQ(wrong, 0u) << "map texels " << texel;
    clReleaseMemObject(map);
  }
  EXPECT_EQ(shader.attribute("penumbra:light-fit").value_or("").rfind("caller 64x64", 0), 0u);
  EXPECT_FALSE(shader.attribute("no such attribute").has_value());
  std::string reason;
  EXPECT_TRUE(takesCallerMap("vssm", &reason));
  EXPECT_FALSE(takesCallerMap("jittered", &reason));
  EXPECT_NE(reason.find("jitter"), std::string::npos);
  clReleaseMemObject(out);
}

// Renderer::enqueue: the visibility into the caller's buffer after its event, channels on request, the same bits as
// render(); RenderOptions' defaults are pn_render_options_init's.
TEST_F(ApiCppBox, AnEnqueuedFrameEqualsARenderedOne) {
  const Params params("pcf");
  const Frame rendered = renderer.render(camera, params);
  pn_render_options c;
  pn_render_options_init(&c);
  const pn_render_options defaults = RenderOptions{}.toC();
  EXPECT_EQ(defaults.channels, c.channels);
  EXPECT_EQ(defaults.visibility_count, c.visibility_count);
  RenderOptions options;
  cl_mem out = cl.buffer<float>(40 * 30);
  options.visibility = {out};
  cl_event done = nullptr;
  const Frame enqueued =
      renderer.enqueue(camera, {{scene.lights().front(), std::nullopt}}, &params, options, {}, &done);
  ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
  clReleaseEvent(done);
  EXPECT_EQ(enqueued.visibilityBuffer(), out);
  const std::vector<float> got = cl.read<float>(out, 40 * 30);
  const float* want = rendered.channel("visibility.Y");  // rows top-down
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) ASSERT_EQ(got[y * 40 + x], want[(29 - y) * 40 + x]) << x << "," << y;
  EXPECT_EQ(std::memcmp(enqueued.channel("N.Y"), rendered.channel("N.Y"), 40 * 30 * sizeof(float)), 0);
  clReleaseMemObject(out);
}

}  // namespace cpp_api_test
}  // namespace penumbra::test
