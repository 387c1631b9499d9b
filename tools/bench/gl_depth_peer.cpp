// The OpenGL depth-only peer: headless EGL (device platform, then Mesa's surfaceless platform, then the default
// display), an OpenGL 4.3 or 3.3 core context with no surface, one VAO over the scene and a depth-texture FBO.
#include "tools/bench/gl_depth_peer.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#define GL_GLEXT_PROTOTYPES  // glvnd's libOpenGL exports every core entry point
#include <GL/glcorearb.h>

namespace penumbra {
namespace {

[[noreturn]] void eglFail(const std::string& step) {
  char code[16];
  std::snprintf(code, sizeof(code), "0x%04x", static_cast<unsigned>(eglGetError()));
  throw std::runtime_error("EGL: " + step + " failed (error " + code + ")");
}

// Whether a space-separated extension list names `word`.
bool hasWord(const char* list, std::string_view word) {
  for (std::string_view rest = list != nullptr ? list : ""; !rest.empty();) {
    const size_t end = std::min(rest.find(' '), rest.size());
    if (rest.substr(0, end) == word) return true;
    rest.remove_prefix(std::min(end + 1, rest.size()));
  }
  return false;
}

// Candidate displays in order of preference, none initialised yet. Hardware devices come before Mesa's software
// one, so that a GPU machine measures its vendor's driver, not llvmpipe.
std::vector<EGLDisplay> candidateDisplays() {
  std::vector<EGLDisplay> displays, software;
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto platformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto deviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (platformDisplay != nullptr && queryDevices != nullptr && hasWord(client, "EGL_EXT_platform_device")) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (queryDevices(16, devices, &count) == EGL_TRUE)
      for (EGLint i = 0; i < count; ++i) {
        const bool soft =
            deviceString != nullptr && hasWord(deviceString(devices[i], EGL_EXTENSIONS), "EGL_MESA_device_software");
        EGLDisplay d = platformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d != EGL_NO_DISPLAY) (soft ? software : displays).push_back(d);
      }
  }
  displays.insert(displays.end(), software.begin(), software.end());
  if (platformDisplay != nullptr && hasWord(client, "EGL_MESA_platform_surfaceless"))
    if (EGLDisplay d = platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        d != EGL_NO_DISPLAY)
      displays.push_back(d);
  if (EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY); d != EGL_NO_DISPLAY) displays.push_back(d);
  return displays;
}

GLuint compileShader(GLenum type, const char* source) {
  GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_TRUE) return shader;
  char log[4096] = {};
  glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
  glDeleteShader(shader);
  throw std::runtime_error(std::string("GL: ") + (type == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                           " shader does not compile:\n" + log);
}

// Depth only: the fragment shader writes nothing and colour writes are off.
GLuint depthProgram() {
  GLuint vs = compileShader(GL_VERTEX_SHADER,
                            "#version 330 core\n"
                            "layout(location = 0) in vec3 p;\n"
                            "uniform mat4 viewProj;\n"
                            "void main() { gl_Position = viewProj * vec4(p, 1.0); }\n");
  GLuint fs = compileShader(GL_FRAGMENT_SHADER, "#version 330 core\nvoid main() {}\n");
  GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok == GL_TRUE) return program;
  char log[4096] = {};
  glGetProgramInfoLog(program, sizeof(log), nullptr, log);
  glDeleteProgram(program);
  throw std::runtime_error(std::string("GL: depth program does not link:\n") + log);
}

void glCheck(const char* step) {
  if (GLenum e = glGetError(); e != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof(code), "0x%04x", e);
    throw std::runtime_error(std::string("GL: ") + step + " failed (error " + code + ")");
  }
}

}  // namespace

struct GlDepthPeer::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  EGLSurface surface = EGL_NO_SURFACE;  // 1x1 pbuffer, only without EGL_KHR_surfaceless_context
  GLuint program = 0, vao = 0, vbo = 0, ibo = 0, fbo = 0, depth = 0, query = 0;
  GLint viewProjLocation = -1;
  GLsizei indexCount = 0;
  int width = 0, height = 0;
  bool current = false, timerQuery = false;
  std::string renderer, version;

  ~Impl() {
    if (current) {
      GLuint buffers[] = {vbo, ibo};
      glDeleteBuffers(2, buffers);
      glDeleteVertexArrays(1, &vao);
      glDeleteFramebuffers(1, &fbo);
      glDeleteTextures(1, &depth);
      glDeleteQueries(1, &query);
      glDeleteProgram(program);
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
    if (display != EGL_NO_DISPLAY) eglTerminate(display);
  }

  // Initialises `d` and makes a core context current on it, or throws (leaving the cleanup to the destructor).
  void open(EGLDisplay d) {
    display = d;
    if (eglInitialize(display, nullptr, nullptr) != EGL_TRUE) eglFail("eglInitialize");
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) eglFail("eglBindAPI(EGL_OPENGL_API)");
    const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (eglChooseConfig(display, configAttribs, &config, 1, &configs) != EGL_TRUE || configs == 0)
      eglFail("eglChooseConfig(pbuffer, OpenGL)");
    for (EGLint major : {4, 3}) {  // 4.3, then 3.3
      const EGLint attribs[] = {
          EGL_CONTEXT_MAJOR_VERSION,           major,   EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
          EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
      context = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs);
      if (context != EGL_NO_CONTEXT) break;
    }
    if (context == EGL_NO_CONTEXT) eglFail("eglCreateContext(OpenGL 3.3 core)");
    if (!hasWord(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_surfaceless_context")) {
      const EGLint pbuffer[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
      surface = eglCreatePbufferSurface(display, config, pbuffer);
      if (surface == EGL_NO_SURFACE) eglFail("eglCreatePbufferSurface(1x1)");
    }
    if (eglMakeCurrent(display, surface, surface, context) != EGL_TRUE) eglFail("eglMakeCurrent");
    current = true;
  }

  void setUp() {
    for (auto [name, out] : {std::pair{GL_RENDERER, &renderer}, std::pair{GL_VERSION, &version}}) {
      const GLubyte* value = glGetString(name);
      if (value == nullptr) throw std::runtime_error("GL: glGetString returned nothing: no usable context");
      *out = reinterpret_cast<const char*>(value);
    }
    program = depthProgram();
    viewProjLocation = glGetUniformLocation(program, "viewProj");
    glGenVertexArrays(1, &vao);
    glGenBuffers(1, &vbo);
    glGenBuffers(1, &ibo);
    glGenFramebuffers(1, &fbo);
    glGenTextures(1, &depth);
    // Timer queries are core since 3.3, but a driver may still give them zero counter bits.
    GLint bits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
    timerQuery = bits > 0;
    if (timerQuery) glGenQueries(1, &query);
    // RasterView's default: no culling (both faces), closest depth wins, and near/far clipping.
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glClearDepth(1.0);
    glCheck("context set-up");
  }

  void resize(int w, int h) {
    GLint maxTexture = 0, maxViewport[2] = {};
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    if (w < 1 || h < 1 || w > 8192 || h > 8192 || w > maxTexture || h > maxTexture || w > maxViewport[0] ||
        h > maxViewport[1])
      throw std::runtime_error("GL: depth target " + std::to_string(w) + "x" + std::to_string(h) +
                               " outside 1..8192 or the driver's limits");
    glBindTexture(GL_TEXTURE_2D, depth);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, w, h, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    if (GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER); status != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("GL: depth FBO incomplete (status " + std::to_string(status) + ")");
    glViewport(0, 0, w, h);
    glCheck("depth target allocation");
    width = w, height = h;
  }
};

GlDepthPeer::GlDepthPeer() {
  std::string tried;
  for (EGLDisplay d : candidateDisplays()) {
    try {
      auto impl = std::make_unique<Impl>();
      impl->open(d);
      impl_ = std::move(impl);
      break;
    } catch (const std::runtime_error& e) {
      tried += std::string(tried.empty() ? "" : "; ") + e.what();
    }
  }
  if (!impl_) throw std::runtime_error("no headless OpenGL context: " + (tried.empty() ? "no EGL display" : tried));
  impl_->setUp();
}

GlDepthPeer::~GlDepthPeer() = default;

const std::string& GlDepthPeer::renderer() const { return impl_->renderer; }
const std::string& GlDepthPeer::version() const { return impl_->version; }
bool GlDepthPeer::software() const {
  return impl_->renderer.find("llvmpipe") != std::string::npos || impl_->renderer.find("softpipe") != std::string::npos;
}

void GlDepthPeer::setScene(const Scene& scene) {
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::uvec3) == 3 * sizeof(GLuint));
  glBindVertexArray(impl_->vao);
  glBindBuffer(GL_ARRAY_BUFFER, impl_->vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(scene.positions.size() * sizeof(glm::vec3)),
               scene.positions.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, impl_->ibo);  // recorded in the VAO
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(scene.triangles.size() * sizeof(glm::uvec3)),
               scene.triangles.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(glm::vec3), nullptr);
  impl_->indexCount = static_cast<GLsizei>(3 * scene.triangles.size());
  glCheck("scene upload");
}

GlFrameTime GlDepthPeer::draw(const glm::mat4& viewProj, int width, int height) {
  if (width != impl_->width || height != impl_->height) impl_->resize(width, height);
  glUseProgram(impl_->program);
  glUniformMatrix4fv(impl_->viewProjLocation, 1, GL_FALSE, &viewProj[0][0]);  // glm is column-major, as GL
  glBindVertexArray(impl_->vao);
  glBindFramebuffer(GL_FRAMEBUFFER, impl_->fbo);
  const auto start = std::chrono::steady_clock::now();
  if (impl_->timerQuery) glBeginQuery(GL_TIME_ELAPSED, impl_->query);
  glClear(GL_DEPTH_BUFFER_BIT);
  glDrawElements(GL_TRIANGLES, impl_->indexCount, GL_UNSIGNED_INT, nullptr);
  if (impl_->timerQuery) glEndQuery(GL_TIME_ELAPSED);
  glFinish();
  GlFrameTime t;
  t.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (impl_->timerQuery) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(impl_->query, GL_QUERY_RESULT, &ns);
    t.queryMs = static_cast<double>(ns) * 1e-6;
  }
  glCheck("depth draw");
  return t;
}

std::vector<float> GlDepthPeer::readDepth() {
  std::vector<float> out(static_cast<size_t>(impl_->width) * impl_->height);
  glBindFramebuffer(GL_FRAMEBUFFER, impl_->fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, impl_->width, impl_->height, GL_DEPTH_COMPONENT, GL_FLOAT, out.data());
  glCheck("depth read-back");
  return out;
}

}  // namespace penumbra
