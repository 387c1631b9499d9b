// The Python module's summed-area tables, pyramids and Lloyd statistics on numpy or pyopencl arrays (see stages.cpp).
// Pyramid levels come back as views into one array holding the whole chain.
#include <pybind11/stl.h>

#include "python/arrays.h"
#include "python/module.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

SatConfig satConfig(const std::string& precision, const std::string& algorithm, int fractionBits, bool zeroMean,
                    const std::optional<std::array<float, 4>>& offset) {
  static const std::map<std::string, SatPrecision> kPrecisions = {{"float32", SatPrecision::Float32},
                                                                  {"fixed32", SatPrecision::Fixed32},
                                                                  {"fixed64", SatPrecision::Fixed64},
                                                                  {"float64", SatPrecision::Float64}};
  static const std::map<std::string, SatAlgorithm> kAlgorithms = {{"auto", SatAlgorithm::Auto},
                                                                  {"tiled", SatAlgorithm::Tiled},
                                                                  {"lines", SatAlgorithm::Lines},
                                                                  {"hensley", SatAlgorithm::Hensley}};
  SatConfig config;
  auto p = kPrecisions.find(precision);
  if (p == kPrecisions.end())
    throw py::value_error("sat: precision '" + precision + "' is not float32, fixed32, fixed64 or float64");
  auto a = kAlgorithms.find(algorithm);
  if (a == kAlgorithms.end())
    throw py::value_error("sat: algorithm '" + algorithm + "' is not auto, tiled, lines or hensley");
  config.precision = p->second;
  config.algorithm = a->second;
  config.fractionBits = fractionBits;
  config.zeroMean = zeroMean;
  config.offset = offset;
  return config;
}

py::tuple satTable(const Context& ctx, const py::object& image, const SatConfig& config) {
  const ArrayIn in(ctx, image, "float32", "sat", "image");
  const ImageShape shape = shapeOf(in.shape(), "sat");
  const char* dtypes[] = {"float32", "uint32", "uint64", "float64"};
  ArrayOut table(ctx, in, in.shape(), dtypes[static_cast<int>(config.precision)]), offset(ctx, in, {4}, "float32");
  const StageEvent done(
      [&](cl_event* event) { sat(ctx, in.mem(), shape, config, table.mem(), offset.mem(), in.waits(), event); });
  return py::make_tuple(table.finish(done.get()), offset.finish(done.get()));
}

// Views of each level of `chain` (a whole pyramid: texels x channels elements; numpy or pyopencl), shaped like images.
py::list levelViews(const py::object& chain, const PyramidLayout& layout, size_t channels) {
  py::list out;
  for (const pn_pyramid_level& level : layout.levels) {
    const size_t first = size_t(level.offset) * channels, last = first + size_t(level.width) * level.height * channels;
    py::object view = chain[py::slice(first, last, 1)];
    out.append(channels == 1 ? view.attr("reshape")(level.height, level.width)
                             : view.attr("reshape")(level.height, level.width, channels));
  }
  return out;
}

py::list mips(const Context& ctx, const py::object& image, const std::string& storage) {
  if (storage != "float32" && storage != "float16")
    throw py::value_error("moment_mips: storage '" + storage + "' is not float32 or float16");
  const ArrayIn in(ctx, image, storage.c_str(), "moment_mips", "image");
  const ImageShape shape = shapeOf(in.shape(), "moment_mips");
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 1);
  ArrayOut chain(ctx, in, {py::ssize_t(layout.texels * shape.channels)}, storage.c_str());
  const MomentStorage s = storage == "float16" ? MomentStorage::Float16 : MomentStorage::Float32;
  const StageEvent done([&](cl_event* event) { momentMips(ctx, in.mem(), shape, s, chain.mem(), in.waits(), event); });
  return levelViews(chain.finish(done.get()), layout, shape.channels);
}

py::list minMax(const Context& ctx, const py::object& depth) {
  const ArrayIn in(ctx, depth, "float32", "minmax_pyramid", "depth");
  const ImageShape shape = shapeOf(in.shape(), "minmax_pyramid");
  if (shape.channels != 1) throw py::value_error("minmax_pyramid: the depth map is (height, width)");
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 0);
  ArrayOut chain(ctx, in, {py::ssize_t(layout.texels * 2)}, "float32");
  const StageEvent done([&](cl_event* event) {
    minMaxPyramid(ctx, in.mem(), shape.width, shape.height, chain.mem(), in.waits(), event);
  });
  return levelViews(chain.finish(done.get()), layout, 2);
}

// The statistics are one value per cluster: numpy arrays whichever the inputs (read when the stage completes).
py::dict lloyd(const Context& ctx, const py::object& xs, const py::object& ws, const py::object& bounds) {
  const ArrayIn x(ctx, xs, "float32", "lloyd_stats", "x"), w(ctx, ws, "float32", "lloyd_stats", "w");
  const ArrayIn boundaries(ctx, bounds, "float32", "lloyd_stats", "boundaries");
  if (x.shape().size() != 1 || w.shape().size() != 1 || boundaries.shape().size() != 1 || x.shape() != w.shape())
    throw py::value_error("lloyd_stats: x and w are 1-D arrays of one length, boundaries a 1-D array");
  const uint32_t clusters = static_cast<uint32_t>(boundaries.shape()[0] + 1);
  std::vector<cl_event> waits = x.waits();
  waits.insert(waits.end(), w.waits().begin(), w.waits().end());
  waits.insert(waits.end(), boundaries.waits().begin(), boundaries.waits().end());
  std::vector<LloydStats> stats(clusters);
  {
    py::gil_scoped_release release;
    DeviceBuffer out(ctx, clusters * sizeof(LloydStats));
    cl_event done = nullptr;
    lloydStats(ctx, x.mem(), w.mem(), size_t(x.shape()[0]), boundaries.mem(), clusters, out.get(), waits, &done);
    download(ctx, out.get(), done, stats.data(), clusters * sizeof(LloydStats));
  }
  py::array_t<float> sumW(clusters), sumWX(clusters), sumWX2(clusters);
  py::array_t<uint32_t> samples(clusters);
  for (uint32_t k = 0; k < clusters; ++k) {
    sumW.mutable_at(k) = stats[k].sum_w, sumWX.mutable_at(k) = stats[k].sum_wx;
    sumWX2.mutable_at(k) = stats[k].sum_wx2, samples.mutable_at(k) = stats[k].samples;
  }
  py::dict out;
  out["sum_w"] = sumW, out["sum_wx"] = sumWX, out["sum_wx2"] = sumWX2, out["samples"] = samples;
  return out;
}

}  // namespace

void bindTables(py::module_& m) {
  using namespace py::literals;
  m.def(
      "sat",
      [](const Context& ctx, const py::object& image, const std::string& precision, const std::string& algorithm,
         int fractionBits, bool zeroMean, const std::optional<std::array<float, 4>>& offset) {
        return satTable(ctx, image, satConfig(precision, algorithm, fractionBits, zeroMean, offset));
      },
      "context"_a, "image"_a, "precision"_a = "float32", "algorithm"_a = "auto", "fraction_bits"_a = -1,
      "zero_mean"_a = true, "offset"_a = std::nullopt,
      "The summed-area table (table[y, x] sums [0, x] x [0, y]) and the 4 floats subtracted before summing (fp32).");
  m.def("moment_mips", &mips, "context"_a, "image"_a, "storage"_a = "float32",
        "Mip levels 1.. (exact area averages), views into one array; float16 storage takes and gives float16.");
  m.def("minmax_pyramid", &minMax, "context"_a, "depth"_a,
        "Levels 0.. of the min-max depth pyramid, (height, width, 2) views into one array.");
  m.def("lloyd_stats", &lloyd, "context"_a, "x"_a, "w"_a, "boundaries"_a,
        "Per-cluster sum_w, sum_wx, sum_wx2 and samples of the weighted samples (x, w) split at the boundaries.");
}

}  // namespace penumbra::python
