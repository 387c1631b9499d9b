// The explicit OpenCL context every stage receives: one device, its context, an in-order profiling queue,
// the device's limits and a program cache. No global state: two Contexts (two devices) can live side by
// side in one process.
#pragma once

#include <CL/opencl.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "host/cl/device.h"
#include "host/cl/embedded_sources.h"

namespace penumbra {

// What a program sets of a context instead of the environment (the library's pn_context_options); unset fields keep
// the environment's (PENUMBRA_CACHE_DIR, PENUMBRA_LOCAL_MEM_LIMIT, PENUMBRA_LAYOUTS), as the command line reads them.
struct ContextOptions {
  std::optional<std::string> cacheDir;  // compiled programs kept on disk there; "": no disk cache
  DeviceOverrides device;
  // Told of every program built (its source, the time the build took) or loaded from the disk cache, on the thread
  // that asked for it and under the context's program lock: it must not call back into the context.
  std::function<void(const std::string&)> log;
};

class Context {
 public:
  // Opens the device chosen by `deviceSpec` (see selectDevice). Throws NoDeviceError / ClError.
  explicit Context(const std::string& deviceSpec = {}, const ContextOptions& options = {});
  explicit Context(DeviceInfo device, const ContextOptions& options = {});
  // Works on the caller's objects (the public API's interop, issue 17): no context or queue of its own. Keeps one
  // retain on each for its lifetime and releases only that; never finishes the queue. The queue must be in-order
  // (the stages rely on it) and belong to `context` and `device`: throws std::invalid_argument otherwise. Without
  // CL_QUEUE_PROFILING_ENABLE on the queue, pass times read 0 (Profiler::resolve).
  Context(cl_context context, cl_device_id device, cl_command_queue queue, const ContextOptions& options = {});
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  // Waits for every command enqueued on its own queue (a caller's queue is left alone): a stage that throws leaves
  // earlier launches in flight, and releasing the queue does not wait for them. PoCL's device threads, still
  // building such a kernel while the process exits, crashed in LLVM's torn-down statics (exit 139 instead of the
  // error's exit code).
  ~Context();

  const DeviceInfo& info() const { return info_; }
  const cl::Context& context() const { return context_; }
  const cl::Device& device() const { return device_; }
  cl::CommandQueue& queue() { return queue_; }

  // The program built from the embedded source `sourceName` (see embedded_sources.h) with `options`,
  // built once per (source text hash, options) and kept. With a cache folder (cacheDir()), binaries are also
  // stored on disk, keyed by the source hash, options, platform, device and driver version.
  // Throws BuildError with the build log on failure.
  const cl::Program& program(const std::string& sourceName, const std::string& options = {});
  // Sources this context's programs may also be built from, searched after the library's table: the tests' and
  // benchmarks' probe kernels (tools/selftest/kernels/, the selftest's too). Throws std::logic_error for a name already
  // known.
  void addSources(std::span<const EmbeddedSource> table);

  // Options every program gets: -cl-std=CL1.2, feature macros
  // (PENUMBRA_HAS_FP64, PENUMBRA_HAS_INT64_ATOMICS) and the caller's options.
  std::string buildOptions(const std::string& options) const;

  size_t programsBuilt() const { return programsBuilt_; }  // compiled here, not loaded from a cache
  size_t programsLoaded() const { return programsLoaded_; }  // loaded from the disk cache
  const std::string& cacheDir() const { return cacheDir_; }  // "" when there is no disk cache
  bool ownsQueue() const { return ownsQueue_; }             // false: the caller's queue (the interop constructor)
  void finish();

  // Simulators only (DeviceInfo::isSimulator): a reference to every buffer a Buffer creates, held until this
  // context goes. Oclgrind 21.10 hands a released buffer's id to the next allocation and keeps the old buffer's
  // shadow for its uninitialised-value check (of the old size), so a buffer reusing the id reads as uninitialised
  // past the old end; memory never released is never reused. Frames on a simulator are small.
  void retire(cl::Buffer memory);

  // Where launches report their events (nullptr: nowhere). Owned by the caller.
  void setProfiler(class Profiler* profiler) { profiler_ = profiler; }
  class Profiler* profiler() const {
    return profiler_;
  }

 private:
  cl::Program compileWithRetry(const std::string& sourceName, const std::string& source, const std::string& options);
  cl::Program buildProgram(const std::string& sourceName, const std::string& source, const std::string& options,
                           uint64_t sourceHash);
  void configure(const ContextOptions& options);  // the constructors' common part: cache folder and log
  void log(const std::string& message) const {
    if (log_) log_(message);
  }

  DeviceInfo info_;
  cl::Device device_;
  cl::Context context_;
  cl::CommandQueue queue_;
  std::mutex mutex_;
  std::map<std::tuple<std::string, std::string>, std::unique_ptr<cl::Program>> programs_;
  SourceTables sources_;  // addSources()
  size_t programsBuilt_ = 0, programsLoaded_ = 0;
  std::string cacheDir_;
  std::function<void(const std::string&)> log_;
  bool ownsQueue_ = true;
  class Profiler* profiler_ = nullptr;
  std::vector<cl::Buffer> retired_;  // retire()
};

// Whether a build log reports the implementation's own files failing (a kernel-cache race between processes) rather
// than a problem in the source; such builds are retried.
bool isTransientBuildFailure(std::string_view log);

// 64-bit FNV-1a: the program cache key. Not cryptographic; collisions only rebuild or, with a disk cache,
// are guarded by storing the full key beside the binary.
uint64_t fnv1a64(std::string_view text, uint64_t seed = 14695981039346656037ull);

}  // namespace penumbra
