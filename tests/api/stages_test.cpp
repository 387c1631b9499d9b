// The C API's filtering stages on the caller's own buffers, context and queue: results against the double-precision
// references of tools/selftest/reference/ (the same tolerances as the stage tests, with their reasons), events in and
// out, and the caller's reference counts where they began once the caller has finished its queue.
#include <Imath/half.h>
#include <penumbra/penumbra.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "tests/api/caller_cl.h"
#include "tests/support/compare.h"
#include "tests/support/random_images.h"
#include "tools/selftest/reference/blur_ref.h"
#include "tools/selftest/reference/moments_ref.h"
#include "tools/selftest/reference/pyramid_ref.h"
#include "tools/selftest/reference/reduce_ref.h"
#include "tools/selftest/reference/sat_ref.h"

namespace penumbra::test {
namespace stages_test {

// fp32 normalisation is within ~3 ulp of the double value; squares double it (moments_test.cpp).
constexpr Tolerance kVsmTol{1e-6, 1e-6};
// ESM's e^(80 (d - 1)) carries d's fp32 rounding (~3 ulp) times 80 as relative error (measured 3.8e-6).
constexpr Tolerance kEsmTol{1e-6, 1e-5};
// The MSM transform sums terms up to ~80 with cancellation: absolute error ~ 80 * 4 * 6e-8.
constexpr Tolerance kMsmTol{5e-5, 0.0};
// Half storage: rounding to 11 significant bits, plus fp32's own error.
constexpr Tolerance kHalfTol{1e-6, 1.0 / 2048};
// A blur tap sum of ~20 fp32 products of values in [0, 1): a few ulp of 1.
constexpr Tolerance kBlurTol{2e-6, 0.0};
// Area averages of fp32 texels (pyramid_test.cpp kMeanTol).
constexpr Tolerance kMeanTol{1e-5, 0.0};
// fp32 sums of up to count / 65536 samples serially, then pairwise trees (reduce_test.cpp kSumRelTol).
constexpr double kSumRelTol = 80 * 6e-8;
constexpr float kNear = 1.0f, kFar = 50.0f;  // randomDepthMap's depths are in [1, 50]
constexpr uint32_t kW = 37, kH = 23;         // neither a multiple of any work-group size
constexpr float kPoison = -1234567.0f;       // outputs start as this: an unwritten element shows up

class ApiStages : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    cl_ = new CallerCl();
    ASSERT_EQ(pn_context_create_from_cl(cl_->context, cl_->device, cl_->queue, &ctx_), PN_SUCCESS)
        << pn_last_error_message();
  }
  static void TearDownTestSuite() {
    pn_context_release(ctx_);
    delete cl_;
  }
  static const CallerCl& cl() { return *cl_; }
  static pn_context* ctx() { return ctx_; }

  // Waits for the stage's event; once the caller has finished its queue, the event is the caller's alone.
  static void complete(cl_event event) {
    ASSERT_NE(event, nullptr);
    ASSERT_EQ(clWaitForEvents(1, &event), CL_SUCCESS);
    clFinish(cl().queue);
    EXPECT_EQ(settled(event, 1u), 1u);
    clReleaseEvent(event);
  }

 private:
  static inline CallerCl* cl_ = nullptr;
  static inline pn_context* ctx_ = nullptr;
};

std::vector<double> toDouble(const std::vector<float>& v) { return {v.begin(), v.end()}; }

float fromHalf(uint16_t bits) {
  Imath::half h;
  h.setBits(bits);
  return float(h);
}

pn_moments_config momentsOf(pn_moment_kind kind) {
  pn_moments_config c;
  pn_moments_config_init(&c);
  c.kind = kind;
  c.depth_near = kNear, c.depth_far = kFar;
  return c;
}

// The internal config the reference reads, for the same settings.
MomentsConfig refConfig(const pn_moments_config& c) {
  MomentsConfig config;
  const MomentKind kinds[] = {MomentKind::Vsm,  MomentKind::Evsm2, MomentKind::Evsm4,
                              MomentKind::Lvsm, MomentKind::Msm,   MomentKind::Esm};
  config.kind = kinds[c.kind];
  config.depthNear = c.depth_near, config.depthFar = c.depth_far;
  config.evsmPositive = c.evsm_positive, config.evsmNegative = c.evsm_negative;
  config.esmExponent = c.esm_exponent;
  config.storage = c.storage == PN_STORAGE_FLOAT16 ? MomentStorage::Float16 : MomentStorage::Float32;
  for (size_t i = 0; i < c.layer_count; ++i) config.layers.push_back({c.layers[i].p, c.layers[i].q});
  return config;
}

TEST_F(ApiStages, MomentsOnTheCallersBuffers) {
  const std::vector<float> depth = randomDepthMap(kW, kH, 7);
  const pn_lvsm_layer layers[] = {{0.0f, 0.6f}, {0.4f, 1.0f}};
  struct Case {
    pn_moments_config config;
    Tolerance tol;
  };
  std::vector<Case> cases = {{momentsOf(PN_MOMENTS_VSM), kVsmTol},
                             {momentsOf(PN_MOMENTS_MSM), kMsmTol},
                             {momentsOf(PN_MOMENTS_LVSM), kVsmTol},
                             {momentsOf(PN_MOMENTS_ESM), kEsmTol},
                             {momentsOf(PN_MOMENTS_ESM), kVsmTol}};
  cases[2].config.layers = layers, cases[2].config.layer_count = 2;
  cases[4].config.esm_exponent = 400.0f;  // log space: the depths themselves
  for (const Case& c : cases) {
    const size_t count = depth.size() * pn_moment_channels(c.config.kind) * std::max<size_t>(1, c.config.layer_count);
    cl_mem in = cl().buffer(depth), out = cl().buffer<float>(count, nullptr, kPoison);
    const cl_uint in0 = references(in), out0 = references(out);
    cl_event done = nullptr;
    PN_ASSERT_OK(pn_moments(ctx(), in, kW, kH, &c.config, out, 0, nullptr, &done));
    complete(done);
    const std::vector<float> got = cl().read<float>(out, count);
    EXPECT_TRUE((allNear<float, double>(got, ref::moments(depth, refConfig(c.config)), c.tol))) << c.config.kind;
    EXPECT_EQ(settled(in, in0), in0);
    EXPECT_EQ(settled(out, out0), out0);
    clReleaseMemObject(in);
    clReleaseMemObject(out);
  }
}

// An input given as a cl_image2d (what an engine's depth attachment often is) is copied once into a temporary after
// the wait list's barrier: the same bits as from a buffer, the image's content as it is when the caller's events
// complete (written on another queue while the stage waits), its reference count as it was; another format or size
// is refused by name.
TEST_F(ApiStages, ImageInputsAreCopiedAfterTheWaitList) {
  cl_bool images = CL_FALSE;
  clGetDeviceInfo(cl().device, CL_DEVICE_IMAGE_SUPPORT, sizeof(images), &images, nullptr);
  if (!images) GTEST_SKIP() << "the device has no image support";
  const std::vector<float> depth = randomDepthMap(kW, kH, 17), first(depth.size(), 5.0f);
  cl_int err = CL_SUCCESS;
  const cl_image_format r32f{CL_R, CL_FLOAT};
  cl_image_desc desc{};
  desc.image_type = CL_MEM_OBJECT_IMAGE2D, desc.image_width = kW, desc.image_height = kH;
  cl_mem image = clCreateImage(cl().context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, &r32f, &desc,
                               const_cast<float*>(first.data()), &err);
  ASSERT_EQ(err, CL_SUCCESS);
  const cl_uint image0 = references(image);
  const pn_moments_config vsm = momentsOf(PN_MOMENTS_VSM);
  const size_t count = depth.size() * 2;
  cl_mem fromImage = cl().buffer<float>(count, nullptr, kPoison),
         fromBuffer = cl().buffer<float>(count, nullptr, kPoison);
  cl_event gate = clCreateUserEvent(cl().context, &err), done = nullptr;
  PN_ASSERT_OK(pn_moments(ctx(), image, kW, kH, &vsm, fromImage, 1, &gate, &done));
  // The caller writes the depth it means while the stage waits for the gate, on a queue of its own.
  cl_command_queue other = clCreateCommandQueue(cl().context, cl().device, 0, &err);
  const size_t origin[3] = {0, 0, 0}, region[3] = {kW, kH, 1};
  ASSERT_EQ(clEnqueueWriteImage(other, image, CL_TRUE, origin, region, 0, 0, depth.data(), 0, nullptr, nullptr),
            CL_SUCCESS);
  clReleaseCommandQueue(other);
  clSetUserEventStatus(gate, CL_COMPLETE);
  complete(done);
  cl_mem in = cl().buffer(depth);
  PN_ASSERT_OK(pn_moments(ctx(), in, kW, kH, &vsm, fromBuffer, 0, nullptr, &done));
  complete(done);
  const std::vector<float> a = cl().read<float>(fromImage, count), b = cl().read<float>(fromBuffer, count);
  EXPECT_EQ(std::memcmp(a.data(), b.data(), count * sizeof(float)), 0);
  EXPECT_EQ(settled(image, image0), image0);

  const pn_image_shape two{kW, kH, 2};
  pn_blur_config blur;
  pn_blur_config_init(&blur);
  EXPECT_EQ(pn_blur(ctx(), image, fromImage, nullptr, &two, &blur, 0, nullptr, nullptr), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "pn_blur: in is an image of another format than 2 float channels");
  EXPECT_EQ(pn_minmax_pyramid(ctx(), image, kW + 1, kH, fromImage, 0, nullptr, nullptr), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("is a 37x23 image for a 38x23 stage"), std::string::npos)
      << pn_last_error_message();
  clReleaseEvent(gate);
  for (cl_mem m : {image, fromImage, fromBuffer, in}) clReleaseMemObject(m);
}

// pn_image_copy: an engine's two-channel image at an offset, with a row pitch and rows from the top, packed for a
// blur, and the blur's result unpacked into the same kind of layout: the packed path's values, moved where the layouts
// say and nowhere else; a cl_image2d source packs like a buffer; bad layouts are refused by name.
TEST_F(ApiStages, ImageCopyPacksAndUnpacksTheCallersLayouts) {
  const std::vector<float> packed = randomUnitImage(size_t(kW) * kH * 2, 31);
  const size_t offset = 3, pitch = kW * 2 + 5;  // floats
  std::vector<float> engine(offset + pitch * kH, -9.0f);
  for (uint32_t y = 0; y < kH; ++y)
    std::memcpy(&engine[offset + (kH - 1 - y) * pitch], &packed[size_t(y) * kW * 2], kW * 2 * sizeof(float));
  cl_mem theirs = cl().buffer(engine), in = cl().buffer<float>(packed.size(), nullptr, kPoison),
         out = cl().buffer<float>(packed.size(), nullptr, kPoison),
         back = cl().buffer<float>(engine.size(), nullptr, -9.0f), reference = cl().buffer(packed),
         referenceOut = cl().buffer<float>(packed.size(), nullptr, kPoison);
  const pn_device_image engineLayout{theirs, offset * 4, pitch * 4, 1}, packedIn{in, 0, 0, 0}, packedOut{out, 0, 0, 0},
      backLayout{back, offset * 4, pitch * 4, 1};
  const pn_image_shape shape{kW, kH, 2};
  pn_blur_config blur;
  pn_blur_config_init(&blur);
  blur.sigma = 1.5f;
  cl_event packedEvent = nullptr, blurred = nullptr, unpacked = nullptr;
  PN_ASSERT_OK(pn_image_copy(ctx(), &engineLayout, &packedIn, kW, kH, 2, 0, nullptr, &packedEvent));
  PN_ASSERT_OK(pn_blur(ctx(), in, out, nullptr, &shape, &blur, 1, &packedEvent, &blurred));
  PN_ASSERT_OK(pn_image_copy(ctx(), &packedOut, &backLayout, kW, kH, 2, 1, &blurred, &unpacked));
  complete(unpacked);
  EXPECT_EQ(cl().read<float>(in, packed.size()), packed);
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_blur(ctx(), reference, referenceOut, nullptr, &shape, &blur, 0, nullptr, &done));
  complete(done);
  const std::vector<float> want = cl().read<float>(referenceOut, packed.size());
  std::vector<float> expected(engine.size(), -9.0f);
  for (uint32_t y = 0; y < kH; ++y)
    std::memcpy(&expected[offset + (kH - 1 - y) * pitch], &want[size_t(y) * kW * 2], kW * 2 * sizeof(float));
  EXPECT_EQ(cl().read<float>(back, engine.size()), expected);
  for (cl_event e : {packedEvent, blurred}) clReleaseEvent(e);

  cl_bool images = CL_FALSE;
  clGetDeviceInfo(cl().device, CL_DEVICE_IMAGE_SUPPORT, sizeof(images), &images, nullptr);
  if (images) {
    cl_int err = CL_SUCCESS;
    const cl_image_format rgba32f{CL_RGBA, CL_FLOAT};
    cl_image_desc desc{};
    desc.image_type = CL_MEM_OBJECT_IMAGE2D, desc.image_width = kW, desc.image_height = kH;
    const std::vector<float> texels = randomUnitImage(size_t(kW) * kH * 4, 32);
    cl_mem image = clCreateImage(cl().context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, &rgba32f, &desc,
                                 const_cast<float*>(texels.data()), &err);
    ASSERT_EQ(err, CL_SUCCESS);
    cl_mem four = cl().buffer<float>(texels.size(), nullptr, kPoison);
    const pn_device_image fromImage{image, 0, 0, 0}, packedFour{four, 0, 0, 0};
    PN_ASSERT_OK(pn_image_copy(ctx(), &fromImage, &packedFour, kW, kH, 4, 0, nullptr, &done));
    complete(done);
    EXPECT_EQ(cl().read<float>(four, texels.size()), texels);
    EXPECT_EQ(pn_image_copy(ctx(), &fromImage, &packedFour, kW, kH, 3, 0, nullptr, nullptr), PN_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pn_last_error_message()).find("1, 2 or 4 channels, not 3"), std::string::npos);
    clReleaseMemObject(four);
    clReleaseMemObject(image);
  }

  auto refused = [&](const pn_device_image& from, const pn_device_image& to, uint32_t floats, const char* words) {
    cl_event event = reinterpret_cast<cl_event>(0x1);
    EXPECT_EQ(pn_image_copy(ctx(), &from, &to, kW, kH, floats, 0, nullptr, &event), PN_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(pn_last_error_message()).find(words), std::string::npos) << pn_last_error_message();
    EXPECT_EQ(event, reinterpret_cast<cl_event>(0x1));
  };
  refused(engineLayout, packedIn, 5, "texel_floats 5 is not 1..4");
  refused(engineLayout, {in, 4, 0, 0}, 2, "pn_image_copy: dst: 37x23 texels of 8 bytes at offset 4");
  refused(engineLayout, {in, 0, kW * 8 - 4, 0}, 2, "shorter than a row");
  refused({theirs, 2, pitch * 4, 1}, packedIn, 2, "multiples of 4 bytes");
  refused(engineLayout, {theirs, 0, 0, 0}, 2, "src and dst are one buffer");
  refused({nullptr, 0, 0, 0}, packedIn, 2, "src->memory is NULL");
  for (cl_mem m : {theirs, in, out, back, reference, referenceOut}) clReleaseMemObject(m);
}

TEST_F(ApiStages, HalfMomentsAndTheFusedBlur) {
  const std::vector<float> depth = randomDepthMap(kW, kH, 8);
  pn_moments_config config = momentsOf(PN_MOMENTS_VSM);
  config.storage = PN_STORAGE_FLOAT16;
  const size_t count = depth.size() * 2;
  cl_mem in = cl().buffer(depth), half = cl().buffer<uint16_t>(count);
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_moments(ctx(), in, kW, kH, &config, half, 0, nullptr, &done));
  complete(done);
  std::vector<float> got;
  for (uint16_t bits : cl().read<uint16_t>(half, count)) got.push_back(fromHalf(bits));
  EXPECT_TRUE((allNear<float, double>(got, ref::moments(depth, refConfig(config)), kHalfTol)));

  // Fused moments + blur: the same bits as the two stages one after the other.
  config.storage = PN_STORAGE_FLOAT32;
  pn_blur_config blur;
  pn_blur_config_init(&blur);
  blur.sigma = 1.5f;
  cl_mem moments = cl().buffer<float>(count), separate = cl().buffer<float>(count), fused = cl().buffer<float>(count);
  const pn_image_shape shape{kW, kH, 2};
  cl_event first = nullptr, second = nullptr, third = nullptr;
  PN_ASSERT_OK(pn_moments(ctx(), in, kW, kH, &config, moments, 0, nullptr, &first));
  PN_ASSERT_OK(pn_blur(ctx(), moments, separate, nullptr, &shape, &blur, 1, &first, &second));
  size_t scratch = 0;
  PN_ASSERT_OK(pn_blur_moments_scratch(ctx(), kW, kH, &config, &blur, &scratch));
  EXPECT_GE(scratch, count);
  PN_ASSERT_OK(pn_blur_moments(ctx(), in, kW, kH, &config, &blur, fused, nullptr, 1, &second, &third));
  complete(third);
  clReleaseEvent(first);
  clReleaseEvent(second);
  EXPECT_EQ(cl().read<float>(separate, count), cl().read<float>(fused, count));
  for (cl_mem m : {in, half, moments, separate, fused}) clReleaseMemObject(m);
}

TEST_F(ApiStages, BlurAgainstTheReference) {
  struct Case {
    uint32_t channels;
    pn_blur_filter filter;
    pn_blur_method method;
    bool inPlace;
  };
  for (const Case& c :
       {Case{2, PN_BLUR_GAUSSIAN, PN_BLUR_AUTO, false}, Case{1, PN_BLUR_BOX, PN_BLUR_RUNNING_SUMS, true},
        Case{4, PN_BLUR_GAUSSIAN, PN_BLUR_DIRECT, false}}) {
    const ImageShape shape{kW, kH, c.channels};
    const std::vector<float> image = randomUnitImage(shape.count(), 11 + c.channels);
    pn_blur_config config;
    pn_blur_config_init(&config);
    config.filter = c.filter, config.method = c.method, config.sigma = 1.7f, config.radius = 5;
    cl_mem in = cl().buffer(image), scratch = cl().buffer<float>(shape.count());
    cl_mem out = c.inPlace ? in : cl().buffer<float>(shape.count(), nullptr, kPoison);
    const cl_uint scratch0 = references(scratch);
    const pn_image_shape s{kW, kH, c.channels};
    cl_event done = nullptr;
    PN_ASSERT_OK(pn_blur(ctx(), in, out, scratch, &s, &config, 0, nullptr, &done));
    complete(done);
    const std::vector<double> taps = c.filter == PN_BLUR_BOX ? ref::boxTaps(5) : ref::gaussianTaps(1.7);
    EXPECT_TRUE(
        (allNear<float, double>(cl().read<float>(out, shape.count()),
                                ref::convolveSeparable(toDouble(image), shape, taps), kBlurTol, kW * c.channels)))
        << c.channels << " channels, filter " << c.filter;
    EXPECT_EQ(settled(scratch, scratch0), scratch0);
    if (!c.inPlace) clReleaseMemObject(out);
    clReleaseMemObject(in);
    clReleaseMemObject(scratch);
  }
}

// Floating-point tables: ~2 x 32 in-tile additions plus one per tile along each axis, each rounding by eps times the
// running magnitude Sum |x - offset| (sat_test.cpp's bound).
double satTolerance(const ImageShape& s, double epsilon, double magnitude) {
  return (2.0 * 32 + 2.0 * (s.width + s.height) / 32 + std::log2(s.texels() + 1.0)) * epsilon * magnitude;
}

TEST_F(ApiStages, SatInEveryPrecision) {
  const ImageShape shape{kW, kH, 2};
  const std::vector<float> image = randomUnitImage(shape.count(), 21);
  const pn_image_shape s{kW, kH, 2};
  cl_mem in = cl().buffer(image);
  const cl_uint in0 = references(in);
  for (pn_sat_precision precision : {PN_SAT_FLOAT32, PN_SAT_FIXED32, PN_SAT_FIXED64, PN_SAT_FLOAT64}) {
    pn_sat_config config;
    pn_sat_config_init(&config);
    config.precision = precision;
    const size_t bytes = precision == PN_SAT_FLOAT32 || precision == PN_SAT_FIXED32 ? 4 : 8;
    cl_mem table = cl().buffer<uint8_t>(shape.count() * bytes), offset = cl().buffer<float>(4);
    cl_event done = nullptr;
    const pn_status status = pn_sat(ctx(), in, &s, &config, table, offset, 0, nullptr, &done);
    cl_device_fp_config fp64 = 0;
    clGetDeviceInfo(cl().device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof(fp64), &fp64, nullptr);
    if (precision == PN_SAT_FLOAT64 && fp64 == 0) {  // a device without doubles says so
      EXPECT_EQ(status, PN_ERROR_RUNTIME);
      EXPECT_NE(std::string(pn_last_error_message()).find("cl_khr_fp64"), std::string::npos);
    } else {
      PN_ASSERT_OK(status);
      complete(done);
      const std::vector<float> mean = cl().read<float>(offset, 4);
      if (precision == PN_SAT_FIXED32) {
        EXPECT_EQ(cl().read<uint32_t>(table, shape.count()), ref::satFixed<uint32_t>(image, shape, 16));
      } else if (precision == PN_SAT_FIXED64) {
        EXPECT_EQ(cl().read<uint64_t>(table, shape.count()), ref::satFixed<uint64_t>(image, shape, 32));
      } else if (precision == PN_SAT_FLOAT64) {
        EXPECT_TRUE((allNear<double, double>(cl().read<double>(table, shape.count()), ref::satDouble(image, shape),
                                             Tolerance{1e-9, 1e-12})));
      } else {
        const std::array<double, 4> expectedMean = ref::finiteMean(image, shape);
        EXPECT_TRUE((allNear<float, double>(mean, expectedMean, Tolerance{0.0, 1e-5})));  // a float tree sum
        const std::array<double, 4> used{mean[0], mean[1], mean[2], mean[3]};
        double magnitude = 0;
        for (size_t i = 0; i < image.size(); ++i) magnitude += std::abs(image[i] - used[i % 2]);
        EXPECT_TRUE((allNear<float, double>(cl().read<float>(table, shape.count()), ref::satDouble(image, shape, used),
                                            Tolerance{satTolerance(shape, 6e-8, magnitude), 0.0})));
      }
    }
    clReleaseMemObject(table);
    clReleaseMemObject(offset);
  }
  EXPECT_EQ(settled(in, in0), in0);
  clReleaseMemObject(in);
  int bits = 0;
  PN_ASSERT_OK(pn_sat_fraction_bits(PN_SAT_FIXED32, 255.0 * 255.0, 1.0, &bits));
  EXPECT_EQ(bits, 15);  // host/stages/sat.h's example
}

TEST_F(ApiStages, PyramidsAgainstTheReference) {
  size_t levels = 0, texels = 0;
  PN_ASSERT_OK(pn_pyramid_layout(kW, kH, 1, nullptr, 0, &levels, &texels));
  std::vector<pn_pyramid_level> layout(levels);
  PN_ASSERT_OK(pn_pyramid_layout(kW, kH, 1, layout.data(), levels, &levels, nullptr));
  ASSERT_EQ(levels, 5u);  // 18x11, 9x5, 4x2, 2x1, 1x1
  EXPECT_EQ(layout[0].width, 18u);
  EXPECT_EQ(layout[4].width * layout[4].height, 1u);

  const ImageShape shape{kW, kH, 2};
  const std::vector<float> base = randomUnitImage(shape.count(), 31);
  cl_mem in = cl().buffer(base), mips = cl().buffer<float>(texels * 2, nullptr, kPoison);
  const pn_image_shape s{kW, kH, 2};
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_moment_mips(ctx(), in, &s, PN_STORAGE_FLOAT32, mips, 0, nullptr, &done));
  complete(done);
  const std::vector<float> got = cl().read<float>(mips, texels * 2);
  const std::vector<std::vector<double>> expected = ref::momentMips(toDouble(base), shape);
  ASSERT_EQ(expected.size(), levels);
  for (size_t l = 0; l < levels; ++l) {
    const std::vector<float> level(got.begin() + layout[l].offset * 2,
                                   got.begin() + (layout[l].offset + layout[l].width * layout[l].height) * 2);
    EXPECT_TRUE((allNear<float, double>(level, expected[l], kMeanTol))) << "level " << l + 1;
  }

  const std::vector<float> depth = randomDepthMap(kW, kH, 32);
  size_t minMaxTexels = 0;
  PN_ASSERT_OK(pn_pyramid_layout(kW, kH, 0, nullptr, 0, &levels, &minMaxTexels));
  cl_mem depthBuffer = cl().buffer(depth), minMax = cl().buffer<float>(minMaxTexels * 2);
  PN_ASSERT_OK(pn_minmax_pyramid(ctx(), depthBuffer, kW, kH, minMax, 0, nullptr, &done));
  complete(done);
  const std::vector<float> pairs = cl().read<float>(minMax, minMaxTexels * 2);
  size_t at = 0;
  for (const auto& level : ref::minMaxPyramid(depth, kW, kH))
    for (const auto& [lo, hi] : level) {
      ASSERT_EQ(pairs[at], lo) << "texel " << at / 2;  // min and max are exact
      ASSERT_EQ(pairs[at + 1], hi) << "texel " << at / 2;
      at += 2;
    }
  EXPECT_EQ(at, pairs.size());
  for (cl_mem m : {in, mips, depthBuffer, minMax}) clReleaseMemObject(m);
}

TEST_F(ApiStages, LloydStatisticsAgainstTheReference) {
  const size_t count = 100003;
  const std::vector<float> x = randomUnitImage(count, 41), w = randomUnitImage(count, 42);
  const std::vector<float> boundaries = {0.2f, 0.45f, 0.7f};
  cl_mem xs = cl().buffer(x), ws = cl().buffer(w), bs = cl().buffer(boundaries), out = cl().buffer<pn_lloyd_stats>(4);
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_lloyd_stats_reduce(ctx(), xs, ws, count, bs, 4, out, 0, nullptr, &done));
  complete(done);
  const std::vector<pn_lloyd_stats> got = cl().read<pn_lloyd_stats>(out, 4);
  const std::vector<ref::LloydRef> expected = ref::lloydStats(x, w, boundaries);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(got[k].samples, expected[k].samples);
    EXPECT_NEAR(got[k].sum_w, expected[k].sumW, kSumRelTol * expected[k].sumW);
    EXPECT_NEAR(got[k].sum_wx, expected[k].sumWX, kSumRelTol * expected[k].sumWX);
    EXPECT_NEAR(got[k].sum_wx2, expected[k].sumWX2, kSumRelTol * expected[k].sumWX2);
  }
  for (cl_mem m : {xs, ws, bs, out}) clReleaseMemObject(m);
}

// A sub-buffer of the caller's is how a stage works on part of a buffer; the parent's count ends where it began.
TEST_F(ApiStages, SubBuffersAndBadBuffers) {
  cl_uint alignBits = 0;
  clGetDeviceInfo(cl().device, CL_DEVICE_MEM_BASE_ADDR_ALIGN, sizeof(alignBits), &alignBits, nullptr);
  const size_t offset = alignBits / 8 / sizeof(float), n = size_t(kW) * kH;
  const std::vector<float> image = randomUnitImage(offset + n, 51);
  cl_mem parent = cl().buffer(image), out = cl().buffer<float>(n);
  const cl_uint parent0 = references(parent);
  const cl_buffer_region region{offset * sizeof(float), n * sizeof(float)};
  cl_int err = CL_SUCCESS;
  cl_mem part = clCreateSubBuffer(parent, CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &region, &err);
  ASSERT_EQ(err, CL_SUCCESS);
  pn_blur_config config;
  pn_blur_config_init(&config);
  const pn_image_shape s{kW, kH, 1};
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_blur(ctx(), part, out, nullptr, &s, &config, 0, nullptr, &done));
  complete(done);
  const std::vector<float> tail(image.begin() + offset, image.end());
  EXPECT_TRUE((allNear<float, double>(cl().read<float>(out, n),
                                      ref::convolveSeparable(toDouble(tail), {kW, kH, 1}, ref::gaussianTaps(1.0)),
                                      kBlurTol, kW)));
  clReleaseMemObject(part);
  EXPECT_EQ(settled(parent, parent0), parent0);

  CallerCl other;
  cl_mem foreign = other.buffer<float>(n), small = cl().buffer<float>(n / 2);
  done = nullptr;
  EXPECT_EQ(pn_blur(ctx(), foreign, out, nullptr, &s, &config, 0, nullptr, &done), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "pn_blur: in belongs to another OpenCL context than the pn_context's");
  EXPECT_EQ(done, nullptr);
  EXPECT_EQ(pn_blur(ctx(), parent, small, nullptr, &s, &config, 0, nullptr, &done), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(std::string(pn_last_error_message()).find("output buffer holds 425 elements, needs 851"), std::string::npos)
      << pn_last_error_message();
  EXPECT_EQ(pn_blur(ctx(), parent, out, nullptr, &s, &config, 1, nullptr, &done), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "pn_blur: a wait list of 1 events is NULL");
  EXPECT_EQ(pn_blur(ctx(), nullptr, out, nullptr, &s, &config, 0, nullptr, &done), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_STREQ(pn_last_error_message(), "pn_blur: in is NULL");
  clFinish(cl().queue);
  EXPECT_EQ(settled(parent, parent0), parent0);
  for (cl_mem m : {parent, out, foreign, small}) clReleaseMemObject(m);
}

// A stage of an image without texels is refused by name, as a camera without pixels is, before anything is enqueued;
// an int that is no moment kind has no channels; a failing call leaves the caller's event variable as it was.
TEST_F(ApiStages, EmptyImagesAndUnknownKindsAreRefused) {
  EXPECT_EQ(pn_moment_channels(PN_MOMENTS_VSM), 2u);
  EXPECT_EQ(pn_moment_channels(PN_MOMENTS_EVSM2), 2u);
  EXPECT_EQ(pn_moment_channels(PN_MOMENTS_EVSM4), 4u);
  EXPECT_EQ(pn_moment_channels(PN_MOMENTS_LVSM), 2u);
  EXPECT_EQ(pn_moment_channels(PN_MOMENTS_MSM), 4u);
  EXPECT_EQ(pn_moment_channels(PN_MOMENTS_ESM), 1u);
  for (int notAKind : {-1, 6, 99, 0x7FFFFFFF})
    EXPECT_EQ(pn_moment_channels(static_cast<pn_moment_kind>(notAKind)), 0u) << notAKind;

  cl_mem in = cl().buffer<float>(64), out = cl().buffer<float>(256);
  cl_int err = CL_SUCCESS;
  cl_event kept = clCreateUserEvent(cl().context, &err);  // the caller's own: a failing call must not overwrite it
  ASSERT_EQ(err, CL_SUCCESS);
  cl_event event = kept;
  const auto refused = [&](pn_status status, const std::string& text) {
    EXPECT_EQ(status, PN_ERROR_INVALID_ARGUMENT) << text;
    EXPECT_NE(std::string(pn_last_error_message()).find(text), std::string::npos) << pn_last_error_message();
    EXPECT_EQ(event, kept) << text;
  };
  const pn_moments_config moments = momentsOf(PN_MOMENTS_VSM);
  refused(pn_moments(ctx(), in, 0, 8, &moments, out, 0, nullptr, &event), "pn_moments: image 0x8 has no texels");
  refused(pn_moments(ctx(), in, 8, 0, &moments, out, 0, nullptr, &event), "pn_moments: image 8x0 has no texels");
  pn_blur_config blur;
  pn_blur_config_init(&blur);
  const pn_image_shape empty{0, 4, 1}, flat{4, 0, 1};
  refused(pn_blur(ctx(), in, out, nullptr, &empty, &blur, 0, nullptr, &event), "pn_blur: image 0x4 has no texels");
  refused(pn_blur_moments(ctx(), in, 0, 4, &moments, &blur, out, nullptr, 0, nullptr, &event),
          "pn_blur_moments: image 0x4 has no texels");
  size_t floats = 7;
  EXPECT_EQ(pn_blur_moments_scratch(ctx(), 4, 0, &moments, &blur, &floats), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(floats, 7u);
  pn_sat_config sat;
  pn_sat_config_init(&sat);
  refused(pn_sat(ctx(), in, &flat, &sat, out, nullptr, 0, nullptr, &event), "pn_sat: image 4x0 has no texels");
  refused(pn_moment_mips(ctx(), in, &empty, PN_STORAGE_FLOAT32, out, 0, nullptr, &event),
          "pn_moment_mips: image 0x4 has no texels");
  refused(pn_minmax_pyramid(ctx(), in, 0, 0, out, 0, nullptr, &event), "pn_minmax_pyramid: image 0x0 has no texels");
  // Settings structs carry their size: one smaller than the first version's is refused (a caller that skipped the
  // init function, or a struct from before its fields), a larger one (a newer caller's) is read up to what we know.
  pn_moments_config small = moments;
  small.size = sizeof(size_t);
  refused(pn_moments(ctx(), in, 8, 8, &small, out, 0, nullptr, &event),
          "pn_moments: config->size 8 is smaller than its first version's");
  EXPECT_NE(std::string(pn_last_error_message()).find("(call pn_moments_config_init first)"), std::string::npos);
  pn_blur_config oldBlur = blur;
  oldBlur.size = 0;
  const pn_image_shape square{8, 8, 1};
  refused(pn_blur(ctx(), in, out, nullptr, &square, &oldBlur, 0, nullptr, &event), "blur config->size 0 is smaller");
  pn_sat_config oldSat = sat;
  oldSat.size = sizeof(pn_sat_config) - 1;
  refused(pn_sat(ctx(), in, &square, &oldSat, out, nullptr, 0, nullptr, &event), "pn_sat: config->size");
  pn_moments_config newer = moments;
  newer.size = sizeof(pn_moments_config) + 64;
  cl_event done = nullptr;
  PN_ASSERT_OK(pn_moments(ctx(), in, 8, 8, &newer, out, 0, nullptr, &done));
  complete(done);

  size_t levels = 5, texels = 9;
  EXPECT_EQ(pn_pyramid_layout(0, 4, 0, nullptr, 0, &levels, &texels), PN_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(levels, 5u);
  EXPECT_EQ(texels, 9u);
  EXPECT_EQ(event, kept);
  clReleaseEvent(kept);
  for (cl_mem m : {in, out}) clReleaseMemObject(m);
}

}  // namespace stages_test
}  // namespace penumbra::test
