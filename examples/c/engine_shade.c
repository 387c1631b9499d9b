/* penumbra's engine-style example: the program owns its OpenCL context and queue, and its own kernels draw a light's
 * depth map (a hardware-like window depth, OpenGL's convention, cleared to 1) and the camera's G-buffer (world
 * positions and normals) of a small scene by ray casting; penumbra then shades pcss and vssm from those buffers
 * (pn_shade), chained by events with no clFinish anywhere, into buffers of the program's, rows from the top. The
 * result is checked against penumbra's own Renderer on the same scene, camera and light: the same shadow but for the
 * two maps' texels (the Renderer fits a map of its own).
 *   engine_shade_c            (exit 0: both techniques agree with the Renderer; 1 otherwise) */
#include <CL/cl.h>
#include <math.h>
#include <penumbra/penumbra.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CHECK(call)                                                                                  \
  do {                                                                                               \
    pn_status status_ = (call);                                                                      \
    if (status_ != PN_SUCCESS) {                                                                     \
      fprintf(stderr, "engine_shade_c: %s: %s\n", pn_status_name(status_), pn_last_error_message()); \
      return 1;                                                                                      \
    }                                                                                                \
  } while (0)
#define CL_CHECK(call)                                                   \
  do {                                                                   \
    cl_int err_ = (call);                                                \
    if (err_ != CL_SUCCESS) {                                            \
      fprintf(stderr, "engine_shade_c: %s failed (%d)\n", #call, err_); \
      return 1;                                                          \
    }                                                                    \
  } while (0)

enum { kWidth = 160, kHeight = 120, kMapSize = 1024 };
static const float kLightRadius = 0.3f, kLightNear = 1.0f, kLightFar = 6.0f;

/* The engine's scene: a 10x10 ground at y = 0 and a 2x2 square at y = 2, both facing up. Its kernels cast a ray
 * against the two quads; the light's map stores window depth, the G-buffer positions (w = 0: background) and normals.
 * Rows from the bottom, as OpenGL and OpenCL images have them. */
static const char* kEngineKernels =
    "float cast(float3 o, float3 d) {\n"
    "  float best = INFINITY;\n"
    "  const float ys[2] = {2.0f, 0.0f}, halves[2] = {1.0f, 5.0f};\n"
    "  for (int q = 0; q < 2; ++q) {\n"
    "    float t = (ys[q] - o.y) / d.y;\n"
    "    float3 p = o + t * d;\n"
    "    if (t > 0.0f && t < best && fabs(p.x) <= halves[q] && fabs(p.z) <= halves[q]) best = t;\n"
    "  }\n"
    "  return best;\n"
    "}\n"
    "float3 ray(float4 right, float4 up, float4 forward, float tanX, float tanY, int x, int y, int w, int h) {\n"
    "  float2 ndc = ((float2)(x, y) + 0.5f) / (float2)(w, h) * 2.0f - 1.0f;\n"
    "  return forward.xyz + ndc.x * tanX * right.xyz + ndc.y * tanY * up.xyz;\n"
    "}\n"
    "__kernel void light_depth(float4 eye, float4 right, float4 up, float4 forward, float tanHalf, float n, float f,\n"
    "                          int size, __global float* depth) {\n"
    "  int x = get_global_id(0), y = get_global_id(1);\n"
    "  float t = cast(eye.xyz, ray(right, up, forward, tanHalf, tanHalf, x, y, size, size));\n"
    "  float ndc = (f + n) / (f - n) - 2.0f * f * n / ((f - n) * t);  /* t is the eye depth: forward's part is 1 */\n"
    "  depth[y * size + x] = isinf(t) ? 1.0f : clamp(ndc * 0.5f + 0.5f, 0.0f, 1.0f);\n"
    "}\n"
    "__kernel void gbuffer(float4 eye, float4 right, float4 up, float4 forward, float tanX, float tanY, int w, int h,\n"
    "                      __global float4* position, __global float4* normal) {\n"
    "  int x = get_global_id(0), y = get_global_id(1);\n"
    "  float3 d = ray(right, up, forward, tanX, tanY, x, y, w, h);\n"
    "  float t = cast(eye.xyz, d);\n"
    "  position[y * w + x] = isinf(t) ? (float4)(0.0f) : (float4)(eye.xyz + t * d, 1.0f);\n"
    "  normal[y * w + x] = (float4)(0.0f, 1.0f, 0.0f, 1.0f);\n"
    "}\n";

typedef struct Basis {
  cl_float4 eye, right, up, forward;
} Basis;

static void normalize3(float v[3]) {
  const float length = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int i = 0; i < 3; ++i) v[i] /= length;
}

static void cross3(const float a[3], const float b[3], float out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/* A look-at basis, and its view matrix (column-major, OpenGL's convention). */
static Basis lookAt(const float eye[3], const float target[3], const float upHint[3], float view[16]) {
  float f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]}, r[3], u[3];
  normalize3(f);
  cross3(f, upHint, r);
  normalize3(r);
  cross3(r, f, u);
  Basis b = {{{eye[0], eye[1], eye[2], 1}}, {{r[0], r[1], r[2], 0}}, {{u[0], u[1], u[2], 0}}, {{f[0], f[1], f[2], 0}}};
  memset(view, 0, 16 * sizeof(float));
  for (int c = 0; c < 3; ++c) {
    view[c * 4 + 0] = r[c];
    view[c * 4 + 1] = u[c];
    view[c * 4 + 2] = -f[c];
  }
  view[12] = -(r[0] * eye[0] + r[1] * eye[1] + r[2] * eye[2]);
  view[13] = -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
  view[14] = f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2];
  view[15] = 1;
  return b;
}

/* OpenGL's symmetric perspective projection (glm::perspective), column-major. */
static void perspective(float tanHalfY, float aspect, float n, float f, float projection[16]) {
  memset(projection, 0, 16 * sizeof(float));
  projection[0] = 1.0f / (aspect * tanHalfY);
  projection[5] = 1.0f / tanHalfY;
  projection[10] = -(f + n) / (f - n);
  projection[11] = -1.0f;
  projection[14] = -2.0f * f * n / (f - n);
}

/* The engine's device: PENUMBRA_DEVICE's kind ("cpu" or "gpu") when set, as penumbra's tests run, else the first GPU,
 * else the first CPU. */
static cl_device_id engineDevice(void) {
  const char* spec = getenv("PENUMBRA_DEVICE");
  cl_device_type order[3] = {CL_DEVICE_TYPE_GPU, CL_DEVICE_TYPE_CPU, CL_DEVICE_TYPE_ALL};
  if (spec != NULL && strcmp(spec, "cpu") == 0) order[0] = CL_DEVICE_TYPE_CPU;
  cl_platform_id platforms[16];
  cl_uint count = 0;
  if (clGetPlatformIDs(16, platforms, &count) != CL_SUCCESS) return NULL;
  for (int k = 0; k < 3; ++k)
    for (cl_uint p = 0; p < count && p < 16; ++p) {
      cl_device_id device = NULL;
      if (clGetDeviceIDs(platforms[p], order[k], 1, &device, NULL) == CL_SUCCESS) return device;
    }
  return NULL;
}

/* The Renderer's frame of the same scene, camera and light with `technique`, compared with ours (rows from the top):
 * mean absolute difference, and the pixels more than 0.25 apart. */
static int compare(pn_renderer* renderer, const pn_camera* camera, const pn_light* light, const char* technique,
                   const float* ours, double* mean, size_t* far) {
  pn_params* params = NULL;
  pn_frame* frame = NULL;
  const float* theirs = NULL;
  const pn_frame_light lights[1] = {{light, NULL}};
  CHECK(pn_params_create(technique, &params));
  CHECK(pn_renderer_render(renderer, camera, lights, 1, params, &frame));
  CHECK(pn_frame_channel(frame, "visibility.Y", &theirs));
  *mean = 0, *far = 0;
  for (size_t i = 0; i < (size_t)kWidth * kHeight; ++i) {
    const double d = fabs((double)ours[i] - (double)theirs[i]);
    *mean += d;
    *far += !(d <= 0.25);
  }
  *mean /= (double)kWidth * kHeight;
  pn_frame_release(frame);
  pn_params_release(params);
  return 0;
}

int main(void) {
  printf("penumbra %s\n", pn_version());
  /* The engine's own OpenCL objects. */
  cl_int err = CL_SUCCESS;
  cl_device_id device = engineDevice();
  if (device == NULL) {
    fprintf(stderr, "engine_shade_c: no OpenCL device\n");
    return 1;
  }
  cl_context cl = clCreateContext(NULL, 1, &device, NULL, NULL, &err);
  CL_CHECK(err);
  cl_command_queue queue = clCreateCommandQueue(cl, device, 0, &err);
  CL_CHECK(err);
  cl_program program = clCreateProgramWithSource(cl, 1, &kEngineKernels, NULL, &err);
  CL_CHECK(err);
  CL_CHECK(clBuildProgram(program, 1, &device, "", NULL, NULL));
  cl_kernel drawMap = clCreateKernel(program, "light_depth", &err);
  CL_CHECK(err);
  cl_kernel drawGBuffer = clCreateKernel(program, "gbuffer", &err);
  CL_CHECK(err);
  const size_t pixels = (size_t)kWidth * kHeight, texels = (size_t)kMapSize * kMapSize;
  cl_mem map = clCreateBuffer(cl, CL_MEM_READ_WRITE, texels * sizeof(float), NULL, &err);
  CL_CHECK(err);
  cl_mem positions = clCreateBuffer(cl, CL_MEM_READ_WRITE, pixels * sizeof(cl_float4), NULL, &err);
  CL_CHECK(err);
  cl_mem normals = clCreateBuffer(cl, CL_MEM_READ_WRITE, pixels * sizeof(cl_float4), NULL, &err);
  CL_CHECK(err);
  cl_mem visibility[2];
  for (int i = 0; i < 2; ++i) {
    visibility[i] = clCreateBuffer(cl, CL_MEM_READ_WRITE, pixels * sizeof(float), NULL, &err);
    CL_CHECK(err);
  }

  /* The light: a disk at (0, 4, 0) facing down; its map a 90-degree perspective from there. The camera: from
   * (0, 7, 5) at the origin, 40 degrees vertically, as a pn_camera "0,7,5:0,0,0:40" sees it. */
  const float lightEye[3] = {0, 4, 0}, origin[3] = {0, 0, 0}, lightUp[3] = {0, 0, -1};
  const float cameraEye[3] = {0, 7, 5}, cameraUp[3] = {0, 1, 0};
  float lightView[16], lightProjection[16], cameraView[16];
  const Basis light = lookAt(lightEye, origin, lightUp, lightView);
  const float tanHalfLight = 1.0f; /* tan 45 */
  perspective(tanHalfLight, 1.0f, kLightNear, kLightFar, lightProjection);
  const Basis camera = lookAt(cameraEye, origin, cameraUp, cameraView);
  const float tanY = tanf(20.0f * 3.14159265f / 180.0f), tanX = tanY * kWidth / kHeight;

  /* The engine's passes: the light's map and the G-buffer, each its own event. */
  const int mapSize = kMapSize, width = kWidth, height = kHeight;
  const Basis* bases[2] = {&light, &camera};
  cl_kernel kernels[2] = {drawMap, drawGBuffer};
  for (int k = 0; k < 2; ++k) {
    CL_CHECK(clSetKernelArg(kernels[k], 0, sizeof(cl_float4), &bases[k]->eye));
    CL_CHECK(clSetKernelArg(kernels[k], 1, sizeof(cl_float4), &bases[k]->right));
    CL_CHECK(clSetKernelArg(kernels[k], 2, sizeof(cl_float4), &bases[k]->up));
    CL_CHECK(clSetKernelArg(kernels[k], 3, sizeof(cl_float4), &bases[k]->forward));
  }
  CL_CHECK(clSetKernelArg(drawMap, 4, sizeof(float), &tanHalfLight));
  CL_CHECK(clSetKernelArg(drawMap, 5, sizeof(float), &kLightNear));
  CL_CHECK(clSetKernelArg(drawMap, 6, sizeof(float), &kLightFar));
  CL_CHECK(clSetKernelArg(drawMap, 7, sizeof(int), &mapSize));
  CL_CHECK(clSetKernelArg(drawMap, 8, sizeof(cl_mem), &map));
  CL_CHECK(clSetKernelArg(drawGBuffer, 4, sizeof(float), &tanX));
  CL_CHECK(clSetKernelArg(drawGBuffer, 5, sizeof(float), &tanY));
  CL_CHECK(clSetKernelArg(drawGBuffer, 6, sizeof(int), &width));
  CL_CHECK(clSetKernelArg(drawGBuffer, 7, sizeof(int), &height));
  CL_CHECK(clSetKernelArg(drawGBuffer, 8, sizeof(cl_mem), &positions));
  CL_CHECK(clSetKernelArg(drawGBuffer, 9, sizeof(cl_mem), &normals));
  cl_event drawn[2];
  const size_t mapRange[2] = {kMapSize, kMapSize}, frameRange[2] = {kWidth, kHeight};
  CL_CHECK(clEnqueueNDRangeKernel(queue, drawMap, 2, NULL, mapRange, NULL, 0, NULL, &drawn[0]));
  CL_CHECK(clEnqueueNDRangeKernel(queue, drawGBuffer, 2, NULL, frameRange, NULL, 0, NULL, &drawn[1]));

  /* penumbra on the engine's objects: pcss and vssm from the map and the G-buffer, after both passes. */
  pn_context* context = NULL;
  pn_shader* shader = NULL;
  CHECK(pn_context_create_from_cl(cl, device, queue, &context));
  CHECK(pn_shader_create(context, &shader));
  pn_shade_desc desc;
  pn_shade_desc_init(&desc);
  desc.light_type = PN_LIGHT_SPOT;
  desc.light_radius = kLightRadius;
  desc.light_depth.memory = map;
  desc.light_map_size = kMapSize;
  memcpy(desc.light_view, lightView, sizeof(lightView));
  memcpy(desc.light_projection, lightProjection, sizeof(lightProjection));
  desc.width = kWidth;
  desc.height = kHeight;
  desc.positions.memory = positions;
  desc.normals.memory = normals;
  desc.has_scene_bounds = 1;
  const float sceneMin[3] = {-5, 0, -5}, sceneMax[3] = {5, 2, 5};
  memcpy(desc.scene_min, sceneMin, sizeof(sceneMin));
  memcpy(desc.scene_max, sceneMax, sizeof(sceneMax));
  desc.visibility.top_down = 1; /* rows from the top, as the frame's host channels */
  const char* techniques[2] = {"pcss", "vssm"};
  cl_event shaded[2];
  for (int t = 0; t < 2; ++t) {
    pn_params* params = NULL;
    CHECK(pn_params_create(techniques[t], &params));
    desc.visibility.memory = visibility[t];
    CHECK(pn_shade(shader, params, &desc, 2, drawn, &shaded[t]));
    pn_params_release(params);
  }
  float* ours[2];
  for (int t = 0; t < 2; ++t) {
    ours[t] = malloc(pixels * sizeof(float));
    if (ours[t] == NULL) return 1;
    CL_CHECK(clEnqueueReadBuffer(queue, visibility[t], t == 1 ? CL_TRUE : CL_FALSE, 0, pixels * sizeof(float),
                                 ours[t], 2, shaded, NULL)); /* the second read blocks: both are then done */
  }
  printf("%s: pcss and vssm from the engine's %dx%d map and %dx%d G-buffer (%s)\n", pn_context_device_name(context),
         kMapSize, kMapSize, kWidth, kHeight, pn_shader_attribute(shader, "penumbra:light-fit"));

  /* penumbra's own Renderer on the same scene, camera and light. */
  const float ground[12] = {-5, 0, -5, 5, 0, -5, 5, 0, 5, -5, 0, 5};
  const float square[12] = {-1, 2, -1, 1, 2, -1, 1, 2, 1, -1, 2, 1};
  const uint32_t quad[6] = {0, 2, 1, 0, 3, 2};
  pn_mesh meshes[2];
  for (int i = 0; i < 2; ++i) {
    pn_mesh_init(&meshes[i]);
    meshes[i].positions = i == 0 ? ground : square;
    meshes[i].vertex_count = 4;
    meshes[i].indices = quad;
    meshes[i].triangle_count = 2;
  }
  pn_scene* scene = NULL;
  pn_renderer* renderer = NULL;
  pn_camera cam;
  pn_light lamp;
  pn_camera_init(&cam);
  pn_light_init(&lamp);
  CHECK(pn_camera_parse("0,7,5:0,0,0:40", &cam));
  cam.width = kWidth, cam.height = kHeight;
  CHECK(pn_light_parse("spot:0,4,0:0,0,0:90:0.3", &lamp));
  CHECK(pn_scene_create(meshes, 2, NULL, 0, &scene));
  CHECK(pn_renderer_create(context, scene, &renderer));
  int failed = 0;
  for (int t = 0; t < 2; ++t) {
    double mean = 0;
    size_t far = 0;
    if (compare(renderer, &cam, &lamp, techniques[t], ours[t], &mean, &far) != 0) return 1;
    /* Two maps of one scene: the same shadow but along the penumbrae's texels. */
    const int agrees = mean <= 0.01 && far <= pixels / 200;
    printf("%s: mean |ours - Renderer's| %.5f, %zu pixels more than 0.25 apart: %s\n", techniques[t], mean, far,
           agrees ? "agrees" : "DIFFERS");
    failed |= !agrees;
  }

  pn_renderer_release(renderer);
  pn_scene_release(scene);
  pn_shader_release(shader);
  pn_context_release(context);
  for (int t = 0; t < 2; ++t) {
    free(ours[t]);
    clReleaseEvent(shaded[t]);
    clReleaseEvent(drawn[t]);
    clReleaseMemObject(visibility[t]);
  }
  clReleaseMemObject(map);
  clReleaseMemObject(positions);
  clReleaseMemObject(normals);
  clReleaseKernel(drawMap);
  clReleaseKernel(drawGBuffer);
  clReleaseProgram(program);
  clReleaseCommandQueue(queue);
  clReleaseContext(cl);
  return failed;
}
