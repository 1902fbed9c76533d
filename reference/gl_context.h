// reference/gl_context.h — a headless OpenGL 4.5 core context for the GPU-equivalent reference.
//
// EGL on Mesa's surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA through eglGetPlatformDisplay),
// the OpenGL API bound, a 4.5 core context created with EGL_NO_CONFIG_KHR and made current with no
// surface: everything renders into framebuffer objects. No X server, no window. On these machines
// the driver is llvmpipe; on a machine with a GPU the same code runs on the GPU's EGL driver
// (LIBGL_ALWAYS_SOFTWARE=1 forces llvmpipe there). See ../shared/platform-notes.md.
#pragma once

#include <memory>
#include <string>

namespace aq::ref {

class GlContext {
public:
    //! Creates the display and context, makes it current on the calling thread and loads every GL
    //! entry point (reference/gl_api.h). Returns nullptr and sets *error to a sentence saying which
    //! step failed (no EGL display, no surfaceless platform, no GL 4.5 core, missing entry point).
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
    //! True when the renderer is Mesa's CPU rasterizer (llvmpipe or softpipe).
    bool is_software() const;

private:
    GlContext() = default;
    void* display_ = nullptr;  // EGLDisplay
    void* context_ = nullptr;  // EGLContext
    std::string renderer_, version_, vendor_;
};

//! Throws aq::Error with `what` and the pending GL error(s), if any.
void check_gl(const char* what);

}  // namespace aq::ref
