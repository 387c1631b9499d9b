// penumbra's C++ example: renders one frame with a technique, saves it as EXR, then blurs the frame's visibility on
// the device (the frame's own cl_mem into a buffer of ours, waiting on the event the stage returns) and writes the
// blurred floats to a raw file.
//   render_frame SCENE WxH TECHNIQUE out.exr out.blur     e.g. render_frame builtin:box 64x48 pcf box.exr box.blur
#include <cstdio>
#include <fstream>
#include <iostream>
#include <penumbra/penumbra.hpp>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: render_frame SCENE WxH TECHNIQUE out.exr out.blur\n";
    return 2;
  }
  try {
    int width = 0, height = 0;
    if (std::sscanf(argv[2], "%dx%d", &width, &height) != 2) throw std::invalid_argument("size is WxH");
    std::cout << "penumbra " << penumbra::version() << "\n";

    penumbra::Context context;  // the device PENUMBRA_DEVICE names, else the first GPU, else the first CPU
    const penumbra::Scene scene(argv[1]);
    penumbra::Camera camera = scene.defaultCamera();
    camera.width = width, camera.height = height;
    penumbra::Renderer renderer(context, scene);
    const penumbra::Frame frame = renderer.render(camera, penumbra::Params(argv[3]));
    frame.saveExr(argv[4]);
    std::cout << context.deviceName() << ": " << frame.width() << "x" << frame.height() << ", "
              << frame.lightLayers().size() << " light(s), technique " << argv[3] << "\n";

    // One stage on the device: a 5x5 box blur of the first light's visibility (rows bottom-up) into our buffer.
    const size_t count = size_t(width) * size_t(height);
    cl_int err = CL_SUCCESS;
    cl_mem blurred = clCreateBuffer(context.clContext(), CL_MEM_READ_WRITE, count * sizeof(float), nullptr, &err);
    if (err != CL_SUCCESS) throw std::runtime_error("clCreateBuffer failed");
    penumbra::BlurConfig box;
    box.filter = penumbra::BlurFilter::Box;
    box.radius = 2;
    cl_event done = nullptr;
    penumbra::blur(context, frame.visibilityBuffer(), blurred, {uint32_t(width), uint32_t(height), 1}, box, {}, &done);
    std::vector<float> host(count);
    err = clEnqueueReadBuffer(context.clQueue(), blurred, CL_TRUE, 0, count * sizeof(float), host.data(), 1, &done,
                              nullptr);
    clReleaseEvent(done);  // the event is ours to release
    clReleaseMemObject(blurred);
    if (err != CL_SUCCESS) throw std::runtime_error("clEnqueueReadBuffer failed");
    std::ofstream(argv[5], std::ios::binary).write(reinterpret_cast<const char*>(host.data()), count * sizeof(float));
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "render_frame: " << e.what() << "\n";
    return 1;
  }
}
