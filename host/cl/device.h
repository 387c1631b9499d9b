// OpenCL platforms and devices: what each can do (the facts our kernels depend on) and how a user picks
// one (`--device` / PENUMBRA_DEVICE). Platforms are ordered by name, never by the loader's order, so
// "PLATFORM:DEVICE" indices are stable between runs and machines with the same drivers.
#pragma once

#include <CL/cl.h>

#include <array>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

struct DeviceInfo {
  cl_platform_id platform = nullptr;
  cl_device_id device = nullptr;
  unsigned platformIndex = 0;  // position among platforms sorted by name
  unsigned deviceIndex = 0;    // position within the platform, as the platform reports it
  std::string platformName, platformVersion;
  std::string name, vendor, driverVersion, deviceVersion, openclCVersion;
  cl_device_type type = 0;
  int openclCMajor = 1, openclCMinor = 2;  // highest OpenCL C version the device compiles
  unsigned computeUnits = 0;
  unsigned maxClockMHz = 0;
  size_t maxWorkGroupSize = 0;
  std::array<size_t, 3> maxWorkItemSizes{};
  uint64_t localMemBytes = 0;  // what plans and launch checks use: the device's, or PENUMBRA_LOCAL_MEM_LIMIT's cap
  uint64_t deviceLocalMemBytes = 0;  // CL_DEVICE_LOCAL_MEM_SIZE as the device reports it
  bool localMemDedicated = false;    // CL_LOCAL vs emulated in global memory (CPU devices)
  uint64_t globalMemBytes = 0;
  uint64_t maxAllocBytes = 0;
  uint32_t baseAddressAlignBytes = 128;  // CL_DEVICE_MEM_BASE_ADDR_ALIGN (bits / 8): sub-buffer offsets
  bool fp64 = false;
  bool fp16 = false;
  bool int64Atomics = false;  // cl_khr_int64_base_atomics
  bool subGroups = false;     // cl_khr_subgroups or OpenCL 3.0 max sub-groups > 0
  bool nonUniformWorkGroups = false;
  std::vector<std::string> extensions;
  // Which tuned layouts Auto choices take: "" the device's own (by type and vendor), "gpu" those of GPUs, "nvidia"
  // those of NVIDIA's (PENUMBRA_LAYOUTS), so that PoCL and Oclgrind run the code paths of the target GPU.
  std::string layouts;

  bool isGpu() const { return (type & CL_DEVICE_TYPE_GPU) != 0; }
  bool isCpu() const { return (type & CL_DEVICE_TYPE_CPU) != 0; }
  // A simulator rather than hardware: Oclgrind (which reports itself as a GPU) by its platform or device name.
  bool isSimulator() const;
  // Whether Auto choices take the CPU layouts: a CPU device with no GPU layouts forced.
  bool cpuLayouts() const { return layouts.empty() && isCpu(); }
  bool hasExtension(const std::string& name) const;
  std::string typeName() const;  // "GPU", "CPU", "ACCELERATOR", ...
};

// Test hooks, read whenever a device is described (so `penumbra devices` shows them): PENUMBRA_LOCAL_MEM_LIMIT=BYTES
// caps localMemBytes (every plan then tiles as for a device of that much local memory, and a launch above it fails
// as it would there) and PENUMBRA_LAYOUTS=gpu|nvidia sets `layouts`. Throws std::invalid_argument on a bad value.
void applyDeviceOverrides(DeviceInfo& info);

// The same overrides given by a program instead of the environment (the library's pn_context_options): unset fields
// leave what the environment set. localMemLimit > 0 caps localMemBytes at the device's; layouts is "" (the device's
// own table), "gpu" or "nvidia". Throws std::invalid_argument on a bad value.
struct DeviceOverrides {
  std::optional<uint64_t> localMemLimit;
  std::optional<std::string> layouts;
};
void applyDeviceOverrides(DeviceInfo& info, const DeviceOverrides& overrides);

// Every device of every platform, platforms sorted by name. Empty when there is no ICD or no platform.
std::vector<DeviceInfo> listDevices();

// Picks a device by spec: "auto" (the first GPU, else the first CPU, else the first device, simulators such as
// Oclgrind only when there is nothing else), "cpu", "gpu", a case-insensitive name substring matched against device
// and platform names ("H100", "pthread", "oclgrind"), or "P:D" where P is a platform index or platform-name
// substring and D a device index. An empty spec means PENUMBRA_DEVICE, else "auto". Throws NoDeviceError with the
// list of devices when none matches.
DeviceInfo selectDevice(const std::string& spec);

// selectDevice's choice among `devices` for a non-empty `spec`.
DeviceInfo chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& spec);

// What `device` (a caller's, issue 17's interop) can do, with its "P:D" indices as listDevices() numbers it.
// Throws ClError when the device cannot be queried.
DeviceInfo describeDevice(cl_device_id device);

nlohmann::json toJson(const DeviceInfo& info);
std::string describeDevices(const std::vector<DeviceInfo>& devices);  // the `penumbra devices` table

}  // namespace penumbra
