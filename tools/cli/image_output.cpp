// -o's extension picks the format; the preview is never written over the EXR (same path, any spelling).
#include "tools/cli/image_output.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "host/io/exr.h"
#include "host/io/png.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// The same file whatever the spelling (./a.exr, dir/../a.exr, a symlink to it), existing or not.
bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code ea, eb;
  const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
  if (ea || eb) return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal();
  return ca == cb;
}

void createParent(const fs::path& path) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
}

}  // namespace

ImageOutputPlan planImageOutput(const ImageOutput& output) {
  const fs::path path = output.path;
  const std::string ext = lowerExtension(path);
  ImageOutputPlan plan;
  try {
    plan.exrOptions.compression = parseExrCompression(output.exrCompression);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--exr-compression: ") + e.what());
  }
  if (ext == ".png") {
    if (!output.png.empty())
      throw std::invalid_argument(fmt::format("--png {}: -o {} is the PNG preview already (use -o NAME.exr for both)",
                                              output.png, output.path));
    plan.png = path;
    return plan;
  }
  if (ext != ".exr")
    throw std::invalid_argument(
        fmt::format("-o {}: unknown output format '{}' (use .exr, or .png for the preview alone)", output.path,
                    ext.empty() ? "(no extension)" : path.extension().string()));
  plan.exr = path;
  if (output.png == "none") return plan;
  plan.png = output.png.empty() ? fs::path(path).replace_extension(".png") : fs::path(output.png);
  if (sameFile(*plan.png, path))
    throw std::invalid_argument(
        fmt::format("--png {}: is the EXR output itself (name another file, or none)", output.png));
  return plan;
}

// The preview first, the EXR last: a batch run takes a finished EXR (its job id) for a finished job.
std::string writeImageOutput(const ImageOutputPlan& plan, const Image& image) {
  return writeImageOutput(plan, ImageRows(image));
}

std::string writeImageOutput(const ImageOutputPlan& plan, const ImageRows& image) {
  // Both files written and synced first, then renamed in that order: a failure of either leaves both old files.
  CommitGroup group;
  if (plan.png) {
    createParent(*plan.png);
    PngOptions options;
    options.commitGroup = &group;
    writePngPreview(*plan.png, image, options);
  }
  if (plan.exr) {
    createParent(*plan.exr);
    ExrOptions options = plan.exrOptions;
    options.commitGroup = &group;
    writeExr(*plan.exr, image, options);
  }
  group.commit();
  if (plan.exr && plan.png) return fmt::format("wrote {} and {}", plan.exr->string(), plan.png->string());
  return "wrote " + (plan.exr ? *plan.exr : *plan.png).string();
}

}  // namespace penumbra::cli
