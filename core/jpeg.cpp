// core/jpeg.cpp — see jpeg.h.
//
// libjpeg reports a fatal error through error_exit, which must not return: the usual setjmp /
// longjmp. The functions that call setjmp (read_header, decompress) hold no object with a
// destructor, so the jump skips none; the decompressor is destroyed by Decoder's destructor in
// the caller, after the jump, whatever happened.
#include "core/jpeg.h"

#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <jpeglib.h>

#include "core/image.h"
#include "core/io.h"
#include "core/unorm8.h"

namespace aq {
namespace {

struct ErrorManager {
    jpeg_error_mgr pub;  // first: libjpeg passes &pub
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
};

[[noreturn]] void on_error(j_common_ptr c) {
    auto* e = reinterpret_cast<ErrorManager*>(c->err);
    (*c->err->format_message)(c, e->message);
    std::longjmp(e->jump, 1);
}

//! Warnings (corrupt or truncated data, which libjpeg fills in) are not printed and not fatal, as
//! in OpenImageIO's reader.
void on_message(j_common_ptr) {}

struct Decoder {
    jpeg_decompress_struct cinfo{};
    ErrorManager err;
    bool created = false;
    Decoder() {
        cinfo.err = jpeg_std_error(&err.pub);
        err.pub.error_exit = on_error;
        err.pub.output_message = on_message;
    }
    ~Decoder() {
        if (created) jpeg_destroy_decompress(&cinfo);
    }
    Decoder(const Decoder&) = delete;
    Decoder& operator=(const Decoder&) = delete;
};

bool read_header(Decoder& d, const unsigned char* bytes, std::size_t size) {
    if (setjmp(d.err.jump)) return false;
    jpeg_create_decompress(&d.cinfo);
    d.created = true;
    jpeg_mem_src(&d.cinfo, bytes, static_cast<unsigned long>(size));
    jpeg_read_header(&d.cinfo, TRUE);
    return true;
}

bool decompress(Decoder& d, PixelDest dst) {
    const float* const unorm8 = unorm8_floats();
    if (setjmp(d.err.jump)) return false;
    jpeg_start_decompress(&d.cinfo);
    const std::size_t row_values = std::size_t(d.cinfo.output_width) * std::size_t(d.cinfo.output_components);
    // Freed with the decompressor (libjpeg's image pool).
    JSAMPARRAY row = (*d.cinfo.mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(&d.cinfo), JPOOL_IMAGE,
                                                   static_cast<JDIMENSION>(row_values), 1);
    while (d.cinfo.output_scanline < d.cinfo.output_height) {
        const std::size_t y = d.cinfo.output_scanline;
        if (dst.rgba_codes) row[0] = dst.rgba_codes + y * row_values;  // JCS_EXT_RGBA rows in place
        if (jpeg_read_scanlines(&d.cinfo, row, 1) != 1) {  // not with a memory source, which never suspends
            std::snprintf(d.err.message, sizeof d.err.message, "no scanline %u", d.cinfo.output_scanline);
            return false;
        }
        if (dst.rgba_codes) continue;
        float* out = dst.values + y * row_values;
        const JSAMPLE* in = row[0];
        for (std::size_t i = 0; i < row_values; ++i) out[i] = unorm8[in[i]];
    }
    jpeg_finish_decompress(&d.cinfo);
    return true;
}

struct Encoder {
    jpeg_compress_struct cinfo{};
    ErrorManager err;
    bool created = false;
    unsigned char* buffer = nullptr;  // jpeg_mem_dest's, malloc'ed
    unsigned long size = 0;
    Encoder() {
        cinfo.err = jpeg_std_error(&err.pub);
        err.pub.error_exit = on_error;
        err.pub.output_message = on_message;
    }
    ~Encoder() {
        if (created) jpeg_destroy_compress(&cinfo);
        std::free(buffer);
    }
    Encoder(const Encoder&) = delete;
    Encoder& operator=(const Encoder&) = delete;
};

bool compress(Encoder& e, int width, int height, int channels, int quality, const unsigned char* rows) {
    if (setjmp(e.err.jump)) return false;
    jpeg_create_compress(&e.cinfo);
    e.created = true;
    jpeg_mem_dest(&e.cinfo, &e.buffer, &e.size);
    e.cinfo.image_width = static_cast<JDIMENSION>(width);
    e.cinfo.image_height = static_cast<JDIMENSION>(height);
    e.cinfo.input_components = channels;
    e.cinfo.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&e.cinfo);
    jpeg_set_quality(&e.cinfo, quality, TRUE);
    jpeg_start_compress(&e.cinfo, TRUE);
    const std::size_t stride = std::size_t(width) * std::size_t(channels);
    while (e.cinfo.next_scanline < e.cinfo.image_height) {
        JSAMPROW row = const_cast<JSAMPROW>(rows + std::size_t(e.cinfo.next_scanline) * stride);
        jpeg_write_scanlines(&e.cinfo, &row, 1);
    }
    jpeg_finish_compress(&e.cinfo);
    return true;
}

}  // namespace

void encode_jpeg(const ImageF& img, int quality, std::vector<unsigned char>& out, std::vector<unsigned char>& rows) {
    const int c = img.channels();
    if (img.empty() || (c != 1 && c != 3)) throw Error("JPEG: needs a non-empty grey or RGB image");
    if (quality < 1 || quality > 100) throw Error("JPEG: quality " + std::to_string(quality) + " outside [1, 100]");
    rows.resize(img.num_values());
    to_unorm8_n(img.data(), rows.data(), rows.size());
    Encoder e;
    if (!compress(e, img.width(), img.height(), c, quality, rows.data())) throw Error(std::string("JPEG: cannot encode: ") + e.err.message);
    out.assign(e.buffer, e.buffer + e.size);
}

bool decode_jpeg(const unsigned char* bytes, std::size_t size, const std::string& where, AcceptHeader accept,
                 void* ctx) {
    Decoder d;
    if (!read_header(d, bytes, size)) throw Error(where + ": cannot be decoded: " + d.err.message);
    const J_COLOR_SPACE cs = d.cinfo.jpeg_color_space;
    const int n = d.cinfo.num_components;
    const bool grey = n == 1 && cs == JCS_GRAYSCALE;
    const bool colour = n == 3 && (cs == JCS_YCbCr || cs == JCS_RGB);
    if (!grey && !colour) return false;  // CMYK, YCCK, ...: OpenImageIO's reader
    d.cinfo.out_color_space = grey ? JCS_GRAYSCALE : JCS_RGB;
    ImageHeader h;
    h.width = int(d.cinfo.image_width);
    h.height = int(d.cinfo.image_height);
    h.nchannels = grey ? 1 : 3;
    const PixelDest dst = accept(ctx, h);
    // RGBA codes: libjpeg-turbo's extended colour space, the same conversion and upsampling as
    // JCS_RGB (grey copied to R, G, B) with a fourth byte of 255.
    if (dst.rgba_codes) d.cinfo.out_color_space = JCS_EXT_RGBA;
    if (!decompress(d, dst)) throw Error(where + ": cannot be decoded: " + d.err.message);
    return true;
}

}  // namespace aq
