// pn_shade from the outside: a light map the caller drew (here on the host, as a window-depth buffer of its own
// projection) and the G-buffer of a pn_renderer frame, both the caller's cl_mem, shaded in the caller's buffer with
// events chained and no clFinish; the shadow matches the Renderer's own frame of the same scene; images, row pitches
// and top-down rows read as buffers do; every refusal names its field and writes no event; the caller's reference
// counts end where they began.
#include <penumbra/penumbra.h>

#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <string>
#include <vector>

#include "tests/api/caller_cl.h"

namespace penumbra::test {
namespace shade_test {

constexpr int kWidth = 160, kHeight = 120;
constexpr int kMapSize = 512;
constexpr float kLightRadius = 0.3f;

// A 10x10 ground at y = 0 and a 2x2 square at y = 2, both facing up.
pn_scene* squareOverPlane() {
  const float ground[] = {-5, 0, -5, 5, 0, -5, 5, 0, 5, -5, 0, 5};
  const float square[] = {-1, 2, -1, 1, 2, -1, 1, 2, 1, -1, 2, 1};
  const uint32_t quad[] = {0, 2, 1, 0, 3, 2};
  pn_mesh meshes[2];
  for (int i = 0; i < 2; ++i) {
    pn_mesh_init(&meshes[i]);
    meshes[i].positions = i == 0 ? ground : square;
    meshes[i].vertex_count = 4;
    meshes[i].indices = quad;
    meshes[i].triangle_count = 2;
  }
  pn_scene* scene = nullptr;
  EXPECT_EQ(pn_scene_create(meshes, 2, nullptr, 0, &scene), PN_SUCCESS) << pn_last_error_message();
  return scene;
}

// The caller's light: a disk of radius 0.3 at (0, 4, 0) facing down; its map a 90-degree perspective from there.
struct CallerLight {
  glm::mat4 view = glm::lookAt(glm::vec3(0, 4, 0), glm::vec3(0), glm::vec3(0, 0, -1));
  glm::mat4 projection = glm::perspective(glm::radians(90.0f), 1.0f, 1.0f, 6.0f);

  // The window depths (OpenGL's convention, cleared to 1) a rasterizer would leave for the square and the ground:
  // every point of either lies at one eye depth (2 and 4) on this light's axis.
  std::vector<float> map() const {
    const glm::mat4 toWorld = glm::inverse(view);
    std::vector<float> texels(size_t(kMapSize) * kMapSize, 1.0f);
    for (int y = 0; y < kMapSize; ++y)
      for (int x = 0; x < kMapSize; ++x) {
        const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / float(kMapSize) * 2.0f - 1.0f;  // tan 45 = 1
        for (const float depth : {2.0f, 4.0f}) {
          const glm::vec3 world(toWorld * glm::vec4(ndc * depth, -depth, 1.0f));
          const float half = depth == 2.0f ? 1.0f : 5.0f;
          if (std::abs(world.x) > half || std::abs(world.z) > half) continue;
          const glm::vec4 clip = projection * glm::vec4(0, 0, -depth, 1);
          texels[size_t(y) * kMapSize + x] = clip.z / clip.w * 0.5f + 0.5f;
          break;
        }
      }
    return texels;
  }

  pn_light light() const {
    pn_light l;
    pn_light_init(&l);
    EXPECT_EQ(pn_light_parse("spot:0,4,0:0,0,0:90:0.3", &l), PN_SUCCESS);
    return l;
  }
};

pn_camera camera() {
  pn_camera c;
  pn_camera_init(&c);
  EXPECT_EQ(pn_camera_parse("0,7,5:0,0,0:40", &c), PN_SUCCESS);
  c.width = kWidth, c.height = kHeight;
  return c;
}

// A Renderer frame of the scene under the caller's light with `technique` at its defaults.
struct RendererFrame {
  pn_params* params = nullptr;
  pn_renderer* renderer = nullptr;
  pn_frame* frame = nullptr;
  RendererFrame(pn_context* ctx, pn_scene* scene, const char* technique, const pn_light& light) {
    EXPECT_EQ(pn_params_create(technique, &params), PN_SUCCESS);
    EXPECT_EQ(pn_renderer_create(ctx, scene, &renderer), PN_SUCCESS) << pn_last_error_message();
    const pn_camera cam = camera();
    const pn_frame_light lights[] = {{&light, nullptr}};
    EXPECT_EQ(pn_renderer_render(renderer, &cam, lights, 1, params, &frame), PN_SUCCESS) << pn_last_error_message();
  }
  ~RendererFrame() {
    pn_frame_release(frame);
    pn_renderer_release(renderer);
    pn_params_release(params);
  }
  cl_mem output(pn_frame_output which) const {
    cl_mem mem = nullptr;
    EXPECT_EQ(pn_frame_device_buffer(frame, which, &mem), PN_SUCCESS);
    return mem;
  }
  // visibility.Y, rows from the bottom.
  std::vector<float> visibility() const {
    const float* top = nullptr;
    EXPECT_EQ(pn_frame_channel(frame, "visibility.Y", &top), PN_SUCCESS);
    std::vector<float> rows(size_t(kWidth) * kHeight);
    for (int y = 0; y < kHeight; ++y)
      std::memcpy(&rows[size_t(y) * kWidth], &top[size_t(kHeight - 1 - y) * kWidth], kWidth * sizeof(float));
    return rows;
  }
};

// The descriptor for the caller's map in `map` and the frame's G-buffer, visibility into `out`.
pn_shade_desc describe(const CallerLight& light, cl_mem map, const RendererFrame& frame, cl_mem out) {
  pn_shade_desc d;
  pn_shade_desc_init(&d);
  d.light_type = PN_LIGHT_SPOT;
  d.light_radius = kLightRadius;
  d.light_depth.memory = map;
  d.light_map_size = kMapSize;
  std::memcpy(d.light_view, glm::value_ptr(light.view), sizeof(d.light_view));
  std::memcpy(d.light_projection, glm::value_ptr(light.projection), sizeof(d.light_projection));
  d.width = kWidth, d.height = kHeight;
  d.positions.memory = frame.output(PN_FRAME_POSITION);
  d.normals.memory = frame.output(PN_FRAME_NORMAL);
  d.has_scene_bounds = 1;
  const float lo[3] = {-5, 0, -5}, hi[3] = {5, 2, 5};
  std::memcpy(d.scene_min, lo, sizeof(lo));
  std::memcpy(d.scene_max, hi, sizeof(hi));
  d.visibility.memory = out;
  return d;
}

struct Difference {
  double mean = 0;
  size_t above = 0;  // pixels more than 0.25 apart
};

Difference difference(const std::vector<float>& a, const std::vector<float>& b) {
  Difference d;
  for (size_t i = 0; i < a.size(); ++i) {
    const float e = std::abs(a[i] - b[i]);
    d.mean += std::isnan(e) ? 1.0 : e;
    d.above += !(e <= 0.25f);
  }
  d.mean /= double(a.size());
  return d;
}

struct Shading {
  pn_context* ctx = nullptr;
  pn_scene* scene = nullptr;
  pn_shader* shader = nullptr;
  explicit Shading(CallerCl& cl) {
    EXPECT_EQ(pn_context_create_from_cl(cl.context, cl.device, cl.queue, &ctx), PN_SUCCESS) << pn_last_error_message();
    scene = squareOverPlane();
    EXPECT_EQ(pn_shader_create(ctx, &shader), PN_SUCCESS) << pn_last_error_message();
  }
  ~Shading() {
    pn_shader_release(shader);
    pn_scene_release(scene);
    pn_context_release(ctx);
  }
};

// The caller's map (its own projection and resolution, not the Renderer's fit) and the Renderer's G-buffer: the same
// shadow as the Renderer's frame but for the two maps' texels. pcss's result, then vssm's waiting on it: chained by
// events, read back once.
TEST(ApiShade, TheCallersMapGivesTheRenderersShadow) {
  CallerCl cl;
  Shading s(cl);
  const CallerLight light;
  const pn_light pnLight = light.light();
  cl_mem map = cl.buffer(light.map());
  const size_t pixels = size_t(kWidth) * kHeight;
  cl_mem pcssOut = cl.buffer<float>(pixels, nullptr, NAN), vssmOut = cl.buffer<float>(pixels, nullptr, NAN);
  RendererFrame pcssFrame(s.ctx, s.scene, "pcss", pnLight), vssmFrame(s.ctx, s.scene, "vssm", pnLight);
  const cl_uint mapReferences = references(map), outReferences = references(pcssOut);

  pn_params* pcss = nullptr;
  pn_params* vssm = nullptr;
  PN_ASSERT_OK(pn_params_create("pcss", &pcss));
  PN_ASSERT_OK(pn_params_create("vssm", &vssm));
  cl_event pcssDone = nullptr, vssmDone = nullptr;
  const pn_shade_desc first = describe(light, map, pcssFrame, pcssOut);
  PN_ASSERT_OK(pn_shade(s.shader, pcss, &first, 0, nullptr, &pcssDone));
  ASSERT_NE(pcssDone, nullptr);
  EXPECT_NE(std::string(pn_shader_attribute(s.shader, "penumbra:light-fit")).find("caller 512x512"), std::string::npos);
  const pn_shade_desc second = describe(light, map, vssmFrame, vssmOut);
  PN_ASSERT_OK(pn_shade(s.shader, vssm, &second, 1, &pcssDone, &vssmDone));
  std::vector<float> pcssGot(pixels), vssmGot(pixels);
  ASSERT_EQ(clEnqueueReadBuffer(cl.queue, pcssOut, CL_FALSE, 0, pixels * 4, pcssGot.data(), 1, &vssmDone, nullptr),
            CL_SUCCESS);
  ASSERT_EQ(clEnqueueReadBuffer(cl.queue, vssmOut, CL_TRUE, 0, pixels * 4, vssmGot.data(), 1, &vssmDone, nullptr),
            CL_SUCCESS);

  // Measured (PoCL): mean 0.0026 (pcss) and 0.0005 (vssm), no pixel 0.25 apart.
  const Difference pcssDiff = difference(pcssGot, pcssFrame.visibility());
  const Difference vssmDiff = difference(vssmGot, vssmFrame.visibility());
  EXPECT_LE(pcssDiff.mean, 0.01) << "pcss";
  EXPECT_LE(pcssDiff.above, pixels / 200) << "pcss";
  EXPECT_LE(vssmDiff.mean, 0.01) << "vssm";
  EXPECT_LE(vssmDiff.above, pixels / 200) << "vssm";
  size_t shadowed = 0;
  for (float v : pcssGot) shadowed += v < 0.5f;
  EXPECT_GT(shadowed, pixels / 50) << "the square's shadow is in view";

  clReleaseEvent(pcssDone);
  clReleaseEvent(vssmDone);
  pn_params_release(pcss);
  pn_params_release(vssm);
  EXPECT_EQ(settled(map, mapReferences), mapReferences);
  EXPECT_EQ(settled(pcssOut, outReferences), outReferences);
  clReleaseMemObject(map);
  clReleaseMemObject(pcssOut);
  clReleaseMemObject(vssmOut);
}

// The map as a cl_image2d (copied once) and as a padded, pitched, top-down buffer; the visibility into a pitched,
// top-down buffer: each the packed buffer's result, bit for bit, written where the layout says.
TEST(ApiShade, ImagesPitchesAndRowOrderReadAsBuffersDo) {
  CallerCl cl;
  Shading s(cl);
  const CallerLight light;
  const std::vector<float> texels = light.map();
  cl_mem map = cl.buffer(texels);
  const size_t pixels = size_t(kWidth) * kHeight;
  cl_mem out = cl.buffer<float>(pixels);
  RendererFrame frame(s.ctx, s.scene, "pcf", light.light());
  pn_params* pcf = nullptr;
  PN_ASSERT_OK(pn_params_create("pcf", &pcf));
  const pn_shade_desc packed = describe(light, map, frame, out);
  PN_ASSERT_OK(pn_shade(s.shader, pcf, &packed, 0, nullptr, nullptr));
  const std::vector<float> want = cl.read<float>(out, pixels);

  cl_int err = CL_SUCCESS;
  const cl_image_format format{CL_R, CL_FLOAT};
  cl_image_desc image{};
  image.image_type = CL_MEM_OBJECT_IMAGE2D;
  image.image_width = image.image_height = kMapSize;
  cl_mem mapImage = clCreateImage(cl.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, &format, &image,
                                  const_cast<float*>(texels.data()), &err);
  ASSERT_EQ(err, CL_SUCCESS);
  const pn_shade_desc fromImage = describe(light, mapImage, frame, out);
  PN_ASSERT_OK(pn_shade(s.shader, pcf, &fromImage, 0, nullptr, nullptr));
  EXPECT_EQ(cl.read<float>(out, pixels), want);

  const size_t pad = 5, pitch = kMapSize + 3;  // floats
  std::vector<float> rows(pad + pitch * kMapSize, -3.0f);
  for (int y = 0; y < kMapSize; ++y)
    std::memcpy(&rows[pad + (kMapSize - 1 - y) * pitch], &texels[size_t(y) * kMapSize], kMapSize * sizeof(float));
  cl_mem mapRows = cl.buffer(rows);
  const size_t outPad = 2, outPitch = kWidth + 1;
  cl_mem outRows = cl.buffer<float>(outPad + outPitch * kHeight, nullptr, -3.0f);
  pn_shade_desc laidOut = describe(light, mapRows, frame, outRows);
  laidOut.light_depth = {mapRows, pad * 4, pitch * 4, 1};
  laidOut.visibility = {outRows, outPad * 4, outPitch * 4, 1};
  PN_ASSERT_OK(pn_shade(s.shader, pcf, &laidOut, 0, nullptr, nullptr));
  std::vector<float> expected(outPad + outPitch * kHeight, -3.0f);
  for (int y = 0; y < kHeight; ++y)
    std::memcpy(&expected[outPad + (kHeight - 1 - y) * outPitch], &want[size_t(y) * kWidth], kWidth * sizeof(float));
  EXPECT_EQ(cl.read<float>(outRows, expected.size()), expected);

  pn_params_release(pcf);
  for (cl_mem m : {map, out, mapImage, mapRows, outRows}) clReleaseMemObject(m);
}

// Each bad input is PN_ERROR_INVALID_ARGUMENT with a message naming it, and the caller's event is left as it was.
TEST(ApiShade, RefusalsNameTheFieldAndWriteNoEvent) {
  CallerCl cl;
  Shading s(cl);
  const CallerLight light;
  cl_mem map = cl.buffer(light.map());
  const size_t pixels = size_t(kWidth) * kHeight;
  cl_mem out = cl.buffer<float>(pixels);
  RendererFrame frame(s.ctx, s.scene, "pcf", light.light());
  pn_params* pcf = nullptr;
  pn_params* izb = nullptr;
  PN_ASSERT_OK(pn_params_create("pcf", &pcf));
  PN_ASSERT_OK(pn_params_create("izb", &izb));
  CallerCl other;
  cl_mem foreign = other.buffer<float>(pixels);
  const pn_shade_desc good = describe(light, map, frame, out);
  auto refused = [&](pn_shader* shader, const pn_params* params, const pn_shade_desc* desc, const char* words) {
    cl_event event = reinterpret_cast<cl_event>(0x1);
    EXPECT_EQ(pn_shade(shader, params, desc, 0, nullptr, &event), PN_ERROR_INVALID_ARGUMENT) << words;
    EXPECT_NE(std::string(pn_last_error_message()).find(words), std::string::npos) << pn_last_error_message();
    EXPECT_EQ(event, reinterpret_cast<cl_event>(0x1)) << words;
  };
  refused(nullptr, pcf, &good, "pn_shade: shader is NULL");
  refused(s.shader, nullptr, &good, "params is NULL");
  refused(s.shader, pcf, nullptr, "desc is NULL");
  pn_shade_desc d = good;
  d.size = 8;
  refused(s.shader, pcf, &d, "pn_shade_desc_init");
  d = good, d.light_type = static_cast<pn_light_type>(99);
  refused(s.shader, pcf, &d, "desc->light_type 99");
  d = good, d.light_depth_storage = static_cast<pn_depth_storage>(7);
  refused(s.shader, pcf, &d, "desc->light_depth_storage 7");
  d = good, d.camera_ndc_depth = static_cast<pn_ndc_depth>(-1);
  refused(s.shader, pcf, &d, "desc->camera_ndc_depth -1");
  d = good, d.light_map_size = 0;
  refused(s.shader, pcf, &d, "desc->light_map_size");
  d = good, d.light_map_size = kMapSize * 2;
  refused(s.shader, pcf, &d, "past the buffer's");
  d = good, d.light_depth.memory = nullptr;
  refused(s.shader, pcf, &d, "desc->light_depth.memory is NULL");
  d = good, d.visibility.memory = nullptr;
  refused(s.shader, pcf, &d, "desc->visibility.memory is NULL");
  d = good, d.visibility.memory = foreign;
  refused(s.shader, pcf, &d, "another OpenCL context");
  d = good, d.light_radius = -1;
  refused(s.shader, pcf, &d, "desc->light_radius");
  d = good, d.light_type = PN_LIGHT_POINT;
  refused(s.shader, pcf, &d, "point light");
  d = good, d.light_type = PN_LIGHT_DIRECTIONAL;
  refused(s.shader, pcf, &d, "orthographic");
  d = good, d.depth = d.positions;
  refused(s.shader, pcf, &d, "not both or neither");
  d = good, d.has_scene_bounds = 1, d.scene_min[0] = 9;
  refused(s.shader, pcf, &d, "not a box");
  refused(s.shader, izb, &good, "technique izb cannot shade from a caller's map");

  const char* reason = nullptr;
  EXPECT_EQ(pn_technique_takes_caller_map("pcss", &reason), 1);
  EXPECT_STREQ(reason, "");
  EXPECT_EQ(pn_technique_takes_caller_map("izb", &reason), 0);
  EXPECT_NE(std::string(reason).find("triangles"), std::string::npos);
  EXPECT_EQ(pn_technique_takes_caller_map("nope", nullptr), 0);
  size_t takers = 0;
  for (size_t i = 0; i < pn_technique_count(); ++i)
    takers += pn_technique_takes_caller_map(pn_technique_name(i), nullptr);
  EXPECT_EQ(takers, 11u);
  EXPECT_EQ(pn_shader_attribute(s.shader, "penumbra:light-fit"), nullptr);  // no call has succeeded

  pn_params_release(pcf);
  pn_params_release(izb);
  for (cl_mem m : {map, out}) clReleaseMemObject(m);
  clReleaseMemObject(foreign);
}

}  // namespace shade_test
}  // namespace penumbra::test
