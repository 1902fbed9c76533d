// core/oiio_module.h — what Aquarelle asks of OpenImageIO, as a table of functions that a separate
// shared module (core/oiio_module.cpp, built as libaq_oiio.so) provides and core/oiio.cpp loads on
// first use.
//
// Why a module: Debian's OpenImageIO links ~260 shared libraries (OpenCV, FFmpeg, DCMTK, OpenVDB,
// LibRaw, ...). A program linked against it spends 0.25-0.30 s in the dynamic loader before main()
// on our machines (an empty main() linked with it: 0.28-0.35 s; perf of `aquarelle --help`: 68 % in
// ld.so's symbol lookup), whether or not it reads or writes one image through OpenImageIO. Behind
// this table, `aquarelle --help`, argument errors and renders that never need it (grey/RGB PNG
// output is core/png.h) do not load it, and a render starts loading it on a second thread while the
// scene loads (preload_oiio(), core/oiio.h). docs/performance.md "Design decisions that hold".
//
// The table is internal: core/io.cpp, core/compare.cpp and app/grid.cpp call it through oiio()
// (core/oiio.h). The module depends on OpenImageIO and the C++ library only (no aq_core symbol: it
// is loaded into executables that link aq_core statically), so the types here are plain. Both
// sides are compiled by the same build with the same compiler; kOiioModuleAbi changes whenever
// this table does.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/image_header.h"

namespace aq::oiio_module {

inline constexpr int kOiioModuleAbi = 2;

//! One image to encode into memory in the format of `extension` (".exr", ".tif", ".png" with alpha, ...).
struct EncodeRequest {
    std::string extension;  //!< lower case, with the dot
    int width = 0, height = 0, channels = 0;
    const unsigned char* u8 = nullptr;  //!< 8-bit values (display formats), or
    const float* f32 = nullptr;         //!< float values (everything else)
    std::string description;            //!< the ImageDescription attribute; empty: none
    bool stored = false;                //!< Compression::None (core/io.h)
};

//! OpenImageIO's ImageBufAlgo::compare results.
struct CompareResult {
    double meanerror = 0, maxerror = 0, psnr = 0;
    int maxx = 0, maxy = 0, maxc = 0;
};

struct Api {
    int abi = kOiioModuleAbi;
    //! Decodes `size` bytes with OpenImageIO's reader named `format` ("png", "jpeg", "openexr",
    //! ...) only, reading through a bounded in-memory proxy (core/oiio_mem_reader.h); `fake_name`
    //! is the name given to open(); `accept` (core/image_header.h) sees the header first. Returns ""
    //! when decoded, else the reader's error.
    std::string (*decode)(const unsigned char* bytes, std::size_t size, const char* format, const char* fake_name,
                          AcceptHeader accept, void* ctx);
    //! Encodes into `out` (cleared first). Returns "" or the reason it failed.
    std::string (*encode)(const EncodeRequest& request, std::vector<unsigned char>& out);
    //! ImageBufAlgo::compare of two w x h x c float images, failure and warning threshold t.
    CompareResult (*compare)(const float* a, const float* b, int w, int h, int c, double t);
    //! ImageBufAlgo::resize (its default filter) of a w x h x c image to tw x th into dst (tw x th x c).
    //! Returns "" or the error.
    std::string (*resize)(const float* src, int w, int h, int c, int tw, int th, float* dst);
    //! The width in pixels of `text` at `size` in `font` (ImageBufAlgo::text_size); -1 when unknown.
    int (*text_width)(const char* text, int size, const char* font);
    //! ImageBufAlgo::render_text into the w x h RGB float image `rgb`, left/baseline aligned at
    //! (x, y), clipped to [x0, x1) x [y0, y1). Returns "" or the error.
    std::string (*render_text)(float* rgb, int w, int h, int x, int y, const char* text, int size, const char* font,
                               const float color[3], int x0, int x1, int y0, int y1);
};

}  // namespace aq::oiio_module

//! The module's one exported symbol.
extern "C" const aq::oiio_module::Api* aq_oiio_module_api();
