// reference/gl_context.cpp — EGL surfaceless context creation and the GL entry-point loader.
#include "reference/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <mutex>
#include <sstream>

#include "core/image.h"
#include "reference/gl_api.h"

namespace aq::ref {

namespace gl {
#define AQ_GL_DEFINE(type, name) type name = nullptr;
AQ_GL_FUNCTIONS(AQ_GL_DEFINE)
#undef AQ_GL_DEFINE
}  // namespace gl

namespace {

std::string egl_error_string(EGLint e) {
    std::ostringstream s;
    s << "EGL error 0x" << std::hex << e;
    return s.str();
}

bool load_gl(std::string* error) {
    bool ok = true;
    std::string missing;
#define AQ_GL_LOAD(type, name)                                                           \
    gl::name = reinterpret_cast<type>(eglGetProcAddress("gl" #name));                    \
    if (!gl::name) {                                                                      \
        ok = false;                                                                       \
        missing += (missing.empty() ? "" : ", ") + std::string("gl" #name);               \
    }
    AQ_GL_FUNCTIONS(AQ_GL_LOAD)
#undef AQ_GL_LOAD
    if (!ok && error) *error = "eglGetProcAddress returned null for: " + missing;
    return ok;
}

}  // namespace

std::unique_ptr<GlContext> GlContext::create(std::string* error) {
    std::string dummy;
    std::string& err = error ? *error : dummy;
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client_ext) {
        err = "EGL client extensions unavailable (no libEGL/Mesa EGL driver? install libegl-mesa0)";
        return nullptr;
    }
    const std::string exts = client_ext;
    if (exts.find("EGL_MESA_platform_surfaceless") == std::string::npos) {
        err = "EGL_MESA_platform_surfaceless is not supported by this libEGL (client extensions: " + exts + ")";
        return nullptr;
    }
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    EGLDisplay dpy = EGL_NO_DISPLAY;
    if (get_platform_display) dpy = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy == EGL_NO_DISPLAY) {
        err = "eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA) failed: " + egl_error_string(eglGetError());
        return nullptr;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) {
        err = "eglInitialize on the surfaceless display failed: " + egl_error_string(eglGetError()) +
              " (is libgl1-mesa-dri installed?)";
        return nullptr;
    }
    const std::string dpy_ext = eglQueryString(dpy, EGL_EXTENSIONS);
    for (const char* need : {"EGL_KHR_no_config_context", "EGL_KHR_surfaceless_context", "EGL_KHR_create_context"}) {
        if (dpy_ext.find(need) == std::string::npos) {
            err = std::string("EGL display lacks ") + need;
            eglTerminate(dpy);
            return nullptr;
        }
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        err = "eglBindAPI(EGL_OPENGL_API) failed: " + egl_error_string(eglGetError());
        eglTerminate(dpy);
        return nullptr;
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (ctx == EGL_NO_CONTEXT) {
        err = "eglCreateContext (OpenGL 4.5 core, EGL_NO_CONFIG_KHR) failed: " + egl_error_string(eglGetError());
        eglTerminate(dpy);
        return nullptr;
    }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        err = "eglMakeCurrent with no surface failed: " + egl_error_string(eglGetError());
        eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return nullptr;
    }
    std::unique_ptr<GlContext> c(new GlContext);
    c->display_ = dpy;
    c->context_ = ctx;
    if (!load_gl(&err)) return nullptr;
    auto str = [](GLenum e) {
        const GLubyte* s = gl::GetString(e);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    c->renderer_ = str(GL_RENDERER);
    c->version_ = str(GL_VERSION);
    c->vendor_ = str(GL_VENDOR);
    GLint maj = 0, min = 0;
    gl::GetIntegerv(GL_MAJOR_VERSION, &maj);
    gl::GetIntegerv(GL_MINOR_VERSION, &min);
    if (maj * 10 + min < 45) {
        err = "context is OpenGL " + c->version_ + ", 4.5 core needed";
        return nullptr;
    }
    // Exact float in, float out: no clamping of fragment colours or read-back values.
    gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    return c;
}

GlContext* GlContext::shared(std::string* error) {
    static std::once_flag once;
    static std::unique_ptr<GlContext> ctx;
    static std::string why;
    std::call_once(once, [] { ctx = create(&why); });
    if (!ctx && error) *error = why;
    return ctx.get();
}

GlContext::~GlContext() {
    auto dpy = static_cast<EGLDisplay>(display_);
    if (!dpy) return;
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_) eglDestroyContext(dpy, static_cast<EGLContext>(context_));
    eglTerminate(dpy);
}

void GlContext::make_current() const {
    if (!eglMakeCurrent(static_cast<EGLDisplay>(display_), EGL_NO_SURFACE, EGL_NO_SURFACE,
                        static_cast<EGLContext>(context_)))
        throw Error("eglMakeCurrent failed: " + egl_error_string(eglGetError()));
}

bool GlContext::is_software() const {
    return renderer_.find("llvmpipe") != std::string::npos || renderer_.find("softpipe") != std::string::npos;
}

void check_gl(const char* what) {
    std::string errs;
    for (int i = 0; i < 8; ++i) {
        GLenum e = gl::GetError();
        if (e == GL_NO_ERROR) break;
        std::ostringstream s;
        s << (errs.empty() ? "" : ", ") << "0x" << std::hex << e;
        errs += s.str();
    }
    if (!errs.empty()) throw Error(std::string("OpenGL error after ") + what + ": " + errs);
}

}  // namespace aq::ref
