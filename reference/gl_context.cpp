// reference/gl_context.cpp — EGL context creation (Mesa surfaceless, else EGL_EXT_platform_device) and
// the GL entry-point loader.
#include "reference/gl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <vector>

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

bool has_ext(const std::string& list, const char* name) {
    // Whole-word match: "EGL_KHR_no_config_context" must not match a longer name.
    const std::string n = name;
    for (std::size_t pos = list.find(n); pos != std::string::npos; pos = list.find(n, pos + 1)) {
        const bool start_ok = pos == 0 || list[pos - 1] == ' ';
        const bool end_ok = pos + n.size() == list.size() || list[pos + n.size()] == ' ';
        if (start_ok && end_ok) return true;
    }
    return false;
}

//! An initialised EGL display and how it was obtained, or the reason there is none.
struct OpenedDisplay {
    EGLDisplay dpy = EGL_NO_DISPLAY;
    std::string platform;  // "surfaceless (EGL_MESA_platform_surfaceless)" or "device 0 of 1 (...)"
};

PFNEGLGETPLATFORMDISPLAYEXTPROC platform_display_fn() {
    return reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
}

//! Mesa's surfaceless platform (the default on our CPU machines: llvmpipe).
OpenedDisplay open_surfaceless(const std::string& client_exts, std::string& err) {
    OpenedDisplay o;
    if (!has_ext(client_exts, "EGL_MESA_platform_surfaceless")) {
        err = "EGL_MESA_platform_surfaceless is not supported by this libEGL (client extensions: " + client_exts + ")";
        return o;
    }
    auto get_platform_display = platform_display_fn();
    EGLDisplay dpy = EGL_NO_DISPLAY;
    if (get_platform_display) dpy = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (dpy == EGL_NO_DISPLAY) {
        err = "eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA) failed: " + egl_error_string(eglGetError());
        return o;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) {
        err = "eglInitialize on the surfaceless display failed: " + egl_error_string(eglGetError()) +
              " (is libgl1-mesa-dri installed?)";
        return o;
    }
    o.dpy = dpy;
    o.platform = "surfaceless (EGL_MESA_platform_surfaceless)";
    return o;
}

//! EGL_EXT_platform_device: the first enumerated device whose display initialises (NVIDIA's
//! libEGL offers this, and not necessarily the Mesa surfaceless platform).
OpenedDisplay open_device(const std::string& client_exts, std::string& err) {
    OpenedDisplay o;
    // EGL_EXT_device_base is EGL_EXT_device_enumeration + EGL_EXT_device_query.
    const bool enumeration = has_ext(client_exts, "EGL_EXT_device_base") || has_ext(client_exts, "EGL_EXT_device_enumeration");
    if (!has_ext(client_exts, "EGL_EXT_platform_device") || !enumeration) {
        err = "EGL_EXT_platform_device with EGL_EXT_device_enumeration is not supported by this libEGL (client extensions: " +
              client_exts + ")";
        return o;
    }
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    auto get_platform_display = platform_display_fn();
    if (!query_devices || !get_platform_display) {
        err = "eglQueryDevicesEXT or eglGetPlatformDisplayEXT not found";
        return o;
    }
    EGLDeviceEXT devices[16];
    EGLint n = 0;
    if (!query_devices(16, devices, &n) || n <= 0) {
        err = "eglQueryDevicesEXT found no EGL device: " + egl_error_string(eglGetError());
        return o;
    }
    std::string why;
    for (EGLint i = 0; i < n; ++i) {
        std::string desc;
        if (query_device_string) {
            if (const char* e = query_device_string(devices[i], EGL_EXTENSIONS)) desc = e;
            if (has_ext(desc, "EGL_EXT_device_drm"))
                if (const char* f = query_device_string(devices[i], EGL_DRM_DEVICE_FILE_EXT)) desc += std::string(" ") + f;
        }
        EGLDisplay dpy = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        EGLint major = 0, minor = 0;
        if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor)) {
            why += "; device " + std::to_string(i) + " (" + desc + "): " + egl_error_string(eglGetError());
            continue;
        }
        o.dpy = dpy;
        o.platform = "device " + std::to_string(i) + " of " + std::to_string(n) + " (EGL_EXT_platform_device; " +
                     (desc.empty() ? std::string("no device extensions") : desc) + ")";
        return o;
    }
    err = "no EGL device display could be initialised" + why;
    return o;
}

//! Binds OpenGL, makes a 4.5 core context current on `dpy` (no config and no surface where the
//! display allows it, else a pbuffer config and a 1x1 pbuffer) and loads the GL entry points.
//! Terminates `dpy` on failure.
bool create_on(EGLDisplay dpy, void*& surface_out, void*& context_out, std::string& err) {
    const char* de = eglQueryString(dpy, EGL_EXTENSIONS);
    const std::string dpy_ext = de ? de : "";
    if (!has_ext(dpy_ext, "EGL_KHR_create_context")) {
        err = "EGL display lacks EGL_KHR_create_context";
        eglTerminate(dpy);
        return false;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        err = "eglBindAPI(EGL_OPENGL_API) failed: " + egl_error_string(eglGetError());
        eglTerminate(dpy);
        return false;
    }
    const bool no_config = has_ext(dpy_ext, "EGL_KHR_no_config_context");
    const bool surfaceless = has_ext(dpy_ext, "EGL_KHR_surfaceless_context");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!no_config || !surfaceless) {
        const EGLint cfg_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                      EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
        EGLint num = 0;
        if (!eglChooseConfig(dpy, cfg_attribs, &config, 1, &num) || num < 1) {
            err = "EGL display lacks EGL_KHR_no_config_context/EGL_KHR_surfaceless_context and has no pbuffer "
                  "OpenGL config: " + egl_error_string(eglGetError());
            eglTerminate(dpy);
            return false;
        }
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
    if (ctx == EGL_NO_CONTEXT) {
        err = std::string("eglCreateContext (OpenGL 4.5 core, ") + (no_config && surfaceless ? "EGL_NO_CONFIG_KHR" : "pbuffer config") +
              ") failed: " + egl_error_string(eglGetError());
        eglTerminate(dpy);
        return false;
    }
    EGLSurface surf = EGL_NO_SURFACE;
    if (!surfaceless) {
        const EGLint pb_attribs[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        surf = eglCreatePbufferSurface(dpy, config, pb_attribs);
        if (surf == EGL_NO_SURFACE) {
            err = "EGL display lacks EGL_KHR_surfaceless_context and eglCreatePbufferSurface failed: " +
                  egl_error_string(eglGetError());
            eglDestroyContext(dpy, ctx);
            eglTerminate(dpy);
            return false;
        }
    }
    if (!eglMakeCurrent(dpy, surf, surf, ctx)) {
        err = std::string("eglMakeCurrent with ") + (surf == EGL_NO_SURFACE ? "no surface" : "a 1x1 pbuffer") +
              " failed: " + egl_error_string(eglGetError());
        if (surf != EGL_NO_SURFACE) eglDestroySurface(dpy, surf);
        eglDestroyContext(dpy, ctx);
        eglTerminate(dpy);
        return false;
    }
    surface_out = surf;
    context_out = ctx;
    return true;
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
    // AQ_GL_PLATFORM: unset/"auto" tries Mesa surfaceless first (llvmpipe on our CPU machines),
    // then EGL_EXT_platform_device (a GPU driver's libEGL, e.g. NVIDIA's); "surfaceless" or
    // "device" tries only that one.
    std::string choice = "auto";
    if (const char* e = std::getenv("AQ_GL_PLATFORM"); e && *e) choice = e;
    std::vector<std::string> order;
    if (choice == "auto") order = {"surfaceless", "device"};
    else if (choice == "surfaceless" || choice == "device") order = {choice};
    else {
        err = "AQ_GL_PLATFORM=" + choice + " is not one of auto, surfaceless, device";
        return nullptr;
    }
    std::string why;
    for (const std::string& platform : order) {
        std::string e;
        OpenedDisplay od = platform == "surfaceless" ? open_surfaceless(exts, e) : open_device(exts, e);
        void* surf = nullptr;
        void* ctx = nullptr;
        if (od.dpy != EGL_NO_DISPLAY) {
            if (create_on(od.dpy, surf, ctx, e)) {
                std::unique_ptr<GlContext> c(new GlContext);
                c->display_ = od.dpy;
                c->surface_ = surf;
                c->context_ = ctx;
                c->platform_ = od.platform;
                if (!c->finish_setup(&e)) {
                    why += (why.empty() ? "" : "; ") + platform + ": " + e;
                    continue;  // the destructor released the display
                }
                return c;
            }
        }
        why += (why.empty() ? "" : "; ") + (order.size() > 1 ? platform + ": " : std::string()) + e;
    }
    err = why;
    return nullptr;
}

bool GlContext::finish_setup(std::string* error) {
    if (!load_gl(error)) return false;
    auto str = [](GLenum e) {
        const GLubyte* s = gl::GetString(e);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
    };
    renderer_ = str(GL_RENDERER);
    version_ = str(GL_VERSION);
    vendor_ = str(GL_VENDOR);
    GLint maj = 0, min = 0;
    gl::GetIntegerv(GL_MAJOR_VERSION, &maj);
    gl::GetIntegerv(GL_MINOR_VERSION, &min);
    if (maj * 10 + min < 45) {
        if (error) *error = "context is OpenGL " + version_ + ", 4.5 core needed";
        return false;
    }
    // Exact float in, float out: no clamping of fragment colours or read-back values.
    gl::PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl::PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    return true;
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
    if (surface_) eglDestroySurface(dpy, static_cast<EGLSurface>(surface_));
    eglTerminate(dpy);
}

void GlContext::make_current() const {
    auto surf = surface_ ? static_cast<EGLSurface>(surface_) : EGL_NO_SURFACE;
    if (!eglMakeCurrent(static_cast<EGLDisplay>(display_), surf, surf, static_cast<EGLContext>(context_)))
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
