/* penumbra's C example: renders one frame with a technique, saves it as EXR, then blurs the frame's visibility on the
 * device (the frame's own cl_mem into a buffer of ours, waiting on the event the stage returns) and writes the
 * blurred floats to a raw file. Every call returns a status; the message says what went wrong.
 *   render_frame_c SCENE WxH TECHNIQUE out.exr out.blur */
#include <penumbra/penumbra.h>
#include <stdio.h>
#include <stdlib.h>

#define CHECK(call)                                                                                  \
  do {                                                                                               \
    pn_status status_ = (call);                                                                      \
    if (status_ != PN_SUCCESS) {                                                                     \
      fprintf(stderr, "render_frame_c: %s: %s\n", pn_status_name(status_), pn_last_error_message()); \
      return 1;                                                                                      \
    }                                                                                                \
  } while (0)

int main(int argc, char** argv) {
  pn_context* context = NULL;
  pn_scene* scene = NULL;
  pn_params* params = NULL;
  pn_renderer* renderer = NULL;
  pn_frame* frame = NULL;
  pn_camera camera;
  int width = 0, height = 0;
  pn_camera_init(&camera); /* its size: every call that fills or reads a camera needs it */
  if (argc != 6 || sscanf(argv[2], "%dx%d", &width, &height) != 2) {
    fprintf(stderr, "usage: render_frame_c SCENE WxH TECHNIQUE out.exr out.blur\n");
    return 2;
  }
  printf("penumbra %s\n", pn_version());

  CHECK(pn_context_create(NULL, &context)); /* PENUMBRA_DEVICE, else the first GPU, else the first CPU */
  CHECK(pn_scene_load(argv[1], NULL, &scene));
  CHECK(pn_scene_default_camera(scene, &camera));
  camera.width = width;
  camera.height = height;
  CHECK(pn_params_create(argv[3], &params));
  CHECK(pn_renderer_create(context, scene, &renderer));
  CHECK(pn_renderer_render(renderer, &camera, NULL, 0, params, &frame)); /* the scene's lights */
  CHECK(pn_frame_save_exr(frame, argv[4]));
  printf("%s: %dx%d, %zu light(s), technique %s\n", pn_context_device_name(context), pn_frame_width(frame),
         pn_frame_height(frame), pn_frame_light_count(frame), pn_params_technique(params));

  /* One stage on the device: a 5x5 box blur of the first light's visibility (rows bottom-up) into our buffer. */
  {
    const size_t count = (size_t)width * (size_t)height;
    const pn_image_shape shape = {(uint32_t)width, (uint32_t)height, 1};
    pn_blur_config box;
    cl_mem visibility = NULL, blurred;
    cl_event done = NULL;
    cl_int err = CL_SUCCESS;
    float* host = malloc(count * sizeof(float));
    FILE* out;
    pn_blur_config_init(&box);
    box.filter = PN_BLUR_BOX;
    box.radius = 2;
    CHECK(pn_frame_visibility_buffer(frame, 0, &visibility));
    blurred = clCreateBuffer(pn_context_cl_context(context), CL_MEM_READ_WRITE, count * sizeof(float), NULL, &err);
    if (err != CL_SUCCESS || host == NULL) return 1;
    CHECK(pn_blur(context, visibility, blurred, NULL, &shape, &box, 0, NULL, &done));
    err = clEnqueueReadBuffer(pn_context_cl_queue(context), blurred, CL_TRUE, 0, count * sizeof(float), host, 1, &done,
                              NULL);
    clReleaseEvent(done); /* the event is ours to release */
    clReleaseMemObject(blurred);
    if (err != CL_SUCCESS) return 1;
    out = fopen(argv[5], "wb");
    if (out == NULL || fwrite(host, sizeof(float), count, out) != count) return 1;
    fclose(out);
    free(host);
  }

  pn_frame_release(frame);
  pn_renderer_release(renderer);
  pn_params_release(params);
  pn_scene_release(scene);
  pn_context_release(context);
  return 0;
}
