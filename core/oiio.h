// core/oiio.h — OpenImageIO, loaded when first needed (core/oiio_module.h says why).
//
// oiio() loads the module libaq_oiio.so once per process (thread-safe; later calls return at
// once) and returns its table; a missing or unloadable module is an aq::Error naming the file and
// dlerror(). The module is found at the path the build gave it (AQ_OIIO_MODULE_PATH, the build
// folder's core/libaq_oiio.so) unless the environment variable AQ_OIIO_MODULE names another file
// (a relocated build, fuzz/remote). preload_oiio() starts the same load on a background thread so
// that it overlaps other work; the first oiio() call then waits for it to finish.
#pragma once

#include "core/oiio_module.h"

namespace aq {

//! The OpenImageIO module's table, loading it on first use. Throws aq::Error.
const oiio_module::Api& oiio();

//! Starts loading the module on a background thread (once; no effect when loaded or loading). A
//! load that fails there is reported by the next oiio() call, which tries again.
void preload_oiio();

//! Whether the module is loaded in this process (for tests and diagnostics).
bool oiio_loaded();

}  // namespace aq
