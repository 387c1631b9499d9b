// Context: device, queue, and the program cache (memory, then an optional disk cache: ContextOptions::cacheDir or
// PENUMBRA_CACHE_DIR).
#include "host/cl/context.h"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "host/cl/embedded_sources.h"
#include "host/cl/error.h"

namespace penumbra {
namespace fs = std::filesystem;

uint64_t fnv1a64(std::string_view text, uint64_t seed) {
  uint64_t hash = seed;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

namespace {

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Where a binary for this key lives in `dir`, or empty when the disk cache is off (`dir` empty).
fs::path cachePath(const std::string& dir, const DeviceInfo& info, uint64_t sourceHash, const std::string& options) {
  if (dir.empty()) return {};
  std::string key =
      fmt::format("{}|{}|{}|{}|{}", info.platformName, info.name, info.driverVersion, info.deviceVersion, options);
  return fs::path(dir) / fmt::format("{:016x}-{:016x}.bin", sourceHash, fnv1a64(key));
}

std::string buildLog(const cl::Program& program, const cl::Device& device) {
  std::string log;
  program.getBuildInfo(device, CL_PROGRAM_BUILD_LOG, &log);
  return log;
}

}  // namespace

Context::Context(const std::string& deviceSpec, const ContextOptions& options)
    : Context(selectDevice(deviceSpec), options) {}

void Context::configure(const ContextOptions& options) {
  applyDeviceOverrides(info_, options.device);
  if (options.cacheDir) {
    cacheDir_ = *options.cacheDir;
  } else if (const char* dir = std::getenv("PENUMBRA_CACHE_DIR"); dir != nullptr) {
    cacheDir_ = dir;
  }
  log_ = options.log;
}

void Context::retire(cl::Buffer memory) {
  std::lock_guard<std::mutex> lock(mutex_);
  retired_.push_back(std::move(memory));
}

Context::~Context() {
  if (ownsQueue_ && queue_() != nullptr) clFinish(queue_());  // errors ignored: nothing left to report them to
}

Context::Context(DeviceInfo device, const ContextOptions& options)
    : info_(std::move(device)), device_(info_.device, true) {
  configure(options);
  cl_int err = CL_SUCCESS;
  context_ = cl::Context(device_, nullptr, nullptr, nullptr, &err);
  clCheck(err, "clCreateContext", {}, "runtime");
  queue_ = cl::CommandQueue(context_, device_, CL_QUEUE_PROFILING_ENABLE, &err);
  clCheck(err, "clCreateCommandQueue", {}, "runtime");
}

namespace {

template <class T>
T queueInfo(cl_command_queue queue, cl_command_queue_info param) {
  T value{};
  clCheck(clGetCommandQueueInfo(queue, param, sizeof(T), &value, nullptr), "clGetCommandQueueInfo", {}, "runtime");
  return value;
}

// The caller's objects must fit together: the device in the context, the queue on both, in order.
void checkCallerObjects(cl_context context, cl_device_id device, cl_command_queue queue) {
  if (context == nullptr || device == nullptr || queue == nullptr)
    throw std::invalid_argument("OpenCL interop: the context, device and queue must all be given");
  size_t bytes = 0;
  clCheck(clGetContextInfo(context, CL_CONTEXT_DEVICES, 0, nullptr, &bytes), "clGetContextInfo", {}, "runtime");
  std::vector<cl_device_id> devices(bytes / sizeof(cl_device_id));
  clCheck(clGetContextInfo(context, CL_CONTEXT_DEVICES, bytes, devices.data(), nullptr), "clGetContextInfo", {},
          "runtime");
  if (std::find(devices.begin(), devices.end(), device) == devices.end())
    throw std::invalid_argument("OpenCL interop: the device is not one of the context's devices");
  if (queueInfo<cl_context>(queue, CL_QUEUE_CONTEXT) != context)
    throw std::invalid_argument("OpenCL interop: the queue belongs to another context");
  if (queueInfo<cl_device_id>(queue, CL_QUEUE_DEVICE) != device)
    throw std::invalid_argument("OpenCL interop: the queue belongs to another device");
  if (queueInfo<cl_command_queue_properties>(queue, CL_QUEUE_PROPERTIES) & CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE)
    throw std::invalid_argument(
        "OpenCL interop: the queue is out of order; penumbra's stages need an in-order queue (their passes "
        "depend on each other)");
}

}  // namespace

bool isTransientBuildFailure(std::string_view log) {
  // What an implementation prints when its own temporary or cache files vanish or cannot be written, as opposed to a
  // diagnostic about the source. Two forms were seen with PoCL 3.1 under concurrent builds: Clang's driver message
  // about a temporary file, and a bare "failed to build the program" with no diagnostic at all. A problem in the
  // source always comes with an "error:" line.
  for (std::string_view marker : {"unable to rename temporary", "unable to open output file",
                                  "unable to open temporary", "Could not create topdir for cache"})
    if (log.find(marker) != std::string_view::npos) return true;
  return !log.empty() && log.find("error") == std::string_view::npos;
}

Context::Context(cl_context context, cl_device_id device, cl_command_queue queue, const ContextOptions& options) {
  checkCallerObjects(context, device, queue);
  info_ = describeDevice(device);
  configure(options);
  device_ = cl::Device(device, true);  // each cl:: wrapper holds one retain and releases it when destroyed
  context_ = cl::Context(context, true);
  queue_ = cl::CommandQueue(queue, true);
  ownsQueue_ = false;
}

std::string Context::buildOptions(const std::string& options) const {
  // Kernels are OpenCL C 1.2; everything newer is detected and passed in as a macro.
  std::string all = "-cl-std=CL1.2";
  if (info_.fp64) all += " -DPENUMBRA_HAS_FP64=1";
  if (info_.int64Atomics) all += " -DPENUMBRA_HAS_INT64_ATOMICS=1";
  // kernels/shared/common.h PN_PREFETCH: software prefetch on CPU devices, not under Oclgrind (no llvm.prefetch there).
  if (info_.cpuLayouts() && !info_.isSimulator()) all += " -DPENUMBRA_CPU_LAYOUTS=1";
  if (!options.empty()) all += " " + options;
  return all;
}

void Context::addSources(std::span<const EmbeddedSource> table) {
  std::lock_guard lock(mutex_);
  checkNewSources(table, sources_);
  sources_.push_back(table);
}

const cl::Program& Context::program(const std::string& sourceName, const std::string& options) {
  std::lock_guard lock(mutex_);
  const std::string all = buildOptions(options);
  auto key = std::make_tuple(sourceName, all);
  if (auto it = programs_.find(key); it != programs_.end()) return *it->second;
  const std::string source = resolveKernelSource(sourceName, sources_);
  auto program = std::make_unique<cl::Program>(buildProgram(sourceName, source, all, fnv1a64(source)));
  return *programs_.emplace(key, std::move(program)).first->second;
}

cl::Program Context::compileWithRetry(const std::string& sourceName, const std::string& source,
                                      const std::string& options) {
  // PoCL keeps its own kernel cache (POCL_CACHE_DIR) and compiles through temporary files in it; two processes
  // building the same source at once (tasks of one job array on one node) can remove each other's temporaries, and
  // the build then fails with "unable to rename temporary ... No such file or directory" although the source is
  // fine (pocl/pocl#430). Such a failure names the file system, not the source: it is retried, a few times with a
  // short pause; a real compile error fails the same way every time and is reported with its log after one try.
  constexpr int kAttempts = 4;
  for (int attempt = 1;; ++attempt) {
    cl_int err = CL_SUCCESS;
    cl::Program program(context_, source, false, &err);
    clCheck(err, "clCreateProgramWithSource", sourceName, "runtime");
    err = program.build({device_}, options.c_str());
    if (err == CL_BUILD_PROGRAM_FAILURE || err == CL_INVALID_BUILD_OPTIONS) {
      std::string log = buildLog(program, device_);
      if (attempt < kAttempts && isTransientBuildFailure(log)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20 * attempt));
        continue;
      }
      throw BuildError(sourceName, info_.name, options, std::move(log));
    }
    clCheck(err, "clBuildProgram", sourceName, "runtime");
    return program;
  }
}

cl::Program Context::buildProgram(const std::string& sourceName, const std::string& source, const std::string& options,
                                  uint64_t sourceHash) {
  cl_int err = CL_SUCCESS;
  const fs::path cached = cachePath(cacheDir_, info_, sourceHash, options);
  if (!cached.empty() && fs::is_regular_file(cached)) {
    std::string bytes = readFile(cached);
    cl::Program::Binaries binaries{std::vector<unsigned char>(bytes.begin(), bytes.end())};
    cl::Program program(context_, {device_}, binaries, nullptr, &err);
    if (err == CL_SUCCESS && program.build({device_}, options.c_str()) == CL_SUCCESS) {
      ++programsLoaded_;
      log(fmt::format("loaded {} from the cache ({})", sourceName, options));
      return program;
    }
    // A stale or foreign binary: fall through and rebuild from source.
  }
  const auto start = std::chrono::steady_clock::now();
  cl::Program program = compileWithRetry(sourceName, source, options);
  ++programsBuilt_;
  log(fmt::format("built {} in {:.0f} ms ({})", sourceName,
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(),
                  options));
  if (!cached.empty()) {
    std::vector<std::vector<unsigned char>> binaries;
    if (program.getInfo(CL_PROGRAM_BINARIES, &binaries) == CL_SUCCESS && binaries.size() == 1 && !binaries[0].empty()) {
      std::error_code ec;
      fs::create_directories(cached.parent_path(), ec);
      // The process id keeps two processes (a Slurm array's tasks on one node) from sharing a temporary name.
      const fs::path temp = cached.string() + fmt::format(".{}.{}.tmp", ::getpid(), static_cast<const void*>(this));
      std::ofstream(temp, std::ios::binary)
          .write(reinterpret_cast<const char*>(binaries[0].data()), static_cast<std::streamsize>(binaries[0].size()));
      fs::rename(temp, cached, ec);  // atomic publish; a failure only loses the cache entry
    }
  }
  return program;
}

void Context::finish() { clCheck(queue_.finish(), "clFinish", {}, "runtime"); }

}  // namespace penumbra
