// core/io.cpp — decoding with header checks (OpenImageIO's readers, through core/oiio.h); encoding
// to memory and crash-safe writes.
#include "core/io.h"

#include "core/hash.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <vector>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "core/input.h"
#include "core/jpeg.h"
#include "core/oiio.h"
#include "core/png.h"

namespace aq {
namespace fs = std::filesystem;

void ensure_directory(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw Error("cannot create folder '" + dir + "': " + (ec ? ec.message() : "not a folder"));
}

std::string safe_file_name(const std::string& name) {
    std::string s = name;
    for (char& c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
    return s;
}

// --- reading ---------------------------------------------------------------------------------

std::string lower_extension(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

namespace {

//! The formats read (docs/limits.md "Image formats"): each decoder is attack surface reached by
//! user and third-party files, so only the ones the project documents are enabled. Keyed by the
//! extension that selects OpenImageIO's reader, with the reader's format_name(). BMP was read
//! until CI's fuzz runs found two memory errors in OpenImageIO 2.4's BMP reader within minutes
//! (fuzz/README.md findings 6 and 7); BMP files are refused like GIF (BMP output is still written).
//! max_pixels_per_byte: the densest the format's own coding can be (docs/limits.md). TGA's only
//! compression is run-length packets of at most 128 pixels in 1 + bytes-per-pixel >= 2 bytes, so no
//! valid TGA holds more than 64 pixels per byte; a header announcing more is refused before a
//! reader allocates the image (a 1,433-byte TGA announcing 2835 x 11653 cost 1.06 s and 647 MB:
//! fuzz/README.md finding 9). The others use kMaxPixelsPerEncodedByte.
struct ReadableFormat {
    const char* extension;
    const char* oiio_format;
    long max_pixels_per_byte = kMaxPixelsPerEncodedByte;
};
constexpr long kTgaMaxPixelsPerByte = 64;
constexpr ReadableFormat kReadableFormats[] = {
    {".png", "png"},   {".jpg", "jpeg"},  {".jpeg", "jpeg"}, {".exr", "openexr"}, {".tif", "tiff"},
    {".tiff", "tiff"}, {".hdr", "hdr"},   {".tga", "targa", kTgaMaxPixelsPerByte},
};

const ReadableFormat* readable_format(const std::string& extension) {
    for (const ReadableFormat& f : kReadableFormats)
        if (extension == f.extension) return &f;
    return nullptr;
}

//! The format by magic bytes where they are unambiguous, else by the name's extension.
std::string format_extension_for(const unsigned char* b, std::size_t n, const std::string& name) {
    if (n >= 8 && std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0) return ".png";
    if (n >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return ".jpg";
    if (n >= 4 && std::memcmp(b, "\x76\x2f\x31\x01", 4) == 0) return ".exr";
    if (n >= 4 && std::memcmp(b, "DDS ", 4) == 0) return ".dds";
    if (n >= 2 && b[0] == 'B' && b[1] == 'M') return ".bmp";
    if (n >= 4 && std::memcmp(b, "GIF8", 4) == 0) return ".gif";
    if (n >= 4 && (std::memcmp(b, "II*\0", 4) == 0 || std::memcmp(b, "MM\0*", 4) == 0)) return ".tif";
    if (n >= 2 && b[0] == '#' && b[1] == '?') return ".hdr";
    const std::string ext = lower_extension(name);
    return ext.empty() ? std::string(".png") : ext;
}

//! The size limits and the decompression-bomb rule, for a header's width and height.
void check_dimensions(int width, int height, std::size_t encoded_bytes, const std::string& where,
                      long max_pixels_per_byte = kMaxPixelsPerEncodedByte) {
    check_image_size(width, height, where);
    // No format we read stores more than kMaxPixelsPerEncodedByte pixels per byte (docs/limits.md):
    // a header announcing more is a decompression bomb that would cost its full size in memory
    // before the reader reached the end of the data (a 21-byte TGA announcing 2835 x 11775 took
    // 0.97 s and 651 MB; found by fuzzing).
    const double pixels = double(width) * double(height);
    if (pixels > double(encoded_bytes) * double(max_pixels_per_byte))
        throw Error(where + ": " + std::to_string(width) + "x" + std::to_string(height) + " pixels in " +
                    std::to_string(encoded_bytes) + " bytes is more than the format can hold (" +
                    std::to_string(max_pixels_per_byte) + " pixels per byte; docs/limits.md)");
}

//! Width and height from a JPEG's frame header (SOFn), found by walking the marker segments
//! before the first scan; false when there is none (OpenImageIO then reports the damage).
//! OpenImageIO 2.4's JPEG reader allocates libjpeg's whole-image buffers inside open(), before its
//! spec can be checked: a 408-byte progressive JPEG announcing 37318 x 11143 cost 2.5 GB and 3 s
//! before being refused (fuzz/README.md finding 8). So the frame size is checked from the bytes.
bool jpeg_frame_size(const unsigned char* b, std::size_t n, int* width, int* height) {
    std::size_t i = 2;  // after SOI
    while (i + 4 <= n) {
        if (b[i] != 0xFF) {  // libjpeg skips extraneous bytes up to the next marker; so do we
            ++i;
            continue;
        }
        const unsigned char m = b[i + 1];
        if (m == 0xFF) {  // fill byte
            ++i;
            continue;
        }
        if (m == 0x01 || (m >= 0xD0 && m <= 0xD8)) {  // TEM, RSTn, SOI: no length
            i += 2;
            continue;
        }
        if (m == 0xD9 || m == 0xDA) return false;  // EOI or a scan before any frame header
        const std::size_t len = (std::size_t(b[i + 2]) << 8) | b[i + 3];
        const bool sof = m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC;
        if (sof) {
            if (i + 9 > n) return false;
            *height = (int(b[i + 5]) << 8) | b[i + 6];
            *width = (int(b[i + 7]) << 8) | b[i + 8];
            return true;
        }
        if (len < 2) return false;
        i += 2 + len;
    }
    return false;
}

//! Refuses what we do not decode, from the header alone (before any pixel is read).
void check_header(const ImageHeader& h, std::size_t encoded_bytes, const std::string& where,
                  DecodeBudget* budget, long max_pixels_per_byte) {
    if (h.depth > 1)
        throw Error(where + ": a volume image (depth " + std::to_string(h.depth) + "); only 2D images are read");
    if (h.deep) throw Error(where + ": deep image data is not supported");
    if (h.nchannels < 1 || h.nchannels > kMaxImageChannels)
        throw Error(where + ": " + std::to_string(h.nchannels) + " channels (1.." + std::to_string(kMaxImageChannels) +
                    " are read)");
    check_dimensions(h.width, h.height, encoded_bytes, where, max_pixels_per_byte);
    if (budget) {
        const std::size_t need = std::size_t(h.width) * std::size_t(h.height) * 4 * sizeof(float);
        if (need > budget->bytes_left)
            throw BudgetError(where + ": decoding " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                        " would exceed the budget for " + budget->what + " (" + std::to_string(budget->bytes_left) +
                        " bytes left; docs/limits.md)");
        budget->bytes_left -= need;
    }
}

//! What accept_header needs, and the image it allocates.
struct DecodeTarget {
    std::size_t encoded_bytes;
    const std::string& where;
    DecodeBudget* budget;
    long max_pixels_per_byte;
    ImageF img;
    //! Zero the image first: OpenImageIO's readers (a reader reporting success on damaged data
    //! must not leave unspecified values); core/jpeg.h writes every value itself.
    bool zero_first = true;
    //! Ask for RGBA codes instead of values (decode_image_or_codes; core/png.h, core/jpeg.h only).
    RgbaCodes* codes = nullptr;
};

//! Every decoder's header callback (core/image_header.h): checks the header, then allocates the image.
PixelDest accept_header(void* ctx, const ImageHeader& h) {
    auto& t = *static_cast<DecodeTarget*>(ctx);
    check_header(h, t.encoded_bytes, t.where, t.budget, t.max_pixels_per_byte);
    if (t.codes) {
        t.codes->width = h.width;
        t.codes->height = h.height;
        t.codes->file_channels = h.nchannels;
        t.codes->codes.resize(std::size_t(h.width) * std::size_t(h.height) * 4);
        return {nullptr, t.codes->codes.data()};
    }
    const int c = std::min(h.nchannels, 4);
    t.img = t.zero_first ? ImageF(h.width, h.height, c) : ImageF(h.width, h.height, c, kUninitialized);
    return {t.img.data(), nullptr};
}

}  // namespace

//! decode_image without the exception translation below; with `codes`, an 8-bit PNG or JPEG that
//! core/png.h or core/jpeg.h reads goes there (the ImageF returned is empty).
static ImageF decode_image_oiio(const unsigned char* bytes, std::size_t size, const std::string& name,
                                DecodeBudget* budget, RgbaCodes* codes = nullptr) {
    const std::string where = "image '" + name + "'";
    if (!bytes || size == 0) throw Error(where + ": no data");
    const std::string ext = format_extension_for(bytes, size, name);
    const ReadableFormat* format = readable_format(ext);
    if (!format)
        throw Error(where + ": the '" + ext.substr(1) +
                    "' format is not read (PNG, JPEG, OpenEXR, TIFF, Radiance HDR and TGA are; docs/limits.md)");
    if (std::string(format->oiio_format) == "jpeg") {
        int w = 0, h = 0;
        if (jpeg_frame_size(bytes, size, &w, &h)) check_dimensions(w, h, size, where + " (JPEG frame header)");
        // Grey and colour JPEG (every paper) without OpenImageIO (core/jpeg.h); CMYK goes on below.
        DecodeTarget jpeg{size, where, budget, format->max_pixels_per_byte, {}, false, codes};
        if (decode_jpeg(bytes, size, where, accept_header, &jpeg)) return std::move(jpeg.img);
    }
    if (std::string(format->oiio_format) == "png") {
        // 8-bit grey and RGB PNG (glTF base-colour maps) without OpenImageIO (core/png.h); the
        // rest, and files libpng reports damaged, go on below with the budget as it was.
        const std::size_t budget_before = budget ? budget->bytes_left : 0;
        DecodeTarget png{size, where, budget, format->max_pixels_per_byte, {}, false, codes};
        if (decode_png(bytes, size, accept_header, &png)) return std::move(png.img);
        if (budget) budget->bytes_left = budget_before;
        if (codes) *codes = RgbaCodes{};
    }
    DecodeTarget target{size, where, budget, format->max_pixels_per_byte, {}, true};
    const std::string fake = "memory" + ext;
    const std::string e = oiio().decode(bytes, size, format->oiio_format, fake.c_str(), accept_header, &target);
    if (!e.empty()) throw Error(where + ": cannot be decoded: " + e);
    return std::move(target.img);
}

//! decode_image and decode_image_or_codes.
static ImageF decode_translated(const unsigned char* bytes, std::size_t size, const std::string& name,
                                DecodeBudget* budget, RgbaCodes* codes) {
    // OpenImageIO's readers can throw on corrupt headers (its GIF reader: std::length_error from
    // a 13-byte file, fuzz/README.md); every reader documents aq::Error only.
    try {
        return decode_image_oiio(bytes, size, name, budget, codes);
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error("image '" + name + "': cannot be decoded: out of memory");
    } catch (const std::exception& e) {
        throw Error("image '" + name + "': cannot be decoded: the decoder failed (" + std::string(e.what()) + ")");
    }
}

ImageF decode_image(const unsigned char* bytes, std::size_t size, const std::string& name, DecodeBudget* budget) {
    return decode_translated(bytes, size, name, budget, nullptr);
}

DecodedImage decode_image_or_codes(const unsigned char* bytes, std::size_t size, const std::string& name,
                                   DecodeBudget* budget) {
    DecodedImage d;
    d.values = decode_translated(bytes, size, name, budget, &d.codes);
    return d;
}

ImageF read_image(const std::string& path, DecodeBudget* budget) {
    const std::vector<unsigned char> bytes = read_input_file(path, kMaxImageFileBytes, "image");
    return decode_image(bytes.data(), bytes.size(), path, budget);
}

#ifdef __AVX2__
namespace {
//! to_unorm8 of eight values, as 32-bit integers in [0, 255].
inline __m256i unorm8_lanes(__m256 v) {
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f), k255 = _mm256_set1_ps(255.0f),
                 half = _mm256_set1_ps(0.5f);
    v = _mm256_max_ps(v, zero);  // maxps returns its second operand when either is NaN: NaN -> 0
    v = _mm256_min_ps(v, one);
    const __m256 x = _mm256_mul_ps(v, k255);
    const __m256i t = _mm256_cvttps_epi32(x);  // int(x): x is in [0, 255]
    const __m256 up = _mm256_cmp_ps(_mm256_sub_ps(x, _mm256_cvtepi32_ps(t)), half, _CMP_GE_OQ);
    return _mm256_sub_epi32(t, _mm256_castps_si256(up));  // + 1 where the mask is all ones
}
}  // namespace
#endif

void to_unorm8_n(const float* src, unsigned char* dst, std::size_t n) {
    std::size_t i = 0;
#ifdef __AVX2__
    for (; i + 8 <= n; i += 8) {
        const __m256i q = unorm8_lanes(_mm256_loadu_ps(src + i));
        const __m128i w = _mm_packus_epi32(_mm256_castsi256_si128(q), _mm256_extracti128_si256(q, 1));
        _mm_storel_epi64(reinterpret_cast<__m128i*>(dst + i), _mm_packus_epi16(w, w));
    }
#endif
    for (; i < n; ++i) dst[i] = to_unorm8(src[i]);
}

void to_unorm8_rgb_n(const float* rgba, unsigned char* rgb, std::size_t pixels) {
    std::size_t p = 0;
#ifdef __AVX2__
    // Eight pixels per step: the 32 codes packed to bytes (the packs interleave the 128-bit lanes:
    // dwords = pixels 0 2 4 6 | 1 3 5 7, put in order by one permute), then each lane's four
    // pixels without their alpha bytes, 12 bytes stored exactly (nothing written past the end).
    const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
    const __m256i drop_alpha =
        _mm256_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1, 0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1);
    for (; p + 8 <= pixels; p += 8) {
        const float* s = rgba + 4 * p;
        const __m256i a = _mm256_packus_epi32(unorm8_lanes(_mm256_loadu_ps(s)), unorm8_lanes(_mm256_loadu_ps(s + 8)));
        const __m256i b = _mm256_packus_epi32(unorm8_lanes(_mm256_loadu_ps(s + 16)), unorm8_lanes(_mm256_loadu_ps(s + 24)));
        const __m256i c = _mm256_shuffle_epi8(_mm256_permutevar8x32_epi32(_mm256_packus_epi16(a, b), order), drop_alpha);
        auto store12 = [](unsigned char* d, __m128i v) {  // bytes 0-11 of v
            _mm_storel_epi64(reinterpret_cast<__m128i*>(d), v);
            const int tail = _mm_cvtsi128_si32(_mm_srli_si128(v, 8));
            std::memcpy(d + 8, &tail, 4);
        };
        store12(rgb + 3 * p, _mm256_castsi256_si128(c));
        store12(rgb + 3 * p + 12, _mm256_extracti128_si256(c, 1));
    }
#endif
    for (; p < pixels; ++p)
        for (int c = 0; c < 3; ++c) rgb[3 * p + std::size_t(c)] = to_unorm8(rgba[4 * p + std::size_t(c)]);
}

// --- writing ---------------------------------------------------------------------------------

namespace {

constexpr const char* kTmpPrefix = ".aqtmp.";  //!< `.aqtmp.PID.N.NAME`: recognisable leftovers
constexpr const char* kLockPrefix = ".aqlock.";  //!< `.aqlock.NAME`: a WriteLock of NAME

// PNG: grey and RGB images (every stylised --out image) are encoded by core/png.h (libdeflate; its
// settings and their measurement are there). Images with alpha (--style none, some targets) and
// every other format go through OpenImageIO's writers (core/oiio_module.cpp, with their settings).

[[noreturn]] void fail_write(const std::string& path, const std::string& why) {
    throw Error("write '" + path + "': " + why);
}

//! Per-thread encoder scratch, kept between calls: an animation's writer thread encodes every
//! frame into the same pages instead of faulting ~13 MB of fresh ones per 1080p PNG frame (fresh
//! pages cost ~2 ms per MB on our VMs; docs/performance.md "Design decisions that hold").
//! Bounded: a buffer that grew past kKeptScratchBytes is released after the call instead of kept.
struct EncodeScratch {
    std::vector<unsigned char> quantised, encoded;
};
constexpr std::size_t kKeptScratchBytes = std::size_t(64) << 20;

EncodeScratch& encode_scratch() {
    thread_local EncodeScratch s;
    return s;
}

void trim_scratch(std::vector<unsigned char>& v) {
    if (v.capacity() > kKeptScratchBytes) std::vector<unsigned char>().swap(v);
}

//! Encodes img in the format of the extension into `buf`: grey and RGB PNG by core/png.h, every
//! other image by OpenImageIO's writer through a proxy; `q` is scratch for the 8-bit values (or a
//! PNG's rows). Both keep their capacity.
void encode_image(const std::string& path, const ImageF& img, const std::string& description,
                  std::vector<unsigned char>& buf, std::vector<unsigned char>& q, Compression compression,
                  bool drop_alpha = false) {
    const bool stored = compression == Compression::None;
    const std::string ext = lower_extension(path);
    if (ext.empty()) fail_write(path, "no file extension to choose a format");
    if (drop_alpha && img.channels() != 4) fail_write(path, "dropping alpha needs a 4-channel image");
    if (ext == ".png" && (drop_alpha || png_encodes(img.channels()))) {
        // 8-bit display images, sRGB-encoded in either working space (docs/look.md): the encoder
        // tags them so (sRGB chunk).
        try {
            encode_png(img, description, buf, q, stored, drop_alpha);
        } catch (const Error& e) {
            fail_write(path, e.what());
        }
        return;
    }
    if (drop_alpha) {  // other formats: through the RGB copy
        ImageF rgb;
        rgb_of(img, rgb);
        encode_image(path, rgb, description, buf, q, compression);
        return;
    }
    const bool eight_bit = (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp");
    oiio_module::EncodeRequest r;
    r.extension = ext;
    r.width = img.width();
    r.height = img.height();
    r.channels = img.channels();
    r.description = description;
    r.stored = stored;
    if (eight_bit) {
        q.resize(img.num_values());  // every value is written below
        to_unorm8_n(img.data(), q.data(), q.size());
        r.u8 = q.data();
    } else {
        r.f32 = img.data();
    }
    if (const std::string e = oiio().encode(r, buf); !e.empty()) fail_write(path, e);
    if (buf.empty()) fail_write(path, "the encoder produced no bytes");
}

bool write_all(int fd, const unsigned char* p, std::size_t n, int* err) {
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            *err = w < 0 ? errno : ENOSPC;
            return false;
        }
        p += w;
        n -= std::size_t(w);
    }
    return true;
}

std::atomic<unsigned> g_tmp_counter{0};

//! Files of at least this many bytes, and at most kKeptScratchBytes (the aligned copy is kept per
//! thread: larger files would hold that much memory), are written with O_DIRECT
//! (write_file_atomically).
constexpr std::size_t kDirectWriteBytes = std::size_t(1) << 20;
//! The block O_DIRECT transfers are aligned and sized to (a multiple of every logical block size
//! Linux file systems use).
constexpr std::size_t kDirectBlock = 4096;

//! Writes the n bytes at p to the empty file fd opened with O_DIRECT: through a 4096-aligned copy
//! (kept per thread), whole blocks, then truncated to n. False with *err when the file system
//! refused (the caller then writes through the page cache).
bool write_direct(int fd, const unsigned char* p, std::size_t n, int* err) {
    struct Aligned {
        void* p = nullptr;
        std::size_t size = 0;
        ~Aligned() { std::free(p); }
    };
    thread_local Aligned buf;
    const std::size_t padded = (n + kDirectBlock - 1) / kDirectBlock * kDirectBlock;
    if (buf.size < padded) {
        // A quarter more than asked: an animation's frames vary a little in size, and growing
        // by each new maximum would fault in fresh pages again and again.
        const std::size_t size = (padded + padded / 4 + kDirectBlock - 1) / kDirectBlock * kDirectBlock;
        std::free(buf.p);
        buf.p = nullptr, buf.size = 0;
        if (::posix_memalign(&buf.p, kDirectBlock, size) != 0) {
            buf.p = nullptr;
            *err = ENOMEM;
            return false;
        }
        buf.size = size;
    }
    unsigned char* b = static_cast<unsigned char*>(buf.p);
    std::memcpy(b, p, n);
    std::memset(b + n, 0, padded - n);
    if (!write_all(fd, b, padded, err)) return false;
    if (::ftruncate(fd, off_t(n)) != 0) {
        *err = errno;
        return false;
    }
    return true;
}

}  // namespace

int remove_stale_temporaries(const std::string& dir) {
    int removed = 0;
    std::error_code ec;
    for (fs::directory_iterator it(dir.empty() ? "." : dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string n = it->path().filename().string();
        if (n.rfind(kLockPrefix, 0) == 0) {  // a lock its holder left (killed): free to take, so removed
            const int fd = ::open(it->path().c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
            if (fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::unlink(it->path().c_str()) == 0) ++removed;
            if (fd >= 0) ::close(fd);
            continue;
        }
        if (n.rfind(kTmpPrefix, 0) != 0) continue;
        const std::size_t a = std::strlen(kTmpPrefix), b = n.find('.', a);
        if (b == std::string::npos) continue;
        long pid = 0;
        try {
            pid = std::stol(n.substr(a, b - a));
        } catch (...) {
            continue;
        }
        if (pid <= 0 || pid == long(::getpid())) continue;
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // still alive (or not ours to judge)
        std::error_code rm;
        if (fs::remove(it->path(), rm)) ++removed;
    }
    return removed;
}

namespace {

//! The file a destination path finally names: symbolic links followed (at most 40, as the kernel).
fs::path follow_links(const std::string& path) {
    fs::path p(path);
    std::error_code ec;
    for (int hops = 0; fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
        if (hops == 40) fail_write(path, "too many levels of symbolic links");
        const fs::path t = fs::read_symlink(p, ec);
        if (ec) fail_write(path, "cannot read the symbolic link: " + ec.message());
        p = t.is_absolute() ? t : p.parent_path() / t;
    }
    return p;
}

//! Writes into an existing character device or FIFO (e.g. /dev/null, a pipe a reader waits on)
//! instead of replacing it: opened without creating or truncating, non-blocking so that a FIFO
//! with no reader is refused instead of hanging.
void write_through(const std::string& path, const void* data, std::size_t size) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0)
        fail_write(path, errno == ENXIO ? std::string("is a FIFO with no reader") : std::string("cannot open: ") + std::strerror(errno));
    int err = 0;
    const int flags = ::fcntl(fd, F_GETFL);
    const bool ok = flags >= 0 && ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) == 0 &&
                    write_all(fd, static_cast<const unsigned char*>(data), size, &err);
    if (!ok) err = err ? err : errno;
    if (::close(fd) != 0 && ok) fail_write(path, std::string("close failed: ") + std::strerror(errno));
    if (!ok) fail_write(path, std::string("write failed: ") + std::strerror(err));
}

}  // namespace

PreparedFile& PreparedFile::operator=(PreparedFile&& o) noexcept {
    if (this != &o) {
        discard();
        path_ = std::move(o.path_), tmp_ = std::move(o.tmp_), dir_ = std::move(o.dir_);
        fd_ = o.fd_, named_ = o.named_;
        o.fd_ = -1, o.named_ = false;
    }
    return *this;
}

void PreparedFile::discard() noexcept {
    if (fd_ >= 0) ::close(fd_);
    if (named_) ::unlink(tmp_.c_str());
    fd_ = -1, named_ = false;
}

PreparedFile prepare_file(const std::string& requested, const void* data, std::size_t size) {
    // A symbolic link stays: the file it names is replaced. A character device or FIFO is written
    // through, never replaced (`--json /dev/null` must not put a regular file in place of the
    // device); any other special file is refused (docs/limits.md "Writing files").
    const std::string path = follow_links(requested).string();
    std::error_code ec;
    const fs::file_status kind = fs::status(path, ec);
    if (fs::is_character_file(kind) || fs::is_fifo(kind)) {
        if (is_input_of_run(path)) fail_write(path, "it is an input of this run; refusing to overwrite it");
        write_through(path, data, size);
        return {};  // nothing left to commit
    }
    if (fs::exists(kind) && !fs::is_regular_file(kind) && !fs::is_directory(kind))
        fail_write(path, "is a block device, socket or other special file; refusing to replace it");
    const fs::path dst(path);
    const fs::path dir = dst.has_parent_path() ? dst.parent_path() : fs::path(".");
    if (!fs::is_directory(dir, ec)) fail_write(path, "folder '" + dir.string() + "' does not exist");
    if (fs::is_directory(dst, ec)) fail_write(path, "is a folder");
    if (is_input_of_run(path)) fail_write(path, "it is an input of this run; refusing to overwrite it");
    remove_stale_temporaries(dir.string());

    // A temporary beside the destination (same file system, so rename is atomic). It exists without
    // a name (O_TMPFILE) while being written and until commit(), so a crash before then leaves
    // nothing.
    PreparedFile f;
    f.path_ = path;
    f.dir_ = dir.string();
    f.tmp_ = (dir / (std::string(kTmpPrefix) + std::to_string(::getpid()) + "." + std::to_string(g_tmp_counter++) + "." +
                     dst.filename().string()))
                 .string();
    f.fd_ = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (f.fd_ < 0) {
        f.fd_ = ::open(f.tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (f.fd_ < 0) fail_write(path, std::string("cannot create a temporary file in '") + dir.string() + "': " + std::strerror(errno));
        f.named_ = true;
    }
    auto abandon = [&](const std::string& why) {
        f.discard();
        fail_write(path, why + "; the previous file, if any, is unchanged");
    };
    const int fd = f.fd_;
    int err = 0;
    // Large files (an animation's frames) bypass the page cache: copying them into fresh
    // page-cache pages cost ~2 ms of CPU per MB on our VMs, against ~0.3 ms per MB this way; the
    // file is flushed below either way. Where the file system refuses O_DIRECT, the ordinary write.
    bool written = false;
    if (size >= kDirectWriteBytes && size <= kKeptScratchBytes) {
        const int flags = ::fcntl(fd, F_GETFL);
        if (flags >= 0 && ::fcntl(fd, F_SETFL, flags | O_DIRECT) == 0) {
            written = write_direct(fd, static_cast<const unsigned char*>(data), size, &err);
            if (::fcntl(fd, F_SETFL, flags) != 0) abandon(std::string("cannot clear O_DIRECT: ") + std::strerror(errno));
            if (!written && (::ftruncate(fd, 0) != 0 || ::lseek(fd, 0, SEEK_SET) != 0))
                abandon(std::string("write failed: ") + std::strerror(err));
        }
    }
    if (!written && !write_all(fd, static_cast<const unsigned char*>(data), size, &err))
        abandon(std::string("write failed: ") + std::strerror(err));
    if (::fsync(fd) != 0) abandon(std::string("flush (fsync) failed: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd, &st) != 0 || std::size_t(st.st_size) != size)
        abandon("the written file has " + std::to_string(st.st_size) + " bytes, expected " + std::to_string(size));
    return f;
}

void PreparedFile::commit() {
    if (fd_ < 0 && !named_) return;  // written through, or already committed
    if (!named_) {
        const std::string proc = "/proc/self/fd/" + std::to_string(fd_);
        if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, tmp_.c_str(), AT_SYMLINK_FOLLOW) != 0) {
            const int e = errno;
            discard();
            fail_write(path_, std::string("cannot name the temporary file: ") + std::strerror(e) + "; the previous file, if any, is unchanged");
        }
        named_ = true;
    }
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) {
        const int e = errno;
        discard();
        fail_write(path_, std::string("close failed: ") + std::strerror(e) + "; the previous file, if any, is unchanged");
    }
    if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
        const int e = errno;
        discard();
        fail_write(path_, std::string("cannot rename the finished file into place: ") + std::strerror(e));
    }
    named_ = false;
    // Make the rename itself durable.
    if (const int dfd = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
}

void write_file_atomically(const std::string& path, const void* data, std::size_t size) {
    prepare_file(path, data, size).commit();
}

// --- WriteLock ----------------------------------------------------------------------------------

WriteLock::WriteLock(const std::string& path) {
    const fs::path p(path);
    lock_path_ = ((p.has_parent_path() ? p.parent_path() : fs::path(".")) / (std::string(kLockPrefix) + p.filename().string())).string();
    for (int attempt = 0; attempt < 8; ++attempt) {
        fd_ = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
        if (fd_ < 0) fail_write(path, std::string("cannot create its lock '") + lock_path_ + "': " + std::strerror(errno));
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            const int e = errno;
            ::close(fd_);
            fd_ = -1;
            if (e == EWOULDBLOCK)
                fail_write(path, "another process is writing it and the files that go with it (its lock '" + lock_path_ +
                                     "' is held): two runs must not write one output at once");
            fail_write(path, std::string("cannot lock '") + lock_path_ + "': " + std::strerror(e));
        }
        // The lock is ours unless its holder removed the file between our open and our flock.
        struct stat a {}, b {};
        if (::fstat(fd_, &a) == 0 && ::stat(lock_path_.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino) return;
        ::close(fd_);
        fd_ = -1;
    }
    fail_write(path, "cannot take its lock '" + lock_path_ + "': it keeps being replaced");
}

WriteLock::~WriteLock() {
    if (fd_ < 0) return;
    ::unlink(lock_path_.c_str());  // while still held: a waiting process sees another inode and retries
    ::close(fd_);
}

PreparedFile prepare_image(const std::string& path, const ImageF& img, std::string* sha256, const std::string& description,
                           Compression compression, bool drop_alpha) {
    if (img.empty()) fail_write(path, "the image is empty");
    const fs::path dst(path);
    const fs::path dir = dst.has_parent_path() ? dst.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) fail_write(path, "folder '" + dir.string() + "' does not exist");
    if (is_input_of_run(path)) fail_write(path, "it is an input of this run; refusing to overwrite it");
    EncodeScratch& scratch = encode_scratch();
    struct Trim {  // on every exit, a failed encode included
        EncodeScratch& s;
        ~Trim() {
            trim_scratch(s.quantised);
            trim_scratch(s.encoded);
        }
    } trim{scratch};
    encode_image(path, img, description, scratch.encoded, scratch.quantised, compression, drop_alpha);
    PreparedFile f = prepare_file(path, scratch.encoded.data(), scratch.encoded.size());
    if (sha256) *sha256 = sha256_hex(scratch.encoded.data(), scratch.encoded.size());
    return f;
}

std::string write_image(const std::string& path, const ImageF& img, const std::string& description,
                        Compression compression, bool drop_alpha) {
    std::string sha;
    prepare_image(path, img, &sha, description, compression, drop_alpha).commit();
    return sha;
}

}  // namespace aq
