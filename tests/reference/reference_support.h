// tests/reference/reference_support.h — the one allowed skip: no EGL/GL context on a local machine.
// In CI (environment variable CI set) a missing context is a loud failure.
#pragma once

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "reference/gl_context.h"

#define AQ_REQUIRE_GL()                                                                              \
    do {                                                                                             \
        std::string aq_gl_why;                                                                       \
        if (!::aq::ref::GlContext::shared(&aq_gl_why)) {                                             \
            if (std::getenv("CI"))                                                                   \
                FAIL() << "CI is set and no OpenGL 4.5 context could be created: " << aq_gl_why      \
                       << " (the set-up script must install libegl-mesa0 libgl1-mesa-dri)";          \
            GTEST_SKIP() << "no OpenGL 4.5 context (EGL surfaceless): " << aq_gl_why                 \
                         << " — the GPU-equivalent reference checks need libegl-mesa0 libgl1-mesa-dri"; \
        }                                                                                            \
    } while (0)
