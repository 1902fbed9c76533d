// core/oiio_module.cpp — the OpenImageIO module (libaq_oiio.so): the only code that calls
// OpenImageIO, behind the table of core/oiio_module.h. No aq_core symbol is used here.
#include "core/oiio_module.h"

#include <algorithm>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "core/oiio_mem_reader.h"

namespace aq::oiio_module {
namespace {

// PNG with alpha goes through OpenImageIO's writer (grey and RGB PNG are core/png.h), told that
// memory holds straight alpha as PNG does (oiio:UnassociatedAlpha, on read too), with these
// settings, chosen for speed (issue 13): zlib level 1 and no row filter (libpng's
// PNG_FILTER_NONE). Measured on WC18 1080p Suzanne frames, 12-frame CLI animation, 2 cores:
// libpng's defaults (level 6, adaptive filters) 845-911 ms/frame and 2.78 MB/frame; level 1 +
// adaptive 375-418 ms, 3.09 MB; level 1 + no filter 299-309 ms, 2.86 MB (+3 %). The paper grain
// makes row filters useless on our images.
constexpr int kPngCompressionLevel = 1;
constexpr int kPngFilterNone = 0x08;
// OpenEXR compression: PIZ (lossless wavelet + Huffman). Same measurement, .exr output: ZIP (used
// before) 852 ms/frame and 18.4 MB/frame, ZIP level 1 807 ms 18.1 MB, PIZ 654 ms 17.6 MB, RLE
// 462 ms 24.9 MB, none 372 ms 24.9 MB: PIZ is both faster and smaller than ZIP on noisy float
// images; values are bit-exact in every lossless mode.
constexpr const char* kExrCompression = "piz";

std::string decode(const unsigned char* bytes, std::size_t size, const char* format, const char* fake_name,
                   AcceptHeader accept, void* ctx) {
    detail::BoundedMemReader mem(bytes, size);
    // create() is given the bare format name: for a file name, OpenImageIO 2.4 first asks that
    // format's reader whether the bytes are valid and, if not, tries every reader it has (DICOM,
    // FITS, ...), so an allow-listed extension would not keep the other decoders away (found by
    // fuzzing with those libraries stubbed: fuzz/README.md). OIIO 2.4 honours an in-memory proxy
    // passed as the "oiio:ioproxy" configuration hint (the ioproxy argument alone is not enough
    // for its PNG reader).
    auto in = OIIO::ImageInput::create(format, false, nullptr, &mem);
    if (!in || in->format_name() != std::string(format)) {
        const std::string e = OIIO::geterror();
        return e.empty() ? std::string("no reader") : e;
    }
    OIIO::ImageSpec config;
    void* proxy = &mem;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    // Straight (unassociated) alpha in memory, as the files that hold it (PNG, TGA) store it and as
    // glTF 2.0 defines its textures: OpenImageIO would otherwise multiply colour by alpha on read.
    config.attribute("oiio:UnassociatedAlpha", 1);
    OIIO::ImageSpec opened;
    if (!in->open(fake_name, opened, config)) {
        const std::string e = in->geterror();
        return e.empty() ? std::string("cannot be opened") : e;
    }
    const OIIO::ImageSpec& spec = in->spec();
    float* dst = accept(ctx, ImageHeader{spec.width, spec.height, spec.depth, spec.nchannels, spec.deep}).values;
    if (!dst) return "no float destination";  // codes are asked of core/png.h and core/jpeg.h only
    const int c = std::min(spec.nchannels, 4);
    if (!in->read_image(0, 0, 0, c, OIIO::TypeDesc::FLOAT, dst)) {
        const std::string e = in->geterror();
        return e.empty() ? std::string("cannot be read") : e;
    }
    in->close();
    return {};
}

std::string encode(const EncodeRequest& r, std::vector<unsigned char>& out) {
    const bool eight_bit = r.u8 != nullptr;
    OIIO::ImageSpec spec(r.width, r.height, r.channels, eight_bit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT);
    // 8-bit images are display images: sRGB-encoded in either working space (docs/look.md), tagged
    // so (the PNG writer emits an sRGB chunk). Float files hold the working-space values untagged.
    if (eight_bit) spec.attribute("oiio:ColorSpace", "sRGB");
    // Our RGBA images hold straight alpha (the G-buffer colour: docs/raster.md "Targets"): written
    // as they are. Without this the PNG writer divides colour by alpha (it takes memory as
    // associated), which turned every partly covered pixel of a --style none image white.
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (r.extension == ".png") {
        spec.attribute("png:compressionLevel", r.stored ? 0 : kPngCompressionLevel);
        spec.attribute("png:filter", kPngFilterNone);
    }
    if (r.extension == ".exr") {
        spec.attribute("compression", r.stored ? "none" : kExrCompression);
        // OpenImageIO stamps EXR files with the wall-clock time (capDate) unless DateTime is set;
        // a fixed value keeps "same input, same bytes" true for whole files, not only pixels.
        spec.attribute("DateTime", "1970:01:01 00:00:00");
    }
    if (!r.description.empty()) spec.attribute("ImageDescription", r.description);
    const std::string fake = "memory" + r.extension;
    auto writer = OIIO::ImageOutput::create(fake);
    if (!writer) return "no writer for '" + r.extension + "': " + OIIO::geterror();
    if (!writer->supports("ioproxy"))
        return "the '" + r.extension + "' writer cannot encode to memory; use .png, .exr, .tif or .jpg";
    out.clear();
    OIIO::Filesystem::IOVecOutput vec(out);
    if (!writer->set_ioproxy(&vec) || !writer->open(fake, spec)) return writer->geterror();
    const bool ok = eight_bit ? writer->write_image(OIIO::TypeDesc::UINT8, r.u8)
                              : writer->write_image(OIIO::TypeDesc::FLOAT, r.f32);
    std::string err = ok ? "" : writer->geterror();
    if (!writer->close() && err.empty()) err = writer->geterror();
    if (!ok && err.empty()) err = "the encoder failed";
    return err;
}

OIIO::ImageBuf wrap(const float* p, int w, int h, int c) {
    return OIIO::ImageBuf(OIIO::ImageSpec(w, h, c, OIIO::TypeDesc::FLOAT), const_cast<float*>(p));
}

CompareResult compare(const float* a, const float* b, int w, int h, int c, double t) {
    const OIIO::ImageBuf A = wrap(a, w, h, c), B = wrap(b, w, h, c);
    const auto r = OIIO::ImageBufAlgo::compare(A, B, float(t), float(t));
    return {r.meanerror, r.maxerror, r.PSNR, r.maxx, r.maxy, r.maxc};
}

std::string resize(const float* src, int w, int h, int c, int tw, int th, float* dst) {
    OIIO::ImageBuf out;
    if (!OIIO::ImageBufAlgo::resize(out, wrap(src, w, h, c), "", 0.0f, OIIO::ROI(0, tw, 0, th, 0, 1, 0, c)))
        return out.geterror();
    if (!out.get_pixels(OIIO::ROI(0, tw, 0, th, 0, 1, 0, c), OIIO::TypeDesc::FLOAT, dst)) return out.geterror();
    return {};
}

int text_width(const char* text, int size, const char* font) {
    const OIIO::ROI r = OIIO::ImageBufAlgo::text_size(text, size, font);
    return r.defined() ? r.width() : -1;
}

std::string render_text(float* rgb, int w, int h, int x, int y, const char* text, int size, const char* font,
                        const float color[3], int x0, int x1, int y0, int y1) {
    OIIO::ImageBuf sheet = wrap(rgb, w, h, 3);  // wraps rgb: the text is drawn into it
    if (!OIIO::ImageBufAlgo::render_text(sheet, x, y, text, size, font, {color, 3},
                                         OIIO::ImageBufAlgo::TextAlignX::Left,
                                         OIIO::ImageBufAlgo::TextAlignY::Baseline, 0,
                                         OIIO::ROI(x0, x1, y0, y1, 0, 1, 0, 3)))
        return sheet.geterror();
    return {};
}

const Api kApi{kOiioModuleAbi, decode, encode, compare, resize, text_width, render_text};

}  // namespace
}  // namespace aq::oiio_module

extern "C" __attribute__((visibility("default"))) const aq::oiio_module::Api* aq_oiio_module_api() {
    return &aq::oiio_module::kApi;
}
