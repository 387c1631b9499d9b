// The C API's contexts on the caller's OpenCL objects: penumbra keeps one retain of each and releases only that,
// refuses objects that do not fit together, never finishes the caller's queue, and waits for the caller's events;
// errors are status codes with a thread-local message.
#include <penumbra/penumbra.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "tests/api/caller_cl.h"

namespace penumbra::test {
namespace context_test {

TEST(ApiContext, OnTheCallersObjectsRetainsOnlyWhatItKeeps) {
  CallerCl cl;
  const cl_uint context0 = references(cl.context), queue0 = references(cl.queue);
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create_from_cl(cl.context, cl.device, cl.queue, &ctx));
  EXPECT_EQ(pn_context_cl_context(ctx), cl.context);  // no second context
  EXPECT_EQ(pn_context_cl_device(ctx), cl.device);
  EXPECT_EQ(pn_context_cl_queue(ctx), cl.queue);
  EXPECT_EQ(settled(cl.context, context0 + 1), context0 + 1);
  EXPECT_EQ(settled(cl.queue, queue0 + 1), queue0 + 1);
  PN_ASSERT_OK(pn_context_retain(ctx));
  EXPECT_EQ(settled(cl.context, context0 + 1), context0 + 1);  // a second pn_context reference is not a second retain
  PN_ASSERT_OK(pn_context_release(ctx));
  PN_ASSERT_OK(pn_context_release(ctx));
  EXPECT_EQ(settled(cl.context, context0), context0);
  EXPECT_EQ(settled(cl.queue, queue0), queue0);
}

TEST(ApiContext, RefusesAnOutOfOrderQueue) {
  CallerCl cl(CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE);
  ASSERT_NE(cl.queue, nullptr) << "the device refused an out-of-order queue";
  const cl_uint context0 = references(cl.context), queue0 = references(cl.queue);
  pn_context* ctx = reinterpret_cast<pn_context*>(1);
  EXPECT_EQ(pn_context_create_from_cl(cl.context, cl.device, cl.queue, &ctx), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(ctx, reinterpret_cast<pn_context*>(1));  // a failing call writes nothing through its out-parameter
  EXPECT_NE(std::string(pn_last_error_message()).find("in-order queue"), std::string::npos) << pn_last_error_message();
  EXPECT_EQ(settled(cl.context, context0), context0);
  EXPECT_EQ(settled(cl.queue, queue0), queue0);
}

TEST(ApiContext, RefusesObjectsThatDoNotFitTogether) {
  CallerCl a, b;
  pn_context* ctx = nullptr;
  EXPECT_EQ(pn_context_create_from_cl(a.context, a.device, b.queue, &ctx), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "OpenCL interop: the queue belongs to another context");
  EXPECT_EQ(pn_context_create_from_cl(a.context, a.device, nullptr, &ctx), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(pn_context_create_from_cl(a.context, a.device, a.queue, nullptr), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "pn_context_create_from_cl: context is NULL");
  EXPECT_EQ(ctx, nullptr);
}

TEST(ApiContext, OwnContextAndDeviceErrors) {
  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create(nullptr, &ctx));  // PENUMBRA_DEVICE
  EXPECT_NE(std::string(pn_context_device_name(ctx)), "");
  EXPECT_NE(pn_context_cl_queue(ctx), nullptr);
  PN_ASSERT_OK(pn_context_release(ctx));
  EXPECT_EQ(pn_context_create("no-such-device-anywhere", &ctx), PN_ERROR_NO_DEVICE);
  EXPECT_NE(std::string(pn_last_error_message()).find("no OpenCL device matches 'no-such-device-anywhere'"),
            std::string::npos)
      << pn_last_error_message();
  EXPECT_EQ(pn_context_release(nullptr), PN_SUCCESS);
  EXPECT_EQ(pn_context_retain(nullptr), PN_ERROR_INVALID_ARGUMENT);
}

// A stage waiting on the caller's user event: the call returns at once, nothing runs until the event completes,
// releasing the context meanwhile does not wait (a clFinish would never return), and the event out completes after.
TEST(ApiContext, WaitsForTheCallersEventsAndNeverFinishesTheQueue) {
  CallerCl cl;
  const uint32_t w = 33, h = 17;
  std::vector<float> image(size_t(w) * h);
  for (size_t i = 0; i < image.size(); ++i) image[i] = float(i % 7);
  cl_mem in = cl.buffer(image), out = cl.buffer<float>(image.size(), nullptr, -1.0f);
  const cl_uint in0 = references(in), out0 = references(out);
  cl_int err = CL_SUCCESS;
  cl_event gate = clCreateUserEvent(cl.context, &err);
  ASSERT_EQ(err, CL_SUCCESS);

  pn_context* ctx = nullptr;
  PN_ASSERT_OK(pn_context_create_from_cl(cl.context, cl.device, cl.queue, &ctx));
  pn_image_shape shape{w, h, 1};
  pn_sat_config config;
  pn_sat_config_init(&config);
  config.precision = PN_SAT_FIXED32;
  config.fraction_bits = 0;
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_sat(ctx, in, &shape, &config, out, nullptr, 1, &gate, &done));
  ASSERT_NE(done, nullptr);
  // A stage with a constant table (the blur's weights) must not upload it with a blocking write behind the gate.
  cl_mem copy = cl.buffer<float>(image.size(), nullptr, -1.0f);
  pn_blur_config identity;
  pn_blur_config_init(&identity);
  identity.filter = PN_BLUR_BOX, identity.radius = 0, identity.method = PN_BLUR_DIRECT;
  cl_event copied = nullptr;
  PN_ASSERT_OK(pn_blur(ctx, in, copy, nullptr, &shape, &identity, 1, &gate, &copied));
  PN_ASSERT_OK(pn_context_release(ctx));  // returns although penumbra's commands wait on the gate

  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  cl_int status = CL_COMPLETE;
  clGetEventInfo(done, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof(status), &status, nullptr);
  EXPECT_GT(status, CL_COMPLETE) << "the stage ran before the caller's event completed";
  ASSERT_EQ(clSetUserEventStatus(gate, CL_COMPLETE), CL_SUCCESS);
  ASSERT_EQ(clWaitForEvents(1, &done), CL_SUCCESS);
  ASSERT_EQ(clWaitForEvents(1, &copied), CL_SUCCESS);
  EXPECT_EQ(cl.read<float>(copy, image.size()), image);  // one tap of weight 1
  const std::vector<uint32_t> table = cl.read<uint32_t>(out, image.size());
  uint32_t total = 0;  // integers in fixed point with 0 fraction bits: the last entry sums them all, exactly
  for (float v : image) total += uint32_t(v);
  EXPECT_EQ(table.back(), total);
  clFinish(cl.queue);                // the caller finishes its own queue
  EXPECT_EQ(settled(done, 1u), 1u);  // the caller's to release
  EXPECT_EQ(settled(in, in0), in0);
  EXPECT_EQ(settled(out, out0), out0);
  clReleaseEvent(done);
  clReleaseEvent(copied);
  clReleaseEvent(gate);
  clReleaseMemObject(copy);
  clReleaseMemObject(in);
  clReleaseMemObject(out);
}

TEST(ApiContext, ErrorsAreStatusCodesWithAThreadLocalMessage) {
  EXPECT_STREQ(pn_status_name(PN_ERROR_OPENCL), "PN_ERROR_OPENCL");
  EXPECT_STREQ(pn_status_name(static_cast<pn_status>(99)), "PN_UNKNOWN_STATUS");
  pn_params* params = nullptr;
  EXPECT_EQ(pn_params_create("nope", &params), PN_ERROR_INVALID_ARGUMENT);
  const std::string here = pn_last_error_message();
  EXPECT_NE(here.find("unknown technique 'nope'"), std::string::npos) << here;
  std::string there;
  std::thread([&] {
    there = pn_last_error_message();  // nothing failed on this thread yet
    pn_scene* scene = nullptr;
    EXPECT_EQ(pn_scene_load("no/such/scene.gltf", nullptr, &scene), PN_ERROR_SCENE);
  }).join();
  EXPECT_EQ(there, "");
  EXPECT_EQ(pn_last_error_message(), here);  // the other thread's failure did not touch this one's
  EXPECT_EQ(pn_last_cl_error(), CL_SUCCESS);
  EXPECT_STREQ(pn_version(), PN_VERSION_STRING);
}

// Options instead of the environment, and programs built before the calls that use them: pn_context_prebuild builds
// (or loads from the options' cache folder) what a technique runs, so a frame after it builds nothing; the log names
// each program; a second context on the same folder loads them all; the caller's log data is released once.
struct LogSink {
  std::vector<std::string> messages;
  int released = 0;
  size_t count(const std::string& word) const {
    size_t n = 0;
    for (const std::string& m : messages) n += m.rfind(word, 0) == 0;
    return n;
  }
};

pn_context_options logged(LogSink& sink, const char* cacheDir) {
  pn_context_options o;
  pn_context_options_init(&o);
  EXPECT_EQ(o.size, sizeof(pn_context_options));
  o.cache_dir = cacheDir;
  o.log = [](const char* message, void* user) { static_cast<LogSink*>(user)->messages.push_back(message); };
  o.log_user_data = &sink;
  o.log_release = [](void* user) { ++static_cast<LogSink*>(user)->released; };
  return o;
}

// builtin:box at 48x32 through `technique`: 0 on success.
pn_status renderBox(pn_context* ctx, const char* technique) {
  pn_scene* scene = nullptr;
  pn_params* params = nullptr;
  pn_renderer* renderer = nullptr;
  pn_frame* frame = nullptr;
  pn_status status = pn_scene_load("builtin:box", nullptr, &scene);
  if (status == PN_SUCCESS) status = pn_params_create(technique, &params);
  if (status == PN_SUCCESS) status = pn_renderer_create(ctx, scene, &renderer);
  pn_camera camera;
  pn_camera_init(&camera);
  if (status == PN_SUCCESS) status = pn_scene_default_camera(scene, &camera);
  camera.width = 48, camera.height = 32;
  if (status == PN_SUCCESS) status = pn_renderer_render(renderer, &camera, nullptr, 0, params, &frame);
  pn_frame_release(frame);
  pn_renderer_release(renderer);
  pn_params_release(params);
  pn_scene_release(scene);
  return status;
}

TEST(ApiContext, OptionsPrebuildAndTheLog) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "penumbra-api-prebuild";
  const std::string folder = dir.string();  // options.cache_dir points into it
  std::filesystem::remove_all(dir);
  LogSink first;
  {
    const pn_context_options options = logged(first, folder.c_str());
    pn_context* ctx = nullptr;
    PN_ASSERT_OK(pn_context_create_with_options(&options, &ctx));
    const char* names[] = {"pcss", "moments"};
    PN_ASSERT_OK(pn_context_prebuild(ctx, names, 2));
    EXPECT_GT(first.count("built kernels/pcss.cl in "), 0u);
    EXPECT_GT(first.count("built kernels/moments.cl in "), 0u);
    EXPECT_EQ(first.count("loaded "), 0u);  // a new cache folder
    EXPECT_FALSE(std::filesystem::is_empty(dir));
    const size_t before = first.messages.size();
    PN_ASSERT_OK(renderBox(ctx, "pcss"));  // another frame size: nothing left to build
    EXPECT_EQ(first.messages.size(), before)
        << "built after prebuild: " << (first.messages.size() > before ? first.messages[before] : "");
    const char* unknown[] = {"pcss", "no-such-stage"};
    EXPECT_EQ(pn_context_prebuild(ctx, unknown, 2), PN_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pn_last_error_message()).find("unknown item \"no-such-stage\" (known: "), std::string::npos)
        << pn_last_error_message();
    const char* none[] = {nullptr};
    EXPECT_EQ(pn_context_prebuild(ctx, none, 1), PN_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(first.released, 0);
    PN_ASSERT_OK(pn_context_release(ctx));
    EXPECT_EQ(first.released, 1);  // with the context
  }
  LogSink second;  // the same folder: every program loaded, none built
  {
    const pn_context_options options = logged(second, folder.c_str());
    pn_context* ctx = nullptr;
    PN_ASSERT_OK(pn_context_create_with_options(&options, &ctx));
    const char* names[] = {"pcss"};
    PN_ASSERT_OK(pn_context_prebuild(ctx, names, 1));
    EXPECT_GT(second.count("loaded kernels/pcss.cl from the cache"), 0u);
    EXPECT_EQ(second.count("built "), 0u);
    pn_context_release(ctx);
  }
  std::filesystem::remove_all(dir);

  LogSink failed;
  pn_context_options options = logged(failed, "");
  options.layouts = "amd";
  pn_context* ctx = nullptr;
  EXPECT_EQ(pn_context_create_with_options(&options, &ctx), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("work-group layouts 'amd': expected gpu, nvidia"),
            std::string::npos)
      << pn_last_error_message();
  EXPECT_EQ(ctx, nullptr);
  EXPECT_EQ(failed.released, 1);  // released with the failed call
  options.layouts = "gpu", options.local_mem_limit = 16384, options.log = nullptr, options.log_release = nullptr;
  PN_ASSERT_OK(pn_context_create_with_options(&options, &ctx));  // the GPU plans within 16 KiB, as CI's local-mem runs
  PN_ASSERT_OK(renderBox(ctx, "vsm"));
  pn_context_release(ctx);
  ctx = nullptr;
  options.size = sizeof(size_t);
  EXPECT_EQ(pn_context_create_with_options(&options, &ctx), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("call pn_context_options_init"), std::string::npos);
  pn_context_options_init(&options);
  options.device = "no-such-device-anywhere";
  EXPECT_EQ(pn_context_create_with_options(&options, &ctx), PN_ERROR_NO_DEVICE);
  EXPECT_EQ(ctx, nullptr);
}

}  // namespace context_test
}  // namespace penumbra::test
