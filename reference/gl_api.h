// reference/gl_api.h — the OpenGL 4.5 core entry points the reference harness uses, loaded at run
// time through eglGetProcAddress (we link only -lEGL; never libGL together with libOSMesa, see
// ../shared/platform-notes.md). Types and enums come from Khronos' <GL/glcorearb.h>, which
// declares no prototypes unless GL_GLCOREARB_PROTOTYPES is defined, so these pointers cannot
// collide with a system libGL.
#pragma once

#include <GL/glcorearb.h>

namespace aq::ref::gl {

// X(type, name): name is the GL function without its "gl" prefix.
#define AQ_GL_FUNCTIONS(X)                                                         \
    X(PFNGLGETERRORPROC, GetError)                                                 \
    X(PFNGLGETSTRINGPROC, GetString)                                               \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                           \
    X(PFNGLFINISHPROC, Finish)                                                     \
    X(PFNGLFLUSHPROC, Flush)                                                       \
    X(PFNGLVIEWPORTPROC, Viewport)                                                 \
    X(PFNGLCLEARPROC, Clear)                                                       \
    X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                                       \
    X(PFNGLENABLEPROC, Enable)                                                     \
    X(PFNGLDISABLEPROC, Disable)                                                   \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                                               \
    X(PFNGLDEPTHMASKPROC, DepthMask)                                               \
    X(PFNGLBLENDFUNCPROC, BlendFunc)                                               \
    X(PFNGLCLIPCONTROLPROC, ClipControl)                                           \
    X(PFNGLCULLFACEPROC, CullFace)                                                 \
    X(PFNGLFRONTFACEPROC, FrontFace)                                               \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                           \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                             \
    X(PFNGLREADBUFFERPROC, ReadBuffer)                                             \
    X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                           \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                                             \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)                                         \
    X(PFNGLGENTEXTURESPROC, GenTextures)                                           \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                     \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                                           \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                       \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                             \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                       \
    X(PFNGLGENSAMPLERSPROC, GenSamplers)                                           \
    X(PFNGLDELETESAMPLERSPROC, DeleteSamplers)                                     \
    X(PFNGLBINDSAMPLERPROC, BindSampler)                                           \
    X(PFNGLSAMPLERPARAMETERIPROC, SamplerParameteri)                               \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                   \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                             \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                   \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                         \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                     \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                                 \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                           \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                 \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                           \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                   \
    X(PFNGLCREATESHADERPROC, CreateShader)                                         \
    X(PFNGLDELETESHADERPROC, DeleteShader)                                         \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                                         \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                                       \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                                           \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                 \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                       \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                       \
    X(PFNGLATTACHSHADERPROC, AttachShader)                                         \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                                           \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                         \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                               \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                             \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                             \
    X(PFNGLUNIFORM1FPROC, Uniform1f)                                               \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                                               \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                                               \
    X(PFNGLUNIFORM2IPROC, Uniform2i)                                               \
    X(PFNGLUNIFORM3FPROC, Uniform3f)                                               \
    X(PFNGLUNIFORM4FPROC, Uniform4f)                                               \
    X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                                 \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                                 \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                   \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                             \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                   \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                                             \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                       \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                                             \
    X(PFNGLBUFFERDATAPROC, BufferData)                                             \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                   \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                           \
    X(PFNGLVERTEXATTRIBIPOINTERPROC, VertexAttribIPointer)

#define AQ_GL_DECLARE(type, name) extern type name;
AQ_GL_FUNCTIONS(AQ_GL_DECLARE)
#undef AQ_GL_DECLARE

}  // namespace aq::ref::gl
