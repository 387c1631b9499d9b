// exr_channel_equal A.exr B.exr [CHANNEL...]: exit 0 when every named channel (none named: every channel, the two
// files having the same ones) of the two EXR files holds the same float bits at every pixel (the install test's check
// of a library frame against the CLI's, the batch test's of `run` against `render`), 1 naming the first pixel or
// channel that differs, 2 for a usage or file error.
#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "host/io/exr.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    fmt::print(stderr, "usage: exr_channel_equal A.exr B.exr [CHANNEL...]\n");
    return 2;
  }
  try {
    const penumbra::Image a = penumbra::readExr(argv[1]), b = penumbra::readExr(argv[2]);
    if (a.width() != b.width() || a.height() != b.height()) {
      fmt::print(stderr, "{} is {}x{}, {} is {}x{}\n", argv[1], a.width(), a.height(), argv[2], b.width(), b.height());
      return 1;
    }
    std::vector<std::string> names(argv + 3, argv + argc);
    if (names.empty()) {
      for (const auto& channel : a.channels()) names.push_back(channel.name);
      std::vector<std::string> others;
      for (const auto& channel : b.channels()) others.push_back(channel.name);
      if (names != others) {
        fmt::print(stderr, "{} and {} do not have the same channels\n", argv[1], argv[2]);
        return 1;
      }
    }
    for (const std::string& name : names) {
      const auto &x = a.require(name).data, &y = b.require(name).data;
      for (size_t i = 0; i < x.size(); ++i)
        if (std::memcmp(&x[i], &y[i], sizeof(float)) != 0) {
          fmt::print(stderr, "{}: pixel ({}, {}) is {} in {} but {} in {}\n", name, i % a.width(), i / a.width(), x[i],
                     argv[1], y[i], argv[2]);
          return 1;
        }
      fmt::print("{}: {} pixels bit-identical\n", name, x.size());
    }
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "exr_channel_equal: {}\n", e.what());
    return 2;
  }
}
