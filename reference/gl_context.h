// reference/gl_context.h — a headless OpenGL 4.5 core context for the GPU-equivalent reference.
//
// EGL on Mesa's surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA through eglGetPlatformDisplay),
// the OpenGL API bound, a 4.5 core context created with EGL_NO_CONFIG_KHR and made current with no
// surface: everything renders into framebuffer objects. No X server, no window. On these machines
// the driver is llvmpipe; on a machine with a GPU the same code runs on the GPU's EGL driver
// (LIBGL_ALWAYS_SOFTWARE=1 forces llvmpipe there). See ../shared/platform-notes.md.
//
// A libEGL without EGL_MESA_platform_surfaceless (NVIDIA's, through GLVND) is reached through
// EGL_EXT_platform_device instead: the first enumerated device whose display initialises. The
// environment variable AQ_GL_PLATFORM picks: unset or "auto" (surfaceless, then device),
// "surfaceless", "device". Where a display lacks EGL_KHR_no_config_context or
// EGL_KHR_surfaceless_context, a pbuffer config and a 1x1 pbuffer stand in (never the case on Mesa).
#pragma once

#include <memory>
#include <string>

namespace aq::ref {

class GlContext {
public:
    //! Creates the display and context, makes it current on the calling thread and loads every GL
    //! entry point (reference/gl_api.h). Returns nullptr and sets *error to a sentence saying which
    //! step failed (no EGL display, no surfaceless/device platform, no GL 4.5 core, missing entry
    //! point), per platform tried.
    static std::unique_ptr<GlContext> create(std::string* error);

    //! One context per process, created on first use and kept current on the creating thread.
    //! Returns nullptr (and the reason in *error) when create() fails; the failure is remembered.
    static GlContext* shared(std::string* error = nullptr);

    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    //! Makes this context current on the calling thread.
    void make_current() const;

    const std::string& renderer() const { return renderer_; }  //!< GL_RENDERER
    const std::string& version() const { return version_; }    //!< GL_VERSION
    const std::string& vendor() const { return vendor_; }      //!< GL_VENDOR
    //! How the display was obtained: "surfaceless (...)" or "device <i> of <n> (...)".
    const std::string& platform() const { return platform_; }
    //! True when the renderer is Mesa's CPU rasterizer (llvmpipe or softpipe).
    bool is_software() const;

private:
    GlContext() = default;
    bool finish_setup(std::string* error);  // loads GL, reads the strings, checks 4.5
    void* display_ = nullptr;  // EGLDisplay
    void* surface_ = nullptr;  // EGLSurface: null (no surface) except for the pbuffer fallback
    void* context_ = nullptr;  // EGLContext
    std::string renderer_, version_, vendor_, platform_;
};

//! Throws aq::Error with `what` and the pending GL error(s), if any.
void check_gl(const char* what);

}  // namespace aq::ref
