// The Python module's summed-area tables, pyramids and Lloyd statistics on numpy arrays (see stages.cpp). Pyramid
// levels come back as views into one array holding the whole chain.
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

py::tuple satTable(const Context& ctx, const Array<float>& image, const SatConfig& config) {
  const ImageShape shape = shapeOf(image, "sat");
  const char* dtypes[] = {"float32", "uint32", "uint64", "float64"};
  py::array table(py::dtype(dtypes[static_cast<int>(config.precision)]),
                  std::vector<py::ssize_t>(image.shape(), image.shape() + image.ndim()));
  py::array_t<float> offset(4);
  const size_t count = size_t(shape.width) * shape.height * shape.channels;
  const float* in = image.data();
  void* tableOut = table.mutable_data();
  float* offsetOut = offset.mutable_data();
  const size_t tableBytes = count * table.itemsize();
  {
    py::gil_scoped_release release;
    DeviceBuffer source(ctx, count * sizeof(float), in), target(ctx, tableBytes), mean(ctx, 4 * sizeof(float));
    cl_event done = nullptr;
    sat(ctx, source.get(), shape, config, target.get(), mean.get(), {}, &done);
    clRetainEvent(done);  // one wait per read
    download(ctx, target, done, tableOut, tableBytes);
    download(ctx, mean, done, offsetOut, 4 * sizeof(float));
  }
  return py::make_tuple(table, offset);
}

// Views of each level of `chain` (a whole pyramid: texels x channels elements), shaped like images.
py::list levelViews(const py::array& chain, const PyramidLayout& layout, size_t channels) {
  py::list out;
  py::object flat = chain.attr("reshape")(-1);
  for (const pn_pyramid_level& level : layout.levels) {
    const size_t first = size_t(level.offset) * channels, last = first + size_t(level.width) * level.height * channels;
    py::object view = flat[py::slice(first, last, 1)];
    out.append(channels == 1 ? view.attr("reshape")(level.height, level.width)
                             : view.attr("reshape")(level.height, level.width, channels));
  }
  return out;
}

py::list mips(const Context& ctx, const py::array& image, const std::string& storage) {
  if (storage != "float32" && storage != "float16")
    throw py::value_error("moment_mips: storage '" + storage + "' is not float32 or float16");
  const py::array base = contiguous(image, storage.c_str());
  const ImageShape shape = shapeOf(base, "moment_mips");
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 1);
  py::array chain(base.dtype(), std::vector<size_t>{layout.texels * shape.channels});
  const MomentStorage s = storage == "float16" ? MomentStorage::Float16 : MomentStorage::Float32;
  const size_t inBytes = size_t(base.nbytes()), outBytes = size_t(chain.nbytes());
  const void* in = base.data();
  void* result = chain.mutable_data();
  {
    py::gil_scoped_release release;
    DeviceBuffer source(ctx, inBytes, in), target(ctx, outBytes);
    cl_event done = nullptr;
    momentMips(ctx, source.get(), shape, s, target.get(), {}, &done);
    download(ctx, target, done, result, outBytes);
  }
  return levelViews(chain, layout, shape.channels);
}

py::list minMax(const Context& ctx, const Array<float>& depth) {
  const ImageShape shape = shapeOf(depth, "minmax_pyramid");
  const PyramidLayout layout = pyramidLayout(shape.width, shape.height, 0);
  py::array_t<float> chain(layout.texels * 2);
  const float* in = depth.data();
  float* result = chain.mutable_data();
  {
    py::gil_scoped_release release;
    DeviceBuffer source(ctx, size_t(depth.nbytes()), in), target(ctx, layout.texels * 2 * sizeof(float));
    cl_event done = nullptr;
    minMaxPyramid(ctx, source.get(), shape.width, shape.height, target.get(), {}, &done);
    download(ctx, target, done, result, layout.texels * 2 * sizeof(float));
  }
  return levelViews(chain, layout, 2);
}

py::dict lloyd(const Context& ctx, const Array<float>& x, const Array<float>& w, const Array<float>& boundaries) {
  if (x.ndim() != 1 || w.ndim() != 1 || boundaries.ndim() != 1 || x.size() != w.size())
    throw py::value_error("lloyd_stats: x and w are 1-D arrays of one length, boundaries a 1-D array");
  const uint32_t clusters = static_cast<uint32_t>(boundaries.size() + 1);
  std::vector<LloydStats> stats(clusters);
  const float *xs = x.data(), *ws = w.data(), *bs = boundaries.data();
  const size_t count = size_t(x.size()), bounds = size_t(boundaries.size());
  {
    py::gil_scoped_release release;
    DeviceBuffer xb(ctx, count * sizeof(float), xs), wb(ctx, count * sizeof(float), ws);
    DeviceBuffer bb(ctx, bounds * sizeof(float), bounds > 0 ? bs : nullptr), out(ctx, clusters * sizeof(LloydStats));
    cl_event done = nullptr;
    lloydStats(ctx, xb.get(), wb.get(), count, bb.get(), clusters, out.get(), {}, &done);
    download(ctx, out, done, stats.data(), clusters * sizeof(LloydStats));
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
      [](const Context& ctx, const Array<float>& image, const std::string& precision, const std::string& algorithm,
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
