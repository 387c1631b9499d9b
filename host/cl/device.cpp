// Enumerates OpenCL devices through the C API and picks one from a user's spec.
#include "host/cl/device.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "host/cl/error.h"

namespace penumbra {
namespace {

std::string platformString(cl_platform_id platform, cl_platform_info param) {
  size_t size = 0;
  if (clGetPlatformInfo(platform, param, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string value(size, '\0');
  clGetPlatformInfo(platform, param, size, value.data(), nullptr);
  value.resize(std::strlen(value.c_str()));
  return value;
}

std::string deviceString(cl_device_id device, cl_device_info param) {
  size_t size = 0;
  if (clGetDeviceInfo(device, param, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string value(size, '\0');
  clGetDeviceInfo(device, param, size, value.data(), nullptr);
  value.resize(std::strlen(value.c_str()));
  return value;
}

template <class T>
T deviceValue(cl_device_id device, cl_device_info param, T fallback = T{}) {
  T value{};
  return clGetDeviceInfo(device, param, sizeof(T), &value, nullptr) == CL_SUCCESS ? value : fallback;
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

bool contains(const std::string& haystack, const std::string& needle) {
  return lower(haystack).find(lower(needle)) != std::string::npos;
}

// "OpenCL C 1.2 PoCL" -> (1, 2).
void parseOpenclC(DeviceInfo& info) {
  int major = 1, minor = 2;
  if (std::sscanf(info.openclCVersion.c_str(), "OpenCL C %d.%d", &major, &minor) == 2) {
    info.openclCMajor = major;
    info.openclCMinor = minor;
  }
}

DeviceInfo describe(cl_platform_id platform, cl_device_id device) {
  DeviceInfo info;
  info.platform = platform;
  info.device = device;
  info.platformName = platformString(platform, CL_PLATFORM_NAME);
  info.platformVersion = platformString(platform, CL_PLATFORM_VERSION);
  info.name = deviceString(device, CL_DEVICE_NAME);
  info.vendor = deviceString(device, CL_DEVICE_VENDOR);
  info.driverVersion = deviceString(device, CL_DRIVER_VERSION);
  info.deviceVersion = deviceString(device, CL_DEVICE_VERSION);
  info.openclCVersion = deviceString(device, CL_DEVICE_OPENCL_C_VERSION);
  parseOpenclC(info);
  info.type = deviceValue<cl_device_type>(device, CL_DEVICE_TYPE);
  info.computeUnits = deviceValue<cl_uint>(device, CL_DEVICE_MAX_COMPUTE_UNITS);
  info.maxClockMHz = deviceValue<cl_uint>(device, CL_DEVICE_MAX_CLOCK_FREQUENCY);
  info.maxWorkGroupSize = deviceValue<size_t>(device, CL_DEVICE_MAX_WORK_GROUP_SIZE);
  clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_ITEM_SIZES, sizeof(info.maxWorkItemSizes), info.maxWorkItemSizes.data(),
                  nullptr);
  info.localMemBytes = info.deviceLocalMemBytes = deviceValue<cl_ulong>(device, CL_DEVICE_LOCAL_MEM_SIZE);
  info.localMemDedicated = deviceValue<cl_device_local_mem_type>(device, CL_DEVICE_LOCAL_MEM_TYPE) == CL_LOCAL;
  info.globalMemBytes = deviceValue<cl_ulong>(device, CL_DEVICE_GLOBAL_MEM_SIZE);
  info.maxAllocBytes = deviceValue<cl_ulong>(device, CL_DEVICE_MAX_MEM_ALLOC_SIZE);
  info.baseAddressAlignBytes = std::max<cl_uint>(8, deviceValue<cl_uint>(device, CL_DEVICE_MEM_BASE_ADDR_ALIGN)) / 8;
  std::istringstream words(deviceString(device, CL_DEVICE_EXTENSIONS));
  for (std::string word; words >> word;) info.extensions.push_back(word);
  std::sort(info.extensions.begin(), info.extensions.end());
  info.fp64 =
      info.hasExtension("cl_khr_fp64") || deviceValue<cl_device_fp_config>(device, CL_DEVICE_DOUBLE_FP_CONFIG) != 0;
  info.fp16 = info.hasExtension("cl_khr_fp16");
  info.int64Atomics = info.hasExtension("cl_khr_int64_base_atomics");
  // OpenCL 3.0 queries; a 1.2 device rejects them and the fallback (0 / false) stands.
  info.subGroups =
      info.hasExtension("cl_khr_subgroups") || deviceValue<cl_uint>(device, CL_DEVICE_MAX_NUM_SUB_GROUPS) > 0;
  info.nonUniformWorkGroups = deviceValue<cl_bool>(device, CL_DEVICE_NON_UNIFORM_WORK_GROUP_SUPPORT) != 0;
  applyDeviceOverrides(info);
  return info;
}

std::vector<cl_platform_id> platformsByName() {
  cl_uint count = 0;
  // No ICD at all gives CL_PLATFORM_NOT_FOUND_KHR (-1001): that is "no platform", not an error.
  if (clGetPlatformIDs(0, nullptr, &count) != CL_SUCCESS || count == 0) return {};
  std::vector<cl_platform_id> platforms(count);
  clCheck(clGetPlatformIDs(count, platforms.data(), nullptr), "clGetPlatformIDs");
  std::stable_sort(platforms.begin(), platforms.end(), [](cl_platform_id a, cl_platform_id b) {
    return platformString(a, CL_PLATFORM_NAME) < platformString(b, CL_PLATFORM_NAME);
  });
  return platforms;
}

std::string knownDevices(const std::vector<DeviceInfo>& devices) {
  if (devices.empty())
    return "no OpenCL platform was found (is an ICD such as pocl-opencl-icd installed and registered in "
           "/etc/OpenCL/vendors or OCL_ICD_VENDORS?)";
  std::string text = "available devices:";
  for (const DeviceInfo& d : devices)
    text +=
        fmt::format("\n  {}:{}  {} — {} ({})", d.platformIndex, d.deviceIndex, d.platformName, d.name, d.typeName());
  return text;
}

bool isIndex(const std::string& text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

}  // namespace

bool DeviceInfo::hasExtension(const std::string& extension) const {
  return std::binary_search(extensions.begin(), extensions.end(), extension);
}

std::string DeviceInfo::typeName() const {
  if (type & CL_DEVICE_TYPE_GPU) return "GPU";
  if (type & CL_DEVICE_TYPE_CPU) return "CPU";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "ACCELERATOR";
  return "OTHER";
}

std::vector<DeviceInfo> listDevices() {
  std::vector<DeviceInfo> devices;
  std::vector<cl_platform_id> platforms = platformsByName();
  for (unsigned p = 0; p < platforms.size(); ++p) {
    cl_uint count = 0;
    if (clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 0, nullptr, &count) != CL_SUCCESS) continue;
    std::vector<cl_device_id> ids(count);
    clCheck(clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr), "clGetDeviceIDs");
    for (unsigned d = 0; d < count; ++d) {
      DeviceInfo info = describe(platforms[p], ids[d]);
      info.platformIndex = p;
      info.deviceIndex = d;
      devices.push_back(std::move(info));
    }
  }
  return devices;
}

namespace {
bool isLayoutsName(const std::string& layouts) { return layouts == "gpu" || layouts == "nvidia"; }
}  // namespace

// The environment's overrides, each checked with the variable's name, applied as a program's are.
void applyDeviceOverrides(DeviceInfo& info) {
  DeviceOverrides overrides;
  if (const char* limit = std::getenv("PENUMBRA_LOCAL_MEM_LIMIT"); limit != nullptr && *limit != '\0') {
    char* end = nullptr;
    const unsigned long long bytes = std::strtoull(limit, &end, 10);
    if (*end != '\0' || bytes == 0 || !std::isdigit(static_cast<unsigned char>(*limit)))
      throw std::invalid_argument(fmt::format("PENUMBRA_LOCAL_MEM_LIMIT '{}': expected a byte count", limit));
    overrides.localMemLimit = bytes;
  }
  if (const char* layouts = std::getenv("PENUMBRA_LAYOUTS"); layouts != nullptr && *layouts != '\0') {
    if (!isLayoutsName(lower(layouts)))
      throw std::invalid_argument(fmt::format("PENUMBRA_LAYOUTS '{}': expected gpu or nvidia", layouts));
    overrides.layouts = layouts;
  }
  applyDeviceOverrides(info, overrides);
}

void applyDeviceOverrides(DeviceInfo& info, const DeviceOverrides& overrides) {
  if (overrides.localMemLimit) {
    if (*overrides.localMemLimit == 0) throw std::invalid_argument("local memory limit: 0 bytes (at least 1)");
    info.localMemBytes = std::min<uint64_t>(info.deviceLocalMemBytes, *overrides.localMemLimit);
  }
  if (overrides.layouts) {
    const std::string layouts = lower(*overrides.layouts);
    if (!layouts.empty() && !isLayoutsName(layouts))
      throw std::invalid_argument(
          fmt::format("work-group layouts '{}': expected gpu, nvidia, or none for the device's own", layouts));
    info.layouts = layouts;
  }
}

bool DeviceInfo::isSimulator() const { return contains(platformName, "oclgrind") || contains(name, "oclgrind"); }

DeviceInfo selectDevice(const std::string& requested) {
  std::string spec = requested;
  if (spec.empty()) {
    const char* env = std::getenv("PENUMBRA_DEVICE");
    spec = env != nullptr && *env != '\0' ? env : "auto";
  }
  return chooseDevice(listDevices(), spec);
}

DeviceInfo chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& spec) {
  auto first = [&](auto&& predicate) -> const DeviceInfo* {
    auto it = std::find_if(devices.begin(), devices.end(), predicate);
    return it == devices.end() ? nullptr : &*it;
  };
  const DeviceInfo* chosen = nullptr;
  const std::string key = lower(spec);
  if (key == "auto") {
    chosen = first([](const DeviceInfo& d) { return d.isGpu() && !d.isSimulator(); });
    if (chosen == nullptr) chosen = first([](const DeviceInfo& d) { return d.isCpu() && !d.isSimulator(); });
    if (chosen == nullptr) chosen = first([](const DeviceInfo& d) { return !d.isSimulator(); });
    if (chosen == nullptr && !devices.empty()) chosen = &devices.front();
  } else if (key == "gpu" || key == "cpu") {
    chosen = first([&](const DeviceInfo& d) { return key == "gpu" ? d.isGpu() : d.isCpu(); });
  } else if (size_t colon = spec.find(':'); colon != std::string::npos) {
    const std::string platform = spec.substr(0, colon), device = spec.substr(colon + 1);
    if (!isIndex(device))
      throw NoDeviceError(fmt::format("device spec '{}': the part after ':' must be a device index", spec));
    chosen = first([&](const DeviceInfo& d) {
      bool platformMatches =
          isIndex(platform) ? d.platformIndex == std::stoul(platform) : contains(d.platformName, platform);
      return platformMatches && d.deviceIndex == std::stoul(device);
    });
  } else {
    chosen = first([&](const DeviceInfo& d) { return contains(d.name, spec) || contains(d.platformName, spec); });
  }
  if (chosen == nullptr)
    throw NoDeviceError(fmt::format("no OpenCL device matches '{}'; {}", spec, knownDevices(devices)));
  return *chosen;
}

DeviceInfo describeDevice(cl_device_id device) {
  cl_platform_id platform = nullptr;
  clCheck(clGetDeviceInfo(device, CL_DEVICE_PLATFORM, sizeof(platform), &platform, nullptr),
          "clGetDeviceInfo(CL_DEVICE_PLATFORM)", {}, "runtime");
  DeviceInfo info = describe(platform, device);
  for (const DeviceInfo& listed : listDevices())
    if (listed.device == device) info.platformIndex = listed.platformIndex, info.deviceIndex = listed.deviceIndex;
  return info;
}

nlohmann::json toJson(const DeviceInfo& d) {
  return {{"platform_index", d.platformIndex},
          {"device_index", d.deviceIndex},
          {"platform", d.platformName},
          {"platform_version", d.platformVersion},
          {"name", d.name},
          {"vendor", d.vendor},
          {"type", d.typeName()},
          {"driver_version", d.driverVersion},
          {"device_version", d.deviceVersion},
          {"opencl_c_version", d.openclCVersion},
          {"compute_units", d.computeUnits},
          {"max_clock_mhz", d.maxClockMHz},
          {"max_work_group_size", d.maxWorkGroupSize},
          {"max_work_item_sizes", d.maxWorkItemSizes},
          {"local_mem_bytes", d.localMemBytes},
          {"device_local_mem_bytes", d.deviceLocalMemBytes},
          {"layouts", d.layouts.empty() ? "device" : d.layouts},
          {"local_mem_dedicated", d.localMemDedicated},
          {"global_mem_bytes", d.globalMemBytes},
          {"max_alloc_bytes", d.maxAllocBytes},
          {"fp64", d.fp64},
          {"fp16", d.fp16},
          {"int64_atomics", d.int64Atomics},
          {"sub_groups", d.subGroups},
          {"non_uniform_work_groups", d.nonUniformWorkGroups},
          {"extensions", d.extensions}};
}

std::string describeDevices(const std::vector<DeviceInfo>& devices) {
  if (devices.empty()) return knownDevices(devices) + "\n";
  std::string text;
  for (const DeviceInfo& d : devices) {
    text += fmt::format("{}:{}  {}  [{}]  platform '{}' ({})\n", d.platformIndex, d.deviceIndex, d.name, d.typeName(),
                        d.platformName, d.platformVersion);
    text += fmt::format("      driver {}, {}, {} compute units @ {} MHz\n", d.driverVersion, d.openclCVersion,
                        d.computeUnits, d.maxClockMHz);
    text += fmt::format("      global {:.1f} GiB (max alloc {:.1f} GiB), local {} KiB ({}{}), max work-group {}\n",
                        d.globalMemBytes / 1073741824.0, d.maxAllocBytes / 1073741824.0, d.localMemBytes / 1024,
                        d.localMemDedicated ? "dedicated" : "emulated in global",
                        d.localMemBytes < d.deviceLocalMemBytes ? ", capped by PENUMBRA_LOCAL_MEM_LIMIT" : "",
                        d.maxWorkGroupSize);
    if (!d.layouts.empty()) text += fmt::format("      layouts forced: {} (PENUMBRA_LAYOUTS)\n", d.layouts);
    text += fmt::format("      fp64 {}, fp16 {}, int64 atomics {}, sub-groups {}, non-uniform work-groups {}\n",
                        d.fp64 ? "yes" : "no", d.fp16 ? "yes" : "no", d.int64Atomics ? "yes" : "no",
                        d.subGroups ? "yes" : "no", d.nonUniformWorkGroups ? "yes" : "no");
  }
  return text;
}

}  // namespace penumbra
