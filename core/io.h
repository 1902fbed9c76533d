// core/io.h — image files through OpenImageIO: checked before decoding, written so that no failure
// can lose data.
//
// PNG: 8-bit, values clamped to [0,1] and rounded (no transfer curve is applied: the watercolor
// maths works on display-referred colour, as MNPR does). EXR: 32-bit float, all channels.
//
// Reading: the file goes through core/input.h (regular files only, size-capped), then its header
// is checked before any pixel is decoded: 2D only (no volume/deep data), 1..kMaxImageChannels
// channels, a size within core/image.h's limits, and, when a DecodeBudget is given, the decoded
// bytes within the budget.
//
// Writing: the file is encoded in memory, written to an unnamed temporary file in the destination
// folder (O_TMPFILE; a named `.aqtmp.PID.*` file where the file system has none), fsync'ed and
// checked (every write's result, the file's size), then linked and renamed over the destination.
// On any failure the temporary is removed, the old file is untouched and aq::Error names the file
// and the reason. A path that is an input of the run (core/input.h) is refused. docs/limits.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/image.h"

namespace aq {

inline constexpr int kMaxImageChannels = 64;  //!< more channels than this is not an image we read
//! The densest encoding we read: deflate's 1032:1 on 1-bit PNG rows is 8256 pixels per byte, a
//! CCITT G4 TIFF of a blank page ~14,000; twice that leaves room. An image whose header announces
//! more pixels than file bytes x this is refused before decoding (docs/limits.md).
inline constexpr long kMaxPixelsPerEncodedByte = 32768;

//! Raised when a decode would exceed its DecodeBudget (a hard error, not a missing texture).
struct BudgetError : Error {
    using Error::Error;
};

//! A total for decoded image bytes shared by several reads (one scene's textures).
struct DecodeBudget {
    std::size_t bytes_left = 0;
    std::string what;  //!< named in the error, e.g. "the scene's textures (1 GiB)"
};

//! How image files are compressed (lossless either way: the same pixels; only file size and
//! writing time differ; measured in docs/performance.md "Writing files").
enum class Compression {
    //! PNG: ISA-L deflate level 2 (core/png.h; zlib level 1 through OpenImageIO for alpha); EXR: PIZ
    Fast,
    None,  //!< PNG: stored deflate blocks (~2.2x larger WC18 frames); EXR: uncompressed
};
//! The name of a Compression on the command line and in manifests: "fast", "none".
inline const char* compression_name(Compression c) { return c == Compression::None ? "none" : "fast"; }
//! The Compression called `name`; false (c untouched) for any other name.
inline bool compression_from_name(const std::string& name, Compression& c) {
    if (name != "fast" && name != "none") return false;
    c = name == "none" ? Compression::None : Compression::Fast;
    return true;
}

//! Writes img to path; the format follows the extension (.png, .exr, .tif, .jpg ...). A non-empty
//! `description` is embedded as the standard ImageDescription attribute (PNG tEXt "Description",
//! EXR/TIFF header; the provenance manifest, app/manifest.h). `compression` applies to PNG and EXR.
//! Returns the SHA-256 (hex) of the bytes written. `drop_alpha`: img has 4 channels and the file
//! gets the first three (RGB), the bytes of writing that RGB copy (a PNG is encoded straight from
//! the RGBA values). Throws aq::Error.
std::string write_image(const std::string& path, const ImageF& img, const std::string& description = {},
                        Compression compression = Compression::Fast, bool drop_alpha = false);

//! The 8-bit code of a display value as PNG/JPEG files store it: NaN -> 0, clamped to [0, 1], then
//! std::lround(v * 255) (round half away from zero), computed as trunc + (fraction >= 1/2), which
//! is exact for these values (the fraction of a float below 256 is representable) and vectorises.
inline unsigned char to_unorm8(float v) {
    v = v == v ? (v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v)) : 0.0f;
    const float x = v * 255.0f;
    const int i = int(x);
    return static_cast<unsigned char>(i + int(x - float(i) >= 0.5f));
}

//! dst[i] = to_unorm8(src[i]) for i < n, eight values per AVX2 step where the build has AVX2 (the
//! scalar function's loop does not vectorise: GCC keeps its float compares as branches because they
//! may trap). Same bytes either way (tests/core/io_test.cpp).
void to_unorm8_n(const float* src, unsigned char* dst, std::size_t n);

//! The RGB bytes of RGBA pixels: rgb[3 p + c] = to_unorm8(rgba[4 p + c]) for c < 3, p < pixels
//! (alpha left out; eight pixels per AVX2 step). Same bytes as to_unorm8 (tests/core/io_test.cpp).
void to_unorm8_rgb_n(const float* rgba, unsigned char* rgb, std::size_t pixels);

//! A file written and flushed beside its destination but not yet in place: the first half of
//! write_file_atomically, so a set of files (a frame's targets, image and manifest) can be written
//! whole before any of them replaces the old set (app/frame_writer.h). The temporary has no name
//! (O_TMPFILE) until commit(), which names it and renames it over the destination; destroyed
//! uncommitted, it leaves the destination as it was. A character device or FIFO destination is
//! written through by prepare_file itself (commit does nothing).
class PreparedFile {
public:
    PreparedFile() = default;
    PreparedFile(PreparedFile&& o) noexcept { *this = std::move(o); }
    PreparedFile& operator=(PreparedFile&& o) noexcept;
    ~PreparedFile() { discard(); }
    //! Puts the file in place (atomic rename, folder fsync'ed). Throws aq::Error.
    void commit();

private:
    friend PreparedFile prepare_file(const std::string& path, const void* data, std::size_t size);
    void discard() noexcept;
    std::string path_, tmp_, dir_;
    int fd_ = -1;
    bool named_ = false;
};

//! Writes bytes beside `path` (every check and flush of write_file_atomically) for a later commit().
PreparedFile prepare_file(const std::string& path, const void* data, std::size_t size);

//! write_image's first half: encoded, written and flushed, not yet in place; *sha256 (when given)
//! receives the SHA-256 of the bytes.
PreparedFile prepare_image(const std::string& path, const ImageF& img, std::string* sha256,
                           const std::string& description = {}, Compression compression = Compression::Fast,
                           bool drop_alpha = false);

//! Writes bytes to path with the same guarantees as write_image (sidecar files, reports).
void write_file_atomically(const std::string& path, const void* data, std::size_t size);

//! Held while one writer writes `path` and the files that go with it: `.aqlock.NAME` beside it,
//! flock'ed; a second process asking for the same lock gets aq::Error at once (two runs writing
//! one --out). Removed when released; a lock whose holder was killed is free (the kernel drops
//! flocks) and removed by the next write into its folder (remove_stale_temporaries).
class WriteLock {
public:
    explicit WriteLock(const std::string& path);
    ~WriteLock();
    WriteLock(const WriteLock&) = delete;
    WriteLock& operator=(const WriteLock&) = delete;

private:
    std::string lock_path_;
    int fd_ = -1;
};

//! Reads an image file as float with its stored values, keeping up to 4 channels. Throws aq::Error.
ImageF read_image(const std::string& path, DecodeBudget* budget = nullptr);

//! Decodes an encoded image held in memory (PNG, JPEG, EXR, ...); `name` is used in messages and
//! to guess the format when the magic bytes do not say. Same checks as read_image.
ImageF decode_image(const unsigned char* bytes, std::size_t size, const std::string& name,
                    DecodeBudget* budget = nullptr);

//! An 8-bit image as its file stores it, widened to RGBA (grey copied to R, G and B, a missing
//! alpha 255): width x height x 4 codes; code k stands for unorm8_floats()[k] (core/unorm8.h),
//! the value decode_image gives it (after the same widening).
struct RgbaCodes {
    int width = 0, height = 0;
    int file_channels = 0;  //!< the channels the file holds (1-4)
    UninitializedVector<std::uint8_t> codes;
    bool empty() const { return codes.empty(); }
};
//! An image decoded as codes (8-bit files) or as values (the rest): one of the two is non-empty.
struct DecodedImage {
    ImageF values;
    RgbaCodes codes;
};
//! decode_image for images kept as 8-bit codes (scene textures): an 8-bit PNG or JPEG that
//! core/png.h or core/jpeg.h reads comes back as `codes` (a quarter of RGBA float's bytes, no
//! float copy); any other image as decode_image's `values`. The same checks and budget
//! (charged as RGBA float either way).
DecodedImage decode_image_or_codes(const unsigned char* bytes, std::size_t size, const std::string& name,
                                   DecodeBudget* budget = nullptr);

//! Creates the folder (and parents) if missing. Throws aq::Error.
void ensure_directory(const std::string& dir);

//! The extension of a path in lower case, with its dot (".png"); empty when it has none.
std::string lower_extension(const std::string& path);

//! Replaces characters outside [A-Za-z0-9._-] so a target name is a safe file name.
std::string safe_file_name(const std::string& name);

//! Removes temporaries (`.aqtmp.PID.*`) that a killed process left in `dir` (PID no longer alive),
//! and write locks (`.aqlock.*`) no process holds.
//! write_file_atomically() calls it for its destination folder. Returns how many were removed.
int remove_stale_temporaries(const std::string& dir);

}  // namespace aq
