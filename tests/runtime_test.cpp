// Tests of the OpenCL runtime (host/cl): error names, device selection, program cache (memory and disk),
// build errors with logs, kernel launch checks and padding, buffers, profiling, two contexts at once.
#include <gtest/gtest.h>

#include <cstring>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "host/cl/buffer.h"
#include "host/cl/context.h"
#include "host/cl/device.h"
#include "host/cl/embedded_sources.h"
#include "host/cl/error.h"
#include "host/cl/kernel.h"
#include "host/cl/profiler.h"
#include "tests/support/cl_test.h"

namespace penumbra {
namespace runtime_test {
namespace fs = std::filesystem;
using test::ClTest;
using test::kPoison;

// Sets an environment variable for the lifetime of the guard.
class EnvGuard {
 public:
  EnvGuard(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~EnvGuard() { old_.empty() ? unsetenv(name_) : setenv(name_, old_.c_str(), 1); }

 private:
  const char* name_;
  std::string old_;
};

fs::path freshDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / fmt::format("penumbra-{}-{}", name, ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(RuntimeErrors, NamesKnownAndUnknownCodes) {
  EXPECT_EQ(clErrorName(CL_INVALID_WORK_GROUP_SIZE), "CL_INVALID_WORK_GROUP_SIZE");
  EXPECT_EQ(clErrorName(CL_OUT_OF_RESOURCES), "CL_OUT_OF_RESOURCES");
  EXPECT_EQ(clErrorName(-1001), "CL_PLATFORM_NOT_FOUND_KHR");
  EXPECT_EQ(clErrorName(-12345), "CL_UNKNOWN_ERROR(-12345)");
}

TEST(RuntimeErrors, MessageCarriesCallKernelAndStage) {
  ClError error(CL_INVALID_KERNEL_ARGS, "clEnqueueNDRangeKernel", "blur_rows", "blur");
  const std::string message = error.what();
  EXPECT_NE(message.find("CL_INVALID_KERNEL_ARGS"), std::string::npos) << message;
  EXPECT_NE(message.find("clEnqueueNDRangeKernel"), std::string::npos) << message;
  EXPECT_NE(message.find("blur_rows"), std::string::npos) << message;
  EXPECT_NE(message.find("'blur'"), std::string::npos) << message;
  EXPECT_THROW(clCheck(CL_INVALID_VALUE, "x"), ClError);
  EXPECT_NO_THROW(clCheck(CL_SUCCESS, "x"));
}

TEST(RuntimeDevices, ListsAtLeastOneDeviceWithLimits) {
  const std::vector<DeviceInfo> devices = listDevices();
  ASSERT_FALSE(devices.empty()) << "no OpenCL device: install pocl-opencl-icd";
  for (const DeviceInfo& d : devices) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_GT(d.maxWorkGroupSize, 0u);
    EXPECT_GT(d.localMemBytes, 0u);
    EXPECT_GE(d.openclCMajor, 1);
    EXPECT_EQ(toJson(d)["name"], d.name);
  }
  EXPECT_NE(describeDevices(devices).find(devices[0].name), std::string::npos);
}

TEST(RuntimeDevices, SelectsBySpec) {
  const DeviceInfo cpu = selectDevice("cpu");
  EXPECT_TRUE(cpu.isCpu());
  EXPECT_NO_THROW(selectDevice("auto"));
  EXPECT_EQ(selectDevice(fmt::format("{}:{}", cpu.platformIndex, cpu.deviceIndex)).name, cpu.name);
  EXPECT_EQ(selectDevice(cpu.platformName.substr(0, 8) + ":" + std::to_string(cpu.deviceIndex)).name, cpu.name);
  EXPECT_EQ(selectDevice(cpu.name.substr(0, 5)).name, cpu.name);  // name substring, any case
}

// "auto" takes hardware first: Oclgrind reports itself as a GPU, yet a real CPU device comes before it, and it is
// chosen only alone or by name.
TEST(RuntimeDevices, AutoPrefersHardwareOverSimulators) {
  auto device = [](const char* platform, const char* name, cl_device_type type, unsigned index) {
    DeviceInfo d;
    d.platformName = platform, d.name = name, d.type = type, d.platformIndex = index;
    return d;
  };
  const DeviceInfo grind = device("Oclgrind", "Oclgrind Simulator", CL_DEVICE_TYPE_GPU, 0);
  const DeviceInfo pocl = device("Portable Computing Language", "pthread-skylake", CL_DEVICE_TYPE_CPU, 1);
  const DeviceInfo gpu = device("NVIDIA CUDA", "NVIDIA H200", CL_DEVICE_TYPE_GPU, 2);
  EXPECT_TRUE(grind.isSimulator());
  EXPECT_FALSE(pocl.isSimulator());
  EXPECT_EQ(chooseDevice({grind, pocl}, "auto").name, pocl.name);
  EXPECT_EQ(chooseDevice({grind, pocl, gpu}, "auto").name, gpu.name);
  EXPECT_EQ(chooseDevice({grind}, "auto").name, grind.name);
  EXPECT_EQ(chooseDevice({grind, pocl}, "oclgrind").name, grind.name);
  EXPECT_EQ(chooseDevice({grind, pocl}, "gpu").name, grind.name);  // asked for a GPU by type: the only one
}

TEST(RuntimeDevices, UnknownSpecListsDevices) {
  try {
    selectDevice("no-such-device-anywhere");
    FAIL() << "expected NoDeviceError";
  } catch (const NoDeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("available devices"), std::string::npos) << e.what();
  }
  EXPECT_THROW(selectDevice("0:x"), NoDeviceError);
  EXPECT_THROW(selectDevice("99:0"), NoDeviceError);
}

TEST(RuntimeSources, ResolvesIncludesFromTheEmbeddedTable) {
  const std::string source = resolveKernelSource("kernels/fill.cl");
  EXPECT_NE(source.find("PENUMBRA_KERNELS_SHARED_COMMON_H"), std::string::npos);
  EXPECT_NE(source.find("fill_float"), std::string::npos);
  EXPECT_EQ(source.find("#include \""), std::string::npos);
  EXPECT_THROW(resolveKernelSource("kernels/does_not_exist.cl"), std::runtime_error);
}

// The probe kernels (tools/selftest/kernels/) are a table the tests add to their contexts: the library ships none of
// them, they resolve the library's includes, and no name may be embedded twice.
TEST(RuntimeSources, ProbeKernelsAreATableOfTheTestsNotOfTheLibrary) {
  for (const EmbeddedSource& source : embeddedSources()) {
    EXPECT_FALSE(source.name.starts_with("tests/")) << source.name;
    for (const char* probe : {"sat_test_box", "moments_msm_decode_test", "fill_local_test", "vssm_visibility_receivers",
                              "shadow_depth_slope_test"})
      EXPECT_EQ(source.text.find(probe), std::string_view::npos) << source.name << " holds the probe " << probe;
  }
  EXPECT_THROW(resolveKernelSource("tools/selftest/kernels/vssm_probe.cl"), std::runtime_error);  // not the library's
  const std::string probe = resolveKernelSource("tools/selftest/kernels/vssm_probe.cl", {probeKernelSources()});
  EXPECT_NE(probe.find("vssm_visibility_receivers"), std::string::npos);
  EXPECT_NE(probe.find("vssm_pixel"), std::string::npos);  // kernels/vssm.cl, from the library's table
  const EmbeddedSource twice[] = {{"kernels/fill.cl", "__kernel void shadowing() {}"}};
  EXPECT_THROW(checkNewSources(twice, {}), std::logic_error);
  EXPECT_THROW(checkNewSources(probeKernelSources(), {probeKernelSources()}), std::logic_error);
}

// PENUMBRA_KERNEL_DIR: every source and include must be in the folder; nothing falls back to the embedded copy.
TEST(RuntimeSources, KernelDirMissingFileNamesTheFolderAndTheFile) {
  const fs::path dir = freshDir("kernel-dir");
  fs::create_directories(dir / "kernels");
  std::ofstream(dir / "kernels" / "fill.cl") << "#include \"kernels/shared/common.h\"\n__kernel void k() {}\n";
  EnvGuard kernels("PENUMBRA_KERNEL_DIR", dir.string());
  auto message = [](std::string_view name) {
    try {
      resolveKernelSource(name);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string include = message("kernels/fill.cl");  // the include is missing, the source is not
  EXPECT_NE(include.find("PENUMBRA_KERNEL_DIR=" + dir.string()), std::string::npos) << include;
  EXPECT_NE(include.find("has no kernels/shared/common.h"), std::string::npos) << include;
  const std::string source = message("kernels/blur.cl");  // embedded, but not in the folder
  EXPECT_NE(source.find("has no kernels/blur.cl"), std::string::npos) << source;
  {
    EnvGuard missing("PENUMBRA_KERNEL_DIR", (dir / "nothere").string());
    const std::string folder = message("kernels/fill.cl");
    EXPECT_NE(folder.find("nothere: not a folder"), std::string::npos) << folder;
  }
  fs::create_directories(dir / "kernels" / "shared");
  std::ofstream(dir / "kernels" / "shared" / "common.h") << "#define FROM_THE_FOLDER 1\n";
  EXPECT_NE(resolveKernelSource("kernels/fill.cl").find("FROM_THE_FOLDER"), std::string::npos);
  fs::remove_all(dir);
}

class Runtime : public ClTest {};

TEST_F(Runtime, ProbeKernelsBuildOnlyInContextsTheyWereAddedTo) {
  Kernel(ctx(), "tools/selftest/kernels/runtime_probe.cl", "fill_local_test", "test");  // the fixture added them
  Context bare;
  EXPECT_THROW(Kernel(bare, "tools/selftest/kernels/runtime_probe.cl", "fill_local_test", "test"), std::runtime_error);
  EXPECT_THROW(ctx().addSources(probeKernelSources()), std::logic_error);  // once per context
}

TEST_F(Runtime, ProgramCacheBuildsOnce) {
  const size_t before = ctx().programsBuilt();
  const cl::Program& a = ctx().program("kernels/fill.cl", "-DUNIQUE_FOR_CACHE_TEST=1");
  const cl::Program& b = ctx().program("kernels/fill.cl", "-DUNIQUE_FOR_CACHE_TEST=1");
  EXPECT_EQ(&a, &b);
  EXPECT_EQ(ctx().programsBuilt(), before + 1);
  ctx().program("kernels/fill.cl", "-DUNIQUE_FOR_CACHE_TEST=2");  // other options: another program
  EXPECT_EQ(ctx().programsBuilt(), before + 2);
}

TEST_F(Runtime, DiskCacheIsReusedByANewContext) {
  const fs::path dir = freshDir("cache");
  EnvGuard cache("PENUMBRA_CACHE_DIR", dir.string());
  {
    Context first(ctx().info());
    first.program("kernels/fill.cl", "-DDISK_CACHE_TEST=1");
    EXPECT_EQ(first.programsBuilt(), 1u);
  }
  EXPECT_FALSE(fs::is_empty(dir));
  Context second(ctx().info());
  second.program("kernels/fill.cl", "-DDISK_CACHE_TEST=1");
  EXPECT_EQ(second.programsBuilt(), 0u) << "the binary should come from " << dir;
  fs::remove_all(dir);
}

TEST_F(Runtime, BuildErrorCarriesTheLog) {
  const fs::path dir = freshDir("kernels");
  fs::create_directories(dir / "kernels");
  std::ofstream(dir / "kernels" / "fill.cl") << "__kernel void broken(__global float* x) { x[0] = undeclared; }\n";
  EnvGuard kernels("PENUMBRA_KERNEL_DIR", dir.string());
  try {
    ctx().program("kernels/fill.cl", "-DBUILD_ERROR_TEST=1");
    FAIL() << "expected BuildError";
  } catch (const BuildError& e) {
    EXPECT_NE(e.log().find("undeclared"), std::string::npos) << e.log();
    EXPECT_NE(std::string(e.what()).find("-DBUILD_ERROR_TEST=1"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(ctx().info().name), std::string::npos);
  }
  fs::remove_all(dir);
}

TEST(BuildRetry, TellsACacheRaceFromASourceError) {
  // The log PoCL printed when two tasks of a Slurm array built one kernel at once (a CI run, 2026-12-01).
  EXPECT_TRUE(isTransientBuildFailure(
      "error: <invalid loc>: unable to rename temporary '/b/pocl-cache/tempfile_LpyNUf.preproc-0230d274.cl.tmp' to "
      "output file '/b/pocl-cache/tempfile_LpyNUf.preproc.cl': 'No such file or directory'\n"
      "Device pthread-skylake-avx512-AMD EPYC failed to build the program\n"));
  EXPECT_TRUE(isTransientBuildFailure("Device pthread-haswell-AMD EPYC failed to build the program\n"));
  EXPECT_FALSE(isTransientBuildFailure("<source>:1:49: error: use of undeclared identifier 'undeclared'\n"));
  EXPECT_FALSE(isTransientBuildFailure("fatal error: 'missing.h' file not found\n"));
  EXPECT_FALSE(isTransientBuildFailure(""));
}

TEST_F(Runtime, LaunchPadsTheGlobalSizeAndKernelsBoundCheck) {
  constexpr uint32_t kCount = 1000;  // not a multiple of the work-group
  Buffer<float> out(ctx(), 1024);
  out.fill(ctx(), kPoison);
  Kernel fill(ctx(), "kernels/fill.cl", "fill_float", "test");
  fill.args(out, kCount, 3.5f).launch(kCount, 64);
  const std::vector<float> host = out.download(ctx());
  for (uint32_t i = 0; i < 1024; ++i) ASSERT_EQ(host[i], i < kCount ? 3.5f : kPoison) << "at " << i;
}

// Buffer::fill writes every element, for each pattern size the rasterizer and the tests use.
template <class T>
void expectFilled(Context& ctx, size_t count, const T& value) {
  Buffer<T> buffer(ctx, count);
  buffer.fill(ctx, value);
  for (const T& v : buffer.download(ctx)) ASSERT_EQ(std::memcmp(&v, &value, sizeof(T)), 0) << sizeof(T) << " bytes";
}

TEST_F(Runtime, FillWritesEveryElement) {
  expectFilled(ctx(), 1001, 0x12345678u);
  expectFilled(ctx(), 3, cl_float2{{1.5f, -2.0f}});
  expectFilled(ctx(), 1, cl_float4{{1, 2, 3, 4}});
  expectFilled(ctx(), 513, uint16_t{0xbeef});
  expectFilled(ctx(), 77, uint8_t{0xab});
}

// A region is a window on its parent: writes through it land at its offset and nowhere else; offsets the
// device cannot align are refused by name.
TEST_F(Runtime, RegionsWriteIntoTheirParent) {
  const size_t stride = Buffer<float>::alignedCount(ctx(), 37);
  ASSERT_GE(stride, 37u);
  ASSERT_EQ(stride * sizeof(float) % ctx().info().baseAddressAlignBytes, 0u);
  Buffer<float> parent(ctx(), 3 * stride);
  parent.fill(ctx(), kPoison);
  Buffer<float> middle = parent.region(ctx(), stride, 37);
  EXPECT_EQ(middle.size(), 37u);
  middle.fill(ctx(), 2.5f);
  const std::vector<float> host = parent.download(ctx());
  for (size_t i = 0; i < host.size(); ++i)
    ASSERT_EQ(host[i], i >= stride && i < stride + 37 ? 2.5f : kPoison) << "at " << i;
  EXPECT_THROW(parent.region(ctx(), 2 * stride, stride + 1), std::out_of_range);
  try {
    parent.region(ctx(), 1, 4);
    FAIL() << "a one-float offset is below every device's alignment";
  } catch (const ClError& e) {
    EXPECT_EQ(e.code(), CL_MISALIGNED_SUB_BUFFER_OFFSET);
  }
}

TEST_F(Runtime, LaunchChecksWorkGroupAndLocalMemoryLimits) {
  Buffer<float> out(ctx(), 16);
  Kernel fill(ctx(), "kernels/fill.cl", "fill_float", "test");
  fill.args(out, 16u, 0.0f);
  try {
    fill.launch(16, fill.maxWorkGroupSize() + 1);
    FAIL() << "expected ClError";
  } catch (const ClError& e) {
    EXPECT_EQ(e.code(), CL_INVALID_WORK_GROUP_SIZE);
    EXPECT_EQ(e.kernel(), "fill_float");
    EXPECT_EQ(e.stage(), "test");
  }
  Kernel local(ctx(), "tools/selftest/kernels/runtime_probe.cl", "fill_local_test", "test");
  local.args(out, 16u, LocalMem{static_cast<size_t>(ctx().info().localMemBytes) + 4});
  try {
    local.launch(16, 16);
    FAIL() << "expected ClError";
  } catch (const ClError& e) {
    EXPECT_EQ(e.code(), CL_OUT_OF_RESOURCES);
  }
}

TEST_F(Runtime, EmptyLaunchAndEmptyBuffers) {
  Buffer<float> empty(ctx(), 0);
  EXPECT_TRUE(empty.download(ctx()).empty());
  Kernel fill(ctx(), "kernels/fill.cl", "fill_float", "test");
  cl::Event done = fill.args(empty, 0u, 1.0f).launch(0, 64);
  EXPECT_EQ(done.wait(), CL_SUCCESS);
}

TEST_F(Runtime, BufferRoundTripAndProfiling) {
  Profiler profiler;
  ctx().setProfiler(&profiler);
  std::vector<cl_float4> data(333);
  for (size_t i = 0; i < data.size(); ++i) data[i] = {{float(i), -float(i), 0.5f, 1e30f}};
  Buffer<cl_float4> in(ctx(), std::span<const cl_float4>(data));
  Buffer<cl_float4> out(ctx(), data.size());
  Kernel copy(ctx(), "kernels/fill.cl", "copy_float4", "test");
  copy.args(in, out, uint32_t(data.size())).launch(data.size(), 32);
  const std::vector<cl_float4> back = out.download(ctx());
  ctx().setProfiler(nullptr);
  for (size_t i = 0; i < data.size(); ++i)
    for (int c = 0; c < 4; ++c) ASSERT_EQ(back[i].s[c], data[i].s[c]);
  const std::vector<PassTime> passes = profiler.resolve();
  ASSERT_EQ(passes.size(), 3u);
  EXPECT_EQ(passes[0].name, "transfer/upload");
  EXPECT_EQ(passes[1].name, "test/copy_float4");
  EXPECT_EQ(passes[2].name, "transfer/download");
  for (const PassTime& pass : passes) EXPECT_GE(pass.ms, 0.0);
}

TEST_F(Runtime, TwoContextsInOneProcess) {
  Context other(ctx().info());
  Buffer<float> a(ctx(), 8), b(other, 8);
  Kernel fillA(ctx(), "kernels/fill.cl", "fill_float", "test");
  Kernel fillB(other, "kernels/fill.cl", "fill_float", "test");
  fillA.args(a, 8u, 1.0f).launch(8, 8);
  fillB.args(b, 8u, 2.0f).launch(8, 8);
  EXPECT_EQ(a.download(ctx())[7], 1.0f);
  EXPECT_EQ(b.download(other)[7], 2.0f);
}

}  // namespace runtime_test
}  // namespace penumbra
