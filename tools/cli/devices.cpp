// `penumbra devices [--json]`: the OpenCL platforms and devices with the facts our kernels depend on.
#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>

#include "host/cl/device.h"
#include "host/cl/error.h"
#include "tools/cli/commands.h"

namespace penumbra::cli {

Command addDevicesCommand(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("devices", "List OpenCL platforms and devices");
  auto json = std::make_shared<bool>(false);
  sub->add_flag("--json", *json, "Print JSON instead of a table");
  return {sub, [json] {
            const std::vector<DeviceInfo> devices = listDevices();
            if (*json) {
              nlohmann::json list = nlohmann::json::array();
              for (const DeviceInfo& d : devices) list.push_back(toJson(d));
              fmt::print("{}\n", list.dump(2));
            } else {
              fmt::print("{}", describeDevices(devices));
            }
            if (devices.empty()) throw NoDeviceError("no OpenCL device found");
            return 0;
          }};
}

}  // namespace penumbra::cli
