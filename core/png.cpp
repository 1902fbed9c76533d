// core/png.cpp — see png.h.
#include "core/png.h"

#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include <isa-l/igzip_lib.h>
#include <libdeflate.h>
#include <png.h>

#include "core/io.h"
#include "core/unorm8.h"

namespace aq {

namespace {

constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
//! PNG colour types by channel count (specification 11.2.2): grey (1), RGB (3).
constexpr unsigned char kColourType[4] = {0, 0, 0, 2};
//! The chunks that go with sRGB (specification 11.3.3.5): gamma 1/2.2 and the sRGB primaries and
//! white point (D65), each times 100000.
constexpr std::uint32_t kSrgbGamma = 45455;
constexpr std::uint32_t kSrgbChromaticities[8] = {31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000};
constexpr unsigned char kSrgbIntentPerceptual = 0;
//! A chunk's data is at most 2^31 - 1 bytes (specification 5.3).
constexpr std::size_t kMaxChunkBytes = 0x7fffffffu;

//! A big-endian 32-bit value (PNG's byte order), stored at p or appended to out.
void store32(unsigned char* p, std::uint32_t v) {
    p[0] = static_cast<unsigned char>(v >> 24);
    p[1] = static_cast<unsigned char>(v >> 16);
    p[2] = static_cast<unsigned char>(v >> 8);
    p[3] = static_cast<unsigned char>(v);
}

void put32(std::vector<unsigned char>& out, std::uint32_t v) {
    unsigned char b[4];
    store32(b, v);
    out.insert(out.end(), b, b + 4);
}

//! Appends the CRC of the chunk that starts (at its length field) at `start`.
void finish_chunk(std::vector<unsigned char>& out, std::size_t start) {
    const unsigned char* type = out.data() + start + 4;
    put32(out, libdeflate_crc32(0, type, out.size() - start - 4));
}

void chunk(std::vector<unsigned char>& out, const char type[4], const unsigned char* data, std::size_t n) {
    const std::size_t start = out.size();
    put32(out, static_cast<std::uint32_t>(n));
    out.insert(out.end(), type, type + 4);
    if (n) out.insert(out.end(), data, data + n);
    finish_chunk(out, start);
}

void text_chunk(std::vector<unsigned char>& out, const std::string& key, const std::string& text) {
    if (text.find('\0') != std::string::npos) throw Error("PNG: a text chunk cannot hold a NUL byte");
    bool ascii = true;
    for (unsigned char ch : text) ascii = ascii && ch < 0x80;
    std::string d = key;
    d.push_back('\0');
    // iTXt (UTF-8): compression flag 0, method 0, empty language tag and translated keyword.
    if (!ascii) d.append(4, '\0');
    d += text;
    if (d.size() > kMaxChunkBytes) throw Error("PNG: the description is too long for a text chunk");
    chunk(out, ascii ? "tEXt" : "iTXt", reinterpret_cast<const unsigned char*>(d.data()), d.size());
}

struct FreeCompressor {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

//! Compression::None: libdeflate's level 0 (stored blocks), one compressor per thread, kept.
std::size_t zlib_stored(const unsigned char* in, std::size_t n, unsigned char* out, std::size_t cap) {
    thread_local std::unique_ptr<libdeflate_compressor, FreeCompressor> c;
    if (!c) c.reset(libdeflate_alloc_compressor(0));
    if (!c) throw Error("PNG: libdeflate could not allocate a compressor");
    return libdeflate_zlib_compress(c.get(), in, n, out, cap);
}

//! Compression::Fast: ISA-L's one-shot deflate at kPngIsalLevel into a zlib stream; its level
//! buffer (the hash table and the pending tokens, ISA-L's default size for the level) is kept per
//! thread. Returns the stream's size, 0 if it did not fit in `cap`.
std::size_t zlib_fast(const unsigned char* in, std::size_t n, unsigned char* out, std::size_t cap) {
    static_assert(kPngIsalLevel == 2, "the level buffer below is level 2's");
    thread_local std::vector<std::uint8_t> level_buf(ISAL_DEF_LVL2_DEFAULT);
    isal_zstream s;
    isal_deflate_stateless_init(&s);
    s.level = kPngIsalLevel;
    s.level_buf = level_buf.data();
    s.level_buf_size = static_cast<std::uint32_t>(level_buf.size());
    s.gzip_flag = IGZIP_ZLIB;
    s.end_of_stream = 1;
    s.flush = NO_FLUSH;
    s.next_in = const_cast<std::uint8_t*>(in);  // ISA-L's field is not const; it only reads the input
    s.avail_in = static_cast<std::uint32_t>(n);
    s.next_out = out;
    s.avail_out = static_cast<std::uint32_t>(cap);
    if (isal_deflate_stateless(&s) != COMP_OK) return 0;
    return s.total_out;
}

//! An upper bound of either encoder's zlib stream of n bytes: both fall back to stored blocks
//! (at most 65,535 bytes each behind a 5-byte header) where compressing would expand the data;
//! the zlib header and Adler-32 trailer (6 bytes) and ISA-L's largest block header
//! (ISAL_DEF_MAX_HDR_SIZE) come on top.
std::size_t zlib_bound(std::size_t n) { return n + 5 * (n / 65535 + 1) + 6 + ISAL_DEF_MAX_HDR_SIZE; }

}  // namespace

void encode_png(const ImageF& img, const std::string& description, std::vector<unsigned char>& out,
                std::vector<unsigned char>& rows, bool stored, bool drop_alpha) {
    const int w = img.width(), h = img.height(), c = drop_alpha ? 3 : img.channels();
    if (drop_alpha ? img.channels() != 4 || img.empty() : img.empty() || !png_encodes(c))
        throw Error(drop_alpha ? "PNG: dropping alpha needs a non-empty RGBA image" : "PNG: needs a non-empty grey or RGB image");
    // The rows as the zlib stream holds them: a filter-type byte (0, none), then the 8-bit values.
    const std::size_t row_values = std::size_t(w) * std::size_t(c);
    rows.resize((row_values + 1) * std::size_t(h));  // every byte is written below
    const float* p = img.data();
    for (int y = 0; y < h; ++y) {
        unsigned char* r = rows.data() + std::size_t(y) * (row_values + 1);
        r[0] = 0;
        if (drop_alpha) to_unorm8_rgb_n(p + 4 * std::size_t(y) * std::size_t(w), r + 1, std::size_t(w));
        else to_unorm8_n(p + std::size_t(y) * row_values, r + 1, row_values);
    }

    out.assign(kSignature, kSignature + sizeof kSignature);
    unsigned char ihdr[13];
    store32(ihdr, std::uint32_t(w));
    store32(ihdr + 4, std::uint32_t(h));
    ihdr[8] = 8;  // bit depth
    ihdr[9] = kColourType[c];
    ihdr[10] = ihdr[11] = ihdr[12] = 0;  // deflate, adaptive filtering (type 0 used), no interlace
    chunk(out, "IHDR", ihdr, sizeof ihdr);
    unsigned char gama[4];
    store32(gama, kSrgbGamma);
    chunk(out, "gAMA", gama, 4);
    chunk(out, "sRGB", &kSrgbIntentPerceptual, 1);
    unsigned char chrm[32];
    for (int i = 0; i < 8; ++i) store32(chrm + 4 * i, kSrgbChromaticities[i]);
    chunk(out, "cHRM", chrm, sizeof chrm);
    if (!description.empty()) text_chunk(out, "Description", description);

    const std::size_t bound = zlib_bound(rows.size());
    if (bound > kMaxChunkBytes) throw Error("PNG: the image is too large for one IDAT chunk");
    const std::size_t start = out.size();
    out.resize(start + 8 + bound);
    std::memcpy(out.data() + start + 4, "IDAT", 4);
    unsigned char* const z = out.data() + start + 8;
    const std::size_t n = stored ? zlib_stored(rows.data(), rows.size(), z, bound) : zlib_fast(rows.data(), rows.size(), z, bound);
    if (n == 0) throw Error("PNG: the deflate encoder could not compress the rows");
    out.resize(start + 8 + n);
    store32(out.data() + start, std::uint32_t(n));
    finish_chunk(out, start);
    chunk(out, "IEND", nullptr, 0);
}

namespace {

//! libpng's read state over a memory buffer. libpng reports a fatal error through the error
//! function, which must not return: png_longjmp to the setjmp of the function that called libpng.
//! Those functions (read_info, read_rows) hold no object with a destructor, so the jump skips
//! none; the structs are destroyed by ~PngReader in the caller, whatever happened.
struct PngReader {
    png_structp png = nullptr;
    png_infop info = nullptr;
    const unsigned char* bytes = nullptr;
    std::size_t size = 0, pos = 0;
    PngReader() = default;
    PngReader(const PngReader&) = delete;
    PngReader& operator=(const PngReader&) = delete;
    ~PngReader() {
        if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    }
};

void read_from_memory(png_structp p, png_bytep out, std::size_t n) {
    auto* r = static_cast<PngReader*>(png_get_io_ptr(p));
    if (n > r->size - r->pos) png_error(p, "truncated");
    std::memcpy(out, r->bytes + r->pos, n);
    r->pos += n;
}

[[noreturn]] void on_png_error(png_structp p, png_const_charp) { png_longjmp(p, 1); }
void on_png_warning(png_structp, png_const_charp) {}  // not printed; OpenImageIO's reader ignores them too

struct PngInfo {
    png_uint_32 width = 0, height = 0;
    int depth = 0, colour = 0;
    bool trns = false;
};

bool read_info(PngReader& r, PngInfo& i) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_set_read_fn(r.png, &r, read_from_memory);
    png_read_info(r.png, r.info);
    png_get_IHDR(r.png, r.info, &i.width, &i.height, &i.depth, &i.colour, nullptr, nullptr, nullptr);
    i.trns = png_get_valid(r.png, r.info, PNG_INFO_tRNS) != 0;
    return true;
}

//! A palette file's indices expanded to 8-bit RGB, and its tRNS chunk to an alpha channel.
bool palette_expansion(PngReader& r, bool trns) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_set_palette_to_rgb(r.png);
    if (trns) png_set_tRNS_to_alpha(r.png);
    return true;
}

//! libpng's expansion of `channels` 8-bit channels (palettes already expanded) to RGBA: grey
//! copied to R, G and B, alpha 255 where the file has none (PixelDest::rgba_codes).
bool rgba_expansion(PngReader& r, int channels) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    if (channels <= 2) png_set_gray_to_rgb(r.png);
    if (channels == 1 || channels == 3) png_set_filler(r.png, 0xFF, PNG_FILLER_AFTER);
    return true;
}

//! Every row (Adam7 passes combined by libpng) into rows[y], then the end of the file.
bool read_rows(PngReader& r, png_bytep* rows) {
    if (setjmp(png_jmpbuf(r.png))) return false;
    png_set_interlace_handling(r.png);
    png_read_update_info(r.png, r.info);
    png_read_image(r.png, rows);
    png_read_end(r.png, nullptr);
    return true;
}

}  // namespace

bool decode_png(const unsigned char* bytes, std::size_t size, AcceptHeader accept, void* ctx) {
    PngReader r;
    r.bytes = bytes;
    r.size = size;
    r.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, on_png_error, on_png_warning);
    if (!r.png) return false;
    r.info = png_create_info_struct(r.png);
    if (!r.info) return false;
    PngInfo i;
    if (!read_info(r, i)) return false;
    int channels = 0;
    switch (i.colour) {
        case PNG_COLOR_TYPE_GRAY: channels = 1; break;
        case PNG_COLOR_TYPE_GRAY_ALPHA: channels = 2; break;
        case PNG_COLOR_TYPE_RGB: channels = 3; break;
        case PNG_COLOR_TYPE_RGB_ALPHA: channels = 4; break;
        case PNG_COLOR_TYPE_PALETTE: channels = i.trns ? 4 : 3; break;  // expanded, as OpenImageIO does
        default: return false;
    }
    const bool palette = i.colour == PNG_COLOR_TYPE_PALETTE;
    if ((!palette && (i.depth != 8 || i.trns)) || (palette && !palette_expansion(r, i.trns))) return false;
    // png_read_info refused sizes of 0 or above libpng's user limits (10^6 by default): they fit in int.
    ImageHeader h;
    h.width = int(i.width);
    h.height = int(i.height);
    h.nchannels = channels;
    const PixelDest dst = accept(ctx, h);  // checks the size (docs/limits.md) before anything is allocated
    const bool rgba = dst.rgba_codes != nullptr;
    if (rgba && !rgba_expansion(r, channels)) return false;
    const std::size_t row_values = std::size_t(i.width) * std::size_t(rgba ? 4 : h.nchannels);
    std::vector<unsigned char> codes(rgba ? 0 : row_values * std::size_t(i.height));
    unsigned char* const out = rgba ? dst.rgba_codes : codes.data();
    std::vector<png_bytep> rows(std::size_t(i.height));
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = out + y * row_values;
    if (!read_rows(r, rows.data())) return false;
    const float* const unorm8 = unorm8_floats();
    for (std::size_t k = 0; k < codes.size(); ++k) dst.values[k] = unorm8[codes[k]];
    return true;
}

}  // namespace aq
