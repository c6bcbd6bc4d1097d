#include "renders/gl_context.h"

#include <dlfcn.h>

#include <atomic>
#include <stdexcept>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>
#include <fmt/format.h>

#include "common/enum_names.h"

namespace trav::renders {
namespace {

// The backend whose library this process loaded first; -1 = none yet.
std::atomic<int> g_loaded_backend{-1};

void ClaimBackend(GlBackend backend) {
  int expected = -1;
  const int wanted = static_cast<int>(backend);
  if (!g_loaded_backend.compare_exchange_strong(expected, wanted) && expected != wanted) {
    throw std::runtime_error(std::string("cannot use the ") + common::NameOf(backend) +
                             " GL backend: this process already uses " +
                             common::NameOf(static_cast<GlBackend>(expected)));
  }
}

// Loads a shared library into the global symbol namespace (where MuJoCo's GL loader looks).
void* OpenLibrary(const char* name, const char* package) {
  void* handle = dlopen(name, RTLD_NOW | RTLD_GLOBAL);
  if (handle == nullptr) {
    throw std::runtime_error(std::string("cannot load ") + name + " (install " + package +
                             "): " + dlerror());
  }
  return handle;
}

template <typename Function>
Function Symbol(void* library, const char* name) {
  void* symbol = dlsym(library, name);
  if (symbol == nullptr) throw std::runtime_error(std::string("GL library lacks ") + name);
  return reinterpret_cast<Function>(symbol);
}

class OsmesaContext final : public GlContext {
 public:
  OsmesaContext(int width, int height) : buffer_(static_cast<std::size_t>(width) * height * 4) {
    library_ = OpenLibrary("libOSMesa.so.8", "libosmesa6");
    auto create = Symbol<OSMesaContext (*)(GLenum, GLint, GLint, GLint, OSMesaContext)>(
        library_, "OSMesaCreateContextExt");
    auto make_current = Symbol<GLboolean (*)(OSMesaContext, void*, GLenum, GLsizei, GLsizei)>(
        library_, "OSMesaMakeCurrent");
    destroy_ = Symbol<void (*)(OSMesaContext)>(library_, "OSMesaDestroyContext");
    get_proc_ = Symbol<void* (*)(const char*)>(library_, "OSMesaGetProcAddress");
    context_ = create(OSMESA_RGBA, 24, 8, 8, nullptr);
    if (context_ == nullptr) throw std::runtime_error("OSMesaCreateContextExt failed");
    if (!make_current(context_, buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
      destroy_(context_);
      throw std::runtime_error("OSMesaMakeCurrent failed");
    }
  }
  ~OsmesaContext() override { destroy_(context_); }
  GlBackend backend() const override { return GlBackend::kOsmesa; }
  void* ProcAddress(const char* name) const override { return get_proc_(name); }

 private:
  void* library_{nullptr};
  std::vector<unsigned char> buffer_;
  OSMesaContext context_{nullptr};
  void (*destroy_)(OSMesaContext){nullptr};
  void* (*get_proc_)(const char*){nullptr};
};

class EglContext final : public GlContext {
 public:
  EglContext() {
    library_ = OpenLibrary("libEGL.so.1", "libegl1 and libegl-mesa0");
    get_proc_ = Symbol<void* (*)(const char*)>(library_, "eglGetProcAddress");
    auto initialize =
        Symbol<EGLBoolean (*)(EGLDisplay, EGLint*, EGLint*)>(library_, "eglInitialize");
    auto choose_config =
        Symbol<EGLBoolean (*)(EGLDisplay, const EGLint*, EGLConfig*, EGLint, EGLint*)>(
            library_, "eglChooseConfig");
    auto bind_api = Symbol<EGLBoolean (*)(EGLenum)>(library_, "eglBindAPI");
    auto create_context = Symbol<EGLContext (*)(EGLDisplay, EGLConfig, EGLContext, const EGLint*)>(
        library_, "eglCreateContext");
    auto make_current = Symbol<EGLBoolean (*)(EGLDisplay, EGLSurface, EGLSurface, EGLContext)>(
        library_, "eglMakeCurrent");
    auto get_error = Symbol<EGLint (*)()>(library_, "eglGetError");
    destroy_context_ =
        Symbol<EGLBoolean (*)(EGLDisplay, EGLContext)>(library_, "eglDestroyContext");
    terminate_ = Symbol<EGLBoolean (*)(EGLDisplay)>(library_, "eglTerminate");

    // headless: Mesa's surfaceless platform needs no display server and no GPU
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(get_proc_("eglGetPlatformDisplayEXT"));
    if (get_platform_display == nullptr)
      throw std::runtime_error("EGL lacks eglGetPlatformDisplayEXT");
    display_ = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display_ == EGL_NO_DISPLAY || !initialize(display_, nullptr, nullptr)) {
      throw std::runtime_error("EGL: cannot initialise the surfaceless display (error 0x" +
                               ToHex(get_error()) + ")");
    }
    const EGLint attributes[] = {EGL_RED_SIZE,
                                 8,
                                 EGL_GREEN_SIZE,
                                 8,
                                 EGL_BLUE_SIZE,
                                 8,
                                 EGL_ALPHA_SIZE,
                                 8,
                                 EGL_DEPTH_SIZE,
                                 24,
                                 EGL_STENCIL_SIZE,
                                 8,
                                 EGL_COLOR_BUFFER_TYPE,
                                 EGL_RGB_BUFFER,
                                 EGL_SURFACE_TYPE,
                                 EGL_PBUFFER_BIT,
                                 EGL_RENDERABLE_TYPE,
                                 EGL_OPENGL_BIT,
                                 EGL_NONE};
    EGLConfig config;
    EGLint num_configs = 0;
    if (!choose_config(display_, attributes, &config, 1, &num_configs) || num_configs < 1) {
      throw std::runtime_error("EGL: no suitable configuration (error 0x" + ToHex(get_error()) +
                               ")");
    }
    if (!bind_api(EGL_OPENGL_API)) throw std::runtime_error("EGL: cannot bind the OpenGL API");
    context_ = create_context(display_, config, EGL_NO_CONTEXT, nullptr);
    if (context_ == EGL_NO_CONTEXT) {
      throw std::runtime_error("EGL: cannot create a context (error 0x" + ToHex(get_error()) + ")");
    }
    if (!make_current(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      throw std::runtime_error("EGL: cannot make the context current (error 0x" +
                               ToHex(get_error()) + ")");
    }
  }
  ~EglContext() override {
    destroy_context_(display_, context_);
    terminate_(display_);
  }
  GlBackend backend() const override { return GlBackend::kEgl; }
  // Mesa's EGL returns core and legacy GL functions too (EGL_KHR_get_all_proc_addresses)
  void* ProcAddress(const char* name) const override { return get_proc_(name); }

 private:
  static std::string ToHex(EGLint value) {
    return fmt::format("{:x}", static_cast<unsigned>(value));
  }
  void* library_{nullptr};
  EGLDisplay display_{EGL_NO_DISPLAY};
  EGLContext context_{EGL_NO_CONTEXT};
  EGLBoolean (*destroy_context_)(EGLDisplay, EGLContext){nullptr};
  EGLBoolean (*terminate_)(EGLDisplay){nullptr};
  void* (*get_proc_)(const char*){nullptr};
};

}  // namespace

std::unique_ptr<GlContext> GlContext::Create(GlBackend backend, int width, int height) {
  ClaimBackend(backend);
  if (backend == GlBackend::kOsmesa) return std::make_unique<OsmesaContext>(width, height);
  return std::make_unique<EglContext>();
}

}  // namespace trav::renders
