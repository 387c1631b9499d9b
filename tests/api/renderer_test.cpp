// The C API's renderer on the caller's context: frames as host channels and as cl_mem in the caller's cl_context
// (the same values, rows bottom-up), snapshots that outlive their renderer, the same bits as on penumbra's own
// context, the caller's reference counts where they began, and errors that say what is wrong.
#include <penumbra/penumbra.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/api/caller_cl.h"

namespace penumbra::test {
namespace renderer_test {

constexpr int kWidth = 64, kHeight = 48;

struct Rendered {
  pn_scene* scene = nullptr;
  pn_params* params = nullptr;
  pn_renderer* renderer = nullptr;
  ~Rendered() {
    pn_renderer_release(renderer);
    pn_params_release(params);
    pn_scene_release(scene);
  }
};

// The scene's default camera at kWidth x kHeight.
pn_camera boxCamera(const Rendered& r) {
  pn_camera camera;
  pn_camera_init(&camera);
  EXPECT_EQ(pn_scene_default_camera(r.scene, &camera), PN_SUCCESS);
  camera.width = kWidth, camera.height = kHeight;
  return camera;
}

// builtin:box at 64x48 with `technique`, the scene's default camera and lights.
pn_frame* renderBox(pn_context* ctx, const char* technique, Rendered& r) {
  EXPECT_EQ(pn_scene_load("builtin:box", nullptr, &r.scene), PN_SUCCESS) << pn_last_error_message();
  EXPECT_EQ(pn_params_create(technique, &r.params), PN_SUCCESS);
  EXPECT_EQ(pn_renderer_create(ctx, r.scene, &r.renderer), PN_SUCCESS) << pn_last_error_message();
  const pn_camera camera = boxCamera(r);
  pn_frame* frame = nullptr;
  EXPECT_EQ(pn_renderer_render(r.renderer, &camera, nullptr, 0, r.params, &frame), PN_SUCCESS)
      << pn_last_error_message();
  return frame;
}

std::vector<float> channel(const pn_frame* frame, const char* name) {
  const float* data = nullptr;
  EXPECT_EQ(pn_frame_channel(frame, name, &data), PN_SUCCESS) << pn_last_error_message();
  return data == nullptr ? std::vector<float>{} : std::vector<float>(data, data + size_t(kWidth) * kHeight);
}

std::vector<float> flipped(std::vector<float> rows) {
  for (int y = 0; y < kHeight / 2; ++y)
    std::swap_ranges(rows.begin() + y * kWidth, rows.begin() + (y + 1) * kWidth, rows.end() - (y + 1) * kWidth);
  return rows;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Component `c` of a device buffer of float4s, read back.
std::vector<float> component(const std::vector<cl_float4>& values, int c) {
  std::vector<float> out;
  for (const cl_float4& v : values) out.push_back(v.s[c]);
  return out;
}

// The frame's device preview and G-buffer in the caller's context hold its host channels bit for bit (rows
// bottom-up); an unknown output is refused.
void expectDeviceOutputs(CallerCl& cl, const pn_frame* frame) {
  const size_t count = size_t(kWidth) * kHeight;
  const struct {
    pn_frame_output output;
    const char* channels[4];
  } outputs[] = {{PN_FRAME_PREVIEW, {"R", "G", "B", "A"}},
                 {PN_FRAME_POSITION, {"P.X", "P.Y", "P.Z", nullptr}},
                 {PN_FRAME_NORMAL, {"N.X", "N.Y", "N.Z", nullptr}}};
  for (const auto& o : outputs) {
    cl_mem buffer = nullptr;
    PN_ASSERT_OK(pn_frame_device_buffer(frame, o.output, &buffer));
    cl_context owner = nullptr;
    clGetMemObjectInfo(buffer, CL_MEM_CONTEXT, sizeof(owner), &owner, nullptr);
    EXPECT_EQ(owner, cl.context);
    const std::vector<cl_float4> values = cl.read<cl_float4>(buffer, count);
    for (int c = 0; c < 4 && o.channels[c] != nullptr; ++c)
      EXPECT_TRUE(sameBits(component(values, c), flipped(channel(frame, o.channels[c])))) << o.channels[c];
  }
  cl_mem depth = nullptr;
  PN_ASSERT_OK(pn_frame_device_buffer(frame, PN_FRAME_DEPTH, &depth));
  EXPECT_TRUE(sameBits(cl.read<float>(depth, count), flipped(channel(frame, "depth.Z"))));
  cl_mem none = nullptr;
  EXPECT_EQ(pn_frame_device_buffer(frame, static_cast<pn_frame_output>(7), &none), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("output 7 is none of"), std::string::npos);
  EXPECT_EQ(none, nullptr);
}

TEST(ApiRenderer, FramesOnTheCallersContext) {
  CallerCl cl;
  const cl_uint context0 = references(cl.context), queue0 = references(cl.queue);
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create_from_cl(cl.context, cl.device, cl.queue, &ctx));
  pn_frame* frame = nullptr;
  {
    Rendered r;
    frame = renderBox(ctx, "pcf", r);
    ASSERT_NE(frame, nullptr);
  }  // the frame outlives its renderer, scene and parameters
  PN_ASSERT_OK(pn_context_release(ctx));
  EXPECT_EQ(pn_frame_width(frame), kWidth);
  EXPECT_EQ(pn_frame_height(frame), kHeight);
  ASSERT_EQ(pn_frame_light_count(frame), 1u);
  const std::string layer = pn_frame_light_layer(frame, 0);
  const std::vector<float> visibility = channel(frame, "visibility.Y");
  EXPECT_TRUE(sameBits(visibility, channel(frame, ("visibility." + layer + ".Y").c_str())));
  EXPECT_STREQ(pn_frame_attribute(frame, "penumbra:technique"), "pcf");
  EXPECT_STREQ(pn_frame_attribute(frame, "penumbra:version"), pn_version());
  EXPECT_STREQ(pn_frame_attribute(frame, "penumbra:scene"), "builtin:box");
  EXPECT_EQ(pn_frame_attribute(frame, "no-such-attribute"), nullptr);
  for (size_t i = 0; i < pn_frame_pass_count(frame); ++i) {
    double ms = -1;
    PN_ASSERT_OK(pn_frame_pass(frame, i, nullptr, &ms));
    EXPECT_EQ(ms, 0.0);  // the caller's queue has no profiling
  }

  cl_mem device = nullptr;
  PN_ASSERT_OK(pn_frame_visibility_buffer(frame, 0, &device));
  cl_context owner = nullptr;
  clGetMemObjectInfo(device, CL_MEM_CONTEXT, sizeof(owner), &owner, nullptr);
  EXPECT_EQ(owner, cl.context);
  EXPECT_TRUE(sameBits(cl.read<float>(device, visibility.size()), flipped(visibility)));  // rows bottom-up
  expectDeviceOutputs(cl, frame);
  PN_ASSERT_OK(pn_frame_release(frame));
  clFinish(cl.queue);
  EXPECT_EQ(settled(cl.context, context0), context0);
  EXPECT_EQ(settled(cl.queue, queue0), queue0);
}

TEST(ApiRenderer, TheSameBitsOnPenumbrasOwnContext) {
  CallerCl cl;
  pn_context *mine = nullptr, *theirs = nullptr;
  PN_ASSERT_OK(pn_context_create(nullptr, &mine));
  PN_ASSERT_OK(pn_context_create_from_cl(cl.context, cl.device, cl.queue, &theirs));
  Rendered a, b;
  pn_frame* own = renderBox(mine, "pcss", a);
  pn_frame* caller = renderBox(theirs, "pcss", b);
  ASSERT_NE(own, nullptr);
  ASSERT_NE(caller, nullptr);
  EXPECT_TRUE(sameBits(channel(own, "visibility.Y"), channel(caller, "visibility.Y")));
  EXPECT_TRUE(sameBits(channel(own, "R"), channel(caller, "R")));
  double total = 0;
  for (size_t i = 0; i < pn_frame_pass_count(own); ++i) {
    double ms = 0;
    PN_ASSERT_OK(pn_frame_pass(own, i, nullptr, &ms));
    total += ms;
  }
  EXPECT_GT(total, 0.0);  // penumbra's own queue profiles
  pn_frame_release(own);
  pn_frame_release(caller);
  pn_context_release(mine);
  pn_context_release(theirs);
}

// Each frame is a snapshot: the next render (another light) leaves the first frame's device copy alone.
TEST(ApiRenderer, LightsTechniquesAndSnapshots) {
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create(nullptr, &ctx));
  Rendered r;
  pn_frame* first = renderBox(ctx, "sm", r);
  ASSERT_NE(first, nullptr);
  cl_mem firstDevice = nullptr;
  PN_ASSERT_OK(pn_frame_visibility_buffer(first, 0, &firstDevice));
  const std::vector<float> before = channel(first, "visibility.Y");

  pn_light key, sun;
  pn_light_init(&key);
  pn_light_init(&sun);
  PN_ASSERT_OK(pn_light_parse("spot:2,6,1:0,0,0:50:0.3", &key));
  PN_ASSERT_OK(pn_light_parse("dir:-0.3,-1,0.2:2", &sun));
  key.name = "Key", sun.name = "Sun";
  pn_params* pcss = nullptr;
  PN_ASSERT_OK(pn_params_create("pcss", &pcss));
  PN_ASSERT_OK(pn_params_set(pcss, "pcss-filter-taps", "16"));
  const pn_frame_light lights[] = {{&key, nullptr}, {&sun, pcss}};
  pn_camera camera;
  pn_camera_init(&camera);
  PN_ASSERT_OK(pn_camera_parse("6,5,8:0,0,0:40", &camera));
  camera.width = 40, camera.height = 30;
  pn_frame* second = nullptr;
  PN_ASSERT_OK(pn_renderer_render(r.renderer, &camera, lights, 2, r.params, &second));
  EXPECT_EQ(pn_frame_width(second), 40);
  ASSERT_EQ(pn_frame_light_count(second), 2u);
  EXPECT_STREQ(pn_frame_light_layer(second, 1), "Sun");
  EXPECT_NE(std::string(pn_frame_attribute(second, "penumbra:light-techniques")).find("Sun=pcss"), std::string::npos);
  const float* sunVisibility = nullptr;
  PN_ASSERT_OK(pn_frame_channel(second, "visibility.Sun.Y", &sunVisibility));

  std::vector<float> after(before.size());
  clEnqueueReadBuffer(pn_context_cl_queue(ctx), firstDevice, CL_TRUE, 0, after.size() * sizeof(float), after.data(), 0,
                      nullptr, nullptr);
  EXPECT_TRUE(sameBits(after, flipped(before)));
  pn_frame_release(first);
  pn_frame_release(second);
  pn_params_release(pcss);
  pn_context_release(ctx);
}

TEST(ApiRenderer, ErrorsSayWhatIsWrong) {
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create(nullptr, &ctx));
  Rendered r;
  pn_frame* frame = renderBox(ctx, "pcf", r);
  ASSERT_NE(frame, nullptr);
  const float* data = nullptr;
  EXPECT_EQ(pn_frame_channel(frame, "visibility.Nope.Y", &data), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("has no channel \"visibility.Nope.Y\" (it has R, G, B, A"),
            std::string::npos)
      << pn_last_error_message();
  EXPECT_EQ(pn_params_set(r.params, "pcf-radius", "-3"), PN_ERROR_INVALID_ARGUMENT);
  // In library terms: the parameter as pn_params_set names it, not the command line's --pcf-radius.
  EXPECT_EQ(std::string(pn_last_error_message()).rfind("pcf-radius: -3 is outside", 0), 0u) << pn_last_error_message();
  pn_params* savsm = nullptr;
  PN_ASSERT_OK(pn_params_create("savsm", &savsm));
  PN_ASSERT_OK(pn_params_set(savsm, "savsm-width", "8"));
  PN_ASSERT_OK(pn_params_set(savsm, "savsm-max-width", "4"));
  pn_frame* contradicted = nullptr;
  EXPECT_EQ(pn_renderer_render(r.renderer, nullptr, nullptr, 0, savsm, &contradicted), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "savsm-width 8 is larger than savsm-max-width 4");
  pn_params_release(savsm);
  EXPECT_EQ(pn_params_set(r.params, "pcss-filter-taps", "4"), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "\"pcss-filter-taps\" is not a parameter of technique 'pcf'");

  pn_light point, a, b;
  pn_light_init(&point);
  pn_light_init(&a);
  pn_light_init(&b);
  PN_ASSERT_OK(pn_light_parse("point:0,5,0", &point));
  pn_frame* none = nullptr;
  const pn_frame_light points[] = {{&point, nullptr}};  // a point light renders as six cube faces
  pn_frame* lit = nullptr;
  PN_ASSERT_OK(pn_renderer_render(r.renderer, nullptr, points, 1, r.params, &lit));
  const float* pointVisibility = nullptr;
  EXPECT_EQ(pn_frame_channel(lit, "visibility.Y", &pointVisibility), PN_SUCCESS);
  EXPECT_NE(pointVisibility, nullptr);
  PN_ASSERT_OK(pn_frame_release(lit));
  PN_ASSERT_OK(pn_light_parse("spot:0,5,0:0,0,0:40", &a));
  PN_ASSERT_OK(pn_light_parse("spot:1,5,0:0,0,0:40", &b));
  const pn_frame_light twins[] = {{&a, nullptr}, {&b, nullptr}};
  EXPECT_EQ(pn_renderer_render(r.renderer, nullptr, twins, 2, r.params, &none), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("has the layer \"light\" of an earlier light"),
            std::string::npos);
  EXPECT_EQ(pn_renderer_render(r.renderer, nullptr, twins, 1, nullptr, &none), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "pn_renderer_render: light 0 has no params and the call gives none");
  EXPECT_EQ(none, nullptr);
  pn_light unsized = a;  // a light or camera pn_*_init did not prepare
  unsized.size = 0;
  const pn_frame_light unprepared[] = {{&unsized, nullptr}};
  EXPECT_EQ(pn_renderer_render(r.renderer, nullptr, unprepared, 1, r.params, &none), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("pn_renderer_render: lights[0].light->size 0 is smaller"),
            std::string::npos)
      << pn_last_error_message();
  pn_camera unsizedCamera;
  pn_camera_init(&unsizedCamera);
  unsizedCamera.size = sizeof(pn_camera) - 1;
  EXPECT_EQ(pn_renderer_render(r.renderer, &unsizedCamera, nullptr, 0, r.params, &none), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("pn_renderer_render: camera->size"), std::string::npos);
  EXPECT_EQ(none, nullptr);

  pn_scene* scene = nullptr;
  EXPECT_EQ(pn_scene_load("no/such/model.glb", nullptr, &scene), PN_ERROR_SCENE);
  EXPECT_NE(std::string(pn_last_error_message()).find("no/such/model.glb"), std::string::npos);
  pn_camera camera;
  pn_camera_init(&camera);
  EXPECT_EQ(pn_camera_parse("1,2,3:1,2,3", &camera), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(pn_frame_save_exr(frame, "/no/such/dir/x.exr"), PN_ERROR_RUNTIME);
  EXPECT_NE(std::string(pn_last_error_message()).find("/no/such/dir/x.exr"), std::string::npos);
  pn_frame_release(frame);
  pn_context_release(ctx);
}

// A call that fails writes nothing through its out-parameters: a live handle the caller passed in is neither
// overwritten (and so leaked) nor released, and stays usable.
TEST(ApiRenderer, AFailingCallLeavesTheCallersHandlesAsTheyWere) {
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create(nullptr, &ctx));
  pn_context* kept = ctx;
  EXPECT_EQ(pn_context_create("no-such-device-anywhere", &ctx), PN_ERROR_NO_DEVICE);
  EXPECT_EQ(ctx, kept);
  EXPECT_NE(std::string(pn_context_device_name(ctx)), "");
  Rendered r;
  pn_frame* frame = renderBox(ctx, "pcf", r);
  ASSERT_NE(frame, nullptr);

  pn_params* params = r.params;
  EXPECT_EQ(pn_params_create("no-such-technique", &params), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(params, r.params);
  pn_scene* scene = r.scene;
  EXPECT_EQ(pn_scene_load("no/such/model.glb", nullptr, &scene), PN_ERROR_SCENE);
  EXPECT_EQ(scene, r.scene);
  pn_mesh mesh;  // a triangle without indices: refused
  pn_mesh_init(&mesh);
  mesh.triangle_count = 1;
  EXPECT_EQ(pn_scene_create(&mesh, 1, nullptr, 0, &scene), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(scene, r.scene);
  pn_renderer* renderer = r.renderer;
  EXPECT_EQ(pn_renderer_create(ctx, nullptr, &renderer), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(renderer, r.renderer);
  pn_frame* held = frame;
  pn_light a;
  pn_light_init(&a);
  PN_ASSERT_OK(pn_light_parse("spot:0,5,0:0,0,0:40", &a));
  const pn_frame_light twins[] = {{&a, nullptr}, {&a, nullptr}};
  EXPECT_EQ(pn_renderer_render(r.renderer, nullptr, twins, 2, r.params, &held), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(held, frame);
  const float* data = nullptr;
  PN_ASSERT_OK(pn_frame_channel(frame, "visibility.Y", &data));
  const float* before = data;
  EXPECT_EQ(pn_frame_channel(frame, "visibility.Nope.Y", &data), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(data, before);
  cl_mem buffer = reinterpret_cast<cl_mem>(&buffer);  // a value the call must not touch (never used as a cl_mem)
  const cl_mem sentinel = buffer;
  EXPECT_EQ(pn_frame_visibility_buffer(frame, 9, &buffer), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(buffer, sentinel);
  EXPECT_EQ(pn_frame_device_buffer(frame, static_cast<pn_frame_output>(7), &buffer), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(buffer, sentinel);
  EXPECT_EQ(pn_frame_width(held), kWidth);  // every handle still alive and usable
  pn_frame_release(frame);
  pn_context_release(ctx);
}

// A scene file light's own technique applies through the library as through the CLI: its technique's defaults, the
// call's explicitly set parameters that it has, then its own "params". Equal bit for bit to passing the lights with
// those params by hand; a bad technique is an invalid argument naming the file and the light.
TEST(ApiRenderer, SceneLightsKeepTheirOwnTechniques) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "penumbra-api-own-techniques";
  std::filesystem::create_directories(dir);
  const std::string spot =
      R"("name": "Key", "type": "spot", "position": [0, 5, 0], "target": [0, 0, 0], "radius": 0.2)";
  const std::string sun = R"({"name": "Sun", "type": "dir", "direction": [0.3, -1, 0.2]})";
  std::ofstream(dir / "own.json") << R"({"procedural": [{"name": "box"}], "lights": [{)" << spot
                                  << R"(, "technique": "pcss", "params": {"pcss-filter-taps": 4}}, )" << sun << "]}";
  std::ofstream(dir / "bad.json") << R"({"procedural": [{"name": "box"}], "lights": [{)" << spot
                                  << R"(, "technique": "nope"}]})";
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create(nullptr, &ctx));
  Rendered r;
  PN_ASSERT_OK(pn_scene_load((dir / "own.json").c_str(), nullptr, &r.scene));
  PN_ASSERT_OK(pn_params_create("sm", &r.params));
  PN_ASSERT_OK(pn_params_set(r.params, "map-size", "256"));  // inherited by Key's pcss
  PN_ASSERT_OK(pn_renderer_create(ctx, r.scene, &r.renderer));
  pn_camera camera;
  pn_camera_init(&camera);
  PN_ASSERT_OK(pn_scene_default_camera(r.scene, &camera));
  camera.width = kWidth, camera.height = kHeight;
  pn_frame* own = nullptr;
  PN_ASSERT_OK(pn_renderer_render(r.renderer, &camera, nullptr, 0, r.params, &own));
  EXPECT_NE(std::string(pn_frame_attribute(own, "penumbra:light-techniques")).find("Key=pcss"), std::string::npos);

  pn_light key, sunLight;
  pn_light_init(&key);
  pn_light_init(&sunLight);
  PN_ASSERT_OK(pn_scene_light(r.scene, 0, &key));
  PN_ASSERT_OK(pn_scene_light(r.scene, 1, &sunLight));
  pn_params* pcss = nullptr;
  PN_ASSERT_OK(pn_params_create("pcss", &pcss));
  PN_ASSERT_OK(pn_params_set(pcss, "map-size", "256"));
  PN_ASSERT_OK(pn_params_set(pcss, "pcss-filter-taps", "4"));
  const pn_frame_light lights[] = {{&key, pcss}, {&sunLight, nullptr}};
  pn_frame* byHand = nullptr;
  PN_ASSERT_OK(pn_renderer_render(r.renderer, &camera, lights, 2, r.params, &byHand));
  for (const char* layer : {"visibility.Key.Y", "visibility.Sun.Y"})
    EXPECT_TRUE(sameBits(channel(own, layer), channel(byHand, layer))) << layer;

  pn_scene* bad = nullptr;
  pn_renderer* badRenderer = nullptr;
  pn_frame* none = nullptr;
  PN_ASSERT_OK(pn_scene_load((dir / "bad.json").c_str(), nullptr, &bad));
  PN_ASSERT_OK(pn_renderer_create(ctx, bad, &badRenderer));
  EXPECT_EQ(pn_renderer_render(badRenderer, &camera, nullptr, 0, r.params, &none), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("bad.json: light \"Key\": unknown technique 'nope'"),
            std::string::npos)
      << pn_last_error_message();
  EXPECT_EQ(none, nullptr);
  pn_renderer_release(badRenderer);
  pn_scene_release(bad);
  pn_frame_release(own);
  pn_frame_release(byHand);
  pn_params_release(pcss);
  pn_context_release(ctx);
  std::filesystem::remove_all(dir);
}

TEST(ApiRenderer, TechniquesAndTheirParameters) {
  ASSERT_GE(pn_technique_count(), 14u);
  EXPECT_STREQ(pn_technique_name(0), "sm");
  EXPECT_EQ(pn_technique_name(pn_technique_count()), nullptr);
  const size_t count = pn_technique_param_count("pcf");
  ASSERT_GT(count, 0u);
  bool radius = false;
  for (size_t i = 0; i < count; ++i) {
    pn_param_info info;
    PN_ASSERT_OK(pn_technique_param("pcf", i, &info));
    radius = radius || std::string(info.name) == "pcf-radius";
  }
  EXPECT_TRUE(radius);
  EXPECT_EQ(pn_technique_param_count("nope"), 0u);
  pn_params* params = nullptr;
  PN_ASSERT_OK(pn_params_create("pcf", &params));
  PN_ASSERT_OK(pn_params_set(params, "pcf-radius", "3"));
  double value = 0;
  PN_ASSERT_OK(pn_params_get(params, "pcf-radius", &value));
  EXPECT_EQ(value, 3.0);
  EXPECT_NE(std::string(pn_params_describe(params)).find("pcf-radius=3"), std::string::npos);
  pn_params_release(params);
  PN_ASSERT_OK(pn_params_create("lvsm", &params));  // a text parameter: set as text, read through the description
  PN_ASSERT_OK(pn_params_set(params, "lvsm-splits", "0.3,0.6"));
  EXPECT_NE(std::string(pn_params_describe(params)).find("lvsm-splits=0.3,0.6"), std::string::npos);
  EXPECT_EQ(pn_params_get(params, "lvsm-splits", &value), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "\"lvsm-splits\" is a text parameter (pn_params_describe shows its value)");
  pn_params_release(params);
}

// pn_render_options::outputs: a frame of the visibility alone has it bit for bit as the whole frame has it, and no
// preview (no shading pass, PN_FRAME_PREVIEW refused naming the bit), no G-buffer copies and none of their channels,
// on request or all at once; a caller compiled against 0.3 (its size ends before `outputs`) gets every output; bits
// beyond PN_FRAME_OUTPUTS_ALL are refused.
TEST(ApiRenderer, FramesLeaveOutTheOutputsTheCallerDoesNotRead) {
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create(nullptr, &ctx));
  Rendered r;
  pn_frame* whole = renderBox(ctx, "pcf", r);
  ASSERT_NE(whole, nullptr);
  const pn_camera camera = boxCamera(r);
  pn_render_options options;
  pn_render_options_init(&options);
  EXPECT_EQ(options.outputs, static_cast<unsigned>(PN_FRAME_OUTPUTS_ALL));
  options.outputs = 0;
  for (const pn_frame_channels channels : {PN_FRAME_CHANNELS_ON_REQUEST, PN_FRAME_CHANNELS_ALL}) {
    options.channels = channels;
    pn_frame* bare = nullptr;
    PN_ASSERT_OK(pn_renderer_enqueue(r.renderer, &camera, nullptr, 0, r.params, &options, 0, nullptr, nullptr, &bare));
    std::vector<std::string> names;
    for (size_t i = 0; i < pn_frame_channel_count(bare); ++i) names.push_back(pn_frame_channel_name(bare, i));
    EXPECT_EQ(names.size(), 2u) << channels;  // visibility.Y and the light's layer
    for (const std::string& name : names) {
      EXPECT_TRUE(name.starts_with("visibility.")) << name;
      EXPECT_TRUE(sameBits(channel(bare, name.c_str()), channel(whole, name.c_str()))) << name;
    }
    const float* data = nullptr;
    EXPECT_EQ(pn_frame_channel(bare, "R", &data), PN_ERROR_INVALID_ARGUMENT);
    cl_mem buffer = nullptr;
    EXPECT_EQ(pn_frame_device_buffer(bare, PN_FRAME_PREVIEW, &buffer), PN_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pn_last_error_message()).find("PN_FRAME_OUTPUT_PREVIEW_BIT"), std::string::npos)
        << pn_last_error_message();
    EXPECT_EQ(pn_frame_device_buffer(bare, PN_FRAME_DEPTH, &buffer), PN_ERROR_INVALID_ARGUMENT);
    PN_ASSERT_OK(pn_frame_visibility_buffer(bare, 0, &buffer));
    for (size_t i = 0; i < pn_frame_pass_count(bare); ++i) {
      const char* name = nullptr;
      PN_ASSERT_OK(pn_frame_pass(bare, i, &name, nullptr));
      EXPECT_FALSE(std::string(name).starts_with("shade/shade_")) << name;
    }
    pn_frame_release(bare);
  }
  // The preview alone: the surfaces stay.
  options.outputs = PN_FRAME_OUTPUT_PREVIEW_BIT;
  pn_frame* preview = nullptr;
  PN_ASSERT_OK(pn_renderer_enqueue(r.renderer, &camera, nullptr, 0, r.params, &options, 0, nullptr, nullptr, &preview));
  cl_mem buffer = nullptr;
  PN_ASSERT_OK(pn_frame_device_buffer(preview, PN_FRAME_PREVIEW, &buffer));
  EXPECT_EQ(pn_frame_device_buffer(preview, PN_FRAME_POSITION, &buffer), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_TRUE(sameBits(channel(preview, "R"), channel(whole, "R")));
  pn_frame_release(preview);
  // A 0.3 caller: its options end before `outputs`, whatever lies beyond is not read.
  options.outputs = 0;
  options.size = offsetof(pn_render_options, outputs);
  pn_frame* old = nullptr;
  PN_ASSERT_OK(pn_renderer_enqueue(r.renderer, &camera, nullptr, 0, r.params, &options, 0, nullptr, nullptr, &old));
  PN_ASSERT_OK(pn_frame_device_buffer(old, PN_FRAME_PREVIEW, &buffer));
  PN_ASSERT_OK(pn_frame_device_buffer(old, PN_FRAME_POSITION, &buffer));
  pn_frame_release(old);
  pn_render_options_init(&options);
  options.outputs = 8;
  pn_frame* none = nullptr;
  EXPECT_EQ(pn_renderer_enqueue(r.renderer, &camera, nullptr, 0, r.params, &options, 0, nullptr, nullptr, &none),
            PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("beyond PN_FRAME_OUTPUTS_ALL"), std::string::npos)
      << pn_last_error_message();
  EXPECT_EQ(none, nullptr);
  pn_frame_release(whole);
  pn_context_release(ctx);
}

// pn_renderer_enqueue: after the caller's event, a frame whose visibility goes into the caller's buffer and whose host
// channels come on request equals pn_renderer_render's frame bit for bit (channels, device outputs), without the
// technique's debug channels; its event completes the caller's buffer; its pass times resolve when asked; the frame
// keeps the caller's buffer and gives it back; bad options are refused before any work and write no event.
TEST(ApiRenderer, EnqueuedFramesChainEventsAndReadChannelsOnRequest) {
  CallerCl cl;
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create_from_cl(cl.context, cl.device, cl.queue, &ctx));
  Rendered r;
  pn_frame* synchronous = renderBox(ctx, "pcss", r);
  ASSERT_NE(synchronous, nullptr);
  const pn_camera camera = boxCamera(r);
  const size_t pixels = size_t(kWidth) * kHeight;

  // The caller's own command first: a write of its output buffer whose event the frame waits for.
  cl_mem out = cl.buffer<float>(pixels);
  const std::vector<float> poison(pixels, NAN);
  cl_event written = nullptr;
  ASSERT_EQ(clEnqueueWriteBuffer(cl.queue, out, CL_FALSE, 0, pixels * 4, poison.data(), 0, nullptr, &written),
            CL_SUCCESS);
  ASSERT_EQ(clWaitForEvents(1, &written), CL_SUCCESS);
  const cl_uint outReferences = settled(out, 1);  // PoCL drops the write's reference a moment after it completes
  pn_render_options options;
  pn_render_options_init(&options);
  EXPECT_EQ(options.channels, PN_FRAME_CHANNELS_ON_REQUEST);
  options.visibility = &out;
  options.visibility_count = 1;
  pn_frame* frame = nullptr;
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_renderer_enqueue(r.renderer, &camera, nullptr, 0, r.params, &options, 1, &written, &done, &frame));
  ASSERT_NE(done, nullptr);
  ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
  EXPECT_TRUE(sameBits(cl.read<float>(out, pixels), flipped(channel(synchronous, "visibility.Y"))));
  cl_mem given = nullptr;
  PN_ASSERT_OK(pn_frame_visibility_buffer(frame, 0, &given));
  EXPECT_EQ(given, out);
  EXPECT_GT(references(out), outReferences);  // the frame (and its channels' readers) keep it

  // The channels on request: each the synchronous frame's, bit for bit; the debug channels are the difference.
  EXPECT_EQ(pn_frame_width(frame), kWidth);
  EXPECT_EQ(pn_frame_height(frame), kHeight);
  std::vector<std::string> names;
  for (size_t i = 0; i < pn_frame_channel_count(frame); ++i) names.push_back(pn_frame_channel_name(frame, i));
  ASSERT_FALSE(names.empty());
  for (const std::string& name : names)
    EXPECT_TRUE(sameBits(channel(frame, name.c_str()), channel(synchronous, name.c_str()))) << name;
  EXPECT_LT(names.size(), pn_frame_channel_count(synchronous));
  const float* again = nullptr;
  const float* first = nullptr;
  PN_ASSERT_OK(pn_frame_channel(frame, "R", &first));
  PN_ASSERT_OK(pn_frame_channel(frame, "R", &again));
  EXPECT_EQ(first, again);  // read once, kept
  cl_mem position = nullptr, theirs = nullptr;
  PN_ASSERT_OK(pn_frame_device_buffer(frame, PN_FRAME_POSITION, &position));
  PN_ASSERT_OK(pn_frame_device_buffer(synchronous, PN_FRAME_POSITION, &theirs));
  EXPECT_EQ(cl.read<cl_float4>(position, pixels).back().s[0], cl.read<cl_float4>(theirs, pixels).back().s[0]);
  ASSERT_EQ(pn_frame_pass_count(frame), pn_frame_pass_count(synchronous));  // the same passes, resolved now
  for (size_t i = 0; i < pn_frame_pass_count(frame); ++i) {
    const char* enqueued = nullptr;
    const char* rendered = nullptr;
    PN_ASSERT_OK(pn_frame_pass(frame, i, &enqueued, nullptr));
    PN_ASSERT_OK(pn_frame_pass(synchronous, i, &rendered, nullptr));
    EXPECT_STREQ(enqueued, rendered);
  }
  const std::string exr = (std::filesystem::temp_directory_path() / "penumbra-enqueued.exr").string();
  PN_ASSERT_OK(pn_frame_save_exr(frame, exr.c_str()));
  EXPECT_GT(std::filesystem::file_size(exr), 1000u);
  std::filesystem::remove(exr);

  // Every channel at once through pn_renderer_enqueue: the synchronous frame's, debug channels included.
  options.channels = PN_FRAME_CHANNELS_ALL;
  options.visibility = nullptr, options.visibility_count = 0;
  pn_frame* all = nullptr;
  PN_ASSERT_OK(pn_renderer_enqueue(r.renderer, &camera, nullptr, 0, r.params, &options, 0, nullptr, nullptr, &all));
  EXPECT_EQ(pn_frame_channel_count(all), pn_frame_channel_count(synchronous));
  EXPECT_TRUE(sameBits(channel(all, "visibility.Y"), channel(synchronous, "visibility.Y")));

  // Refusals: nothing enqueued, no event written.
  CallerCl other;
  cl_mem foreign = other.buffer<float>(pixels), small = cl.buffer<float>(pixels - 1);
  auto refused = [&](const pn_render_options& o, const char* words) {
    cl_event event = reinterpret_cast<cl_event>(0x1);
    pn_frame* none = nullptr;
    EXPECT_EQ(pn_renderer_enqueue(r.renderer, &camera, nullptr, 0, r.params, &o, 0, nullptr, &event, &none),
              PN_ERROR_INVALID_ARGUMENT)
        << words;
    EXPECT_NE(std::string(pn_last_error_message()).find(words), std::string::npos) << pn_last_error_message();
    EXPECT_EQ(event, reinterpret_cast<cl_event>(0x1));
    EXPECT_EQ(none, nullptr);
  };
  pn_render_options bad;
  pn_render_options_init(&bad);
  bad.size = 4;
  refused(bad, "pn_render_options_init");
  pn_render_options_init(&bad);
  bad.channels = static_cast<pn_frame_channels>(7);
  refused(bad, "options->channels 7");
  pn_render_options_init(&bad);
  const cl_mem two[2] = {out, out};
  bad.visibility = two, bad.visibility_count = 2;
  refused(bad, "2 entries for 1 lights");
  bad.visibility = &small, bad.visibility_count = 1;
  refused(bad, "holds 3071 floats");
  bad.visibility = &foreign;
  refused(bad, "another OpenCL context");

  pn_frame_release(all);
  pn_frame_release(frame);
  EXPECT_EQ(settled(out, outReferences), outReferences);
  pn_frame_release(synchronous);
  clReleaseEvent(done);
  clReleaseEvent(written);
  for (cl_mem m : {out, foreign, small}) clReleaseMemObject(m);
  pn_context_release(ctx);
}

}  // namespace renderer_test
}  // namespace penumbra::test
