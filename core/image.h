// core/image.h — float images with 1..4 interleaved channels, typed views, regions and borders.
//
// Every G-buffer target and every stylization intermediate is an ImageF. Stages get typed views
// (View<float>, View<glm::vec4>, ...) whose element size must match the channel count; the check
// happens once, at the view's creation, so inner loops index without checks.
#pragma once

#include <algorithm>
#include <atomic>
#include <climits>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#ifdef __AVX__
#include <immintrin.h>
#endif

namespace aq {

//! Error raised for invalid input at an API entry (bad sizes, names, ranges, files).
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

//! Largest image side and pixel count we allocate (docs/limits.md). A request above these is
//! refused before any allocation. 32 Mpx covers 8K UHD; at ~100 B/px of G-buffer plus the
//! stylization intermediates this stays well inside our 24 GiB machines.
inline constexpr int kMaxImageSide = 16384;
inline constexpr std::int64_t kMaxImagePixels = 32LL * 1024 * 1024;

//! Throws aq::Error unless 1 <= w,h <= kMaxImageSide and w*h <= kMaxImagePixels.
void check_image_size(int w, int h, const std::string& what = "image");

//! Half-open pixel region [x0, x1) x [y0, y1). Roi::all() means the whole image.
struct Roi {
    int x0 = 0, y0 = 0, x1 = INT_MAX, y1 = INT_MAX;
    static constexpr Roi all() { return {}; }
    Roi clipped(int w, int h) const {
        return {std::max(x0, 0), std::max(y0, 0), std::min(x1, w), std::min(y1, h)};
    }
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

//! How a neighbourhood read outside the image is resolved. Always named, never accidental.
enum class Border { Clamp, Mirror };

//! Maps an out-of-range coordinate into [0, n) with the given border rule (n >= 1).
inline int resolve_border(int i, int n, Border b) {
    if (i >= 0 && i < n) return i;
    if (b == Border::Clamp) return i < 0 ? 0 : n - 1;
    // Mirror without repeating the edge texel (GL_MIRRORED_REPEAT-like about the edge centre):
    // -1 -> 1, n -> n-2. Period 2(n-1); n == 1 degenerates to 0.
    if (n == 1) return 0;
    const int period = 2 * (n - 1);
    int m = i % period;
    if (m < 0) m += period;
    return m < n ? m : period - m;
}

const char* border_name(Border b);
Border parse_border(const std::string& s);  // "clamp" | "mirror", throws aq::Error

template <class T>
struct View {
    T* data = nullptr;
    int width = 0, height = 0;
    std::ptrdiff_t stride = 0;  //!< elements per row

    T& operator()(int x, int y) const { return data[y * stride + x]; }
    T* row(int y) const { return data + y * stride; }
    //! Read with the border rule applied (neighbourhood taps).
    const T& at(int x, int y, Border b) const {
        return data[resolve_border(y, height, b) * stride + resolve_border(x, width, b)];
    }
};

//! Most bytes of freed large image buffers kept for reuse (core/image.cpp); beyond it the oldest
//! are returned to the system. Two 1080p frames' worth of 4-channel temporaries.
inline constexpr std::size_t kImagePoolBytes = std::size_t(256) << 20;

//! Changes the pool's limit (at most kImagePoolBytes is the default) and returns the previous one;
//! pooled bytes beyond the new limit are returned to the system at the next release into the pool.
//! A one-shot render lowers it (app/render_job.cpp: a single image gains little from reuse, and
//! parked buffers of sizes no later image takes count in its peak memory).
std::size_t set_image_pool_limit(std::size_t bytes);

//! Bytes currently held by the buffer pool (for tests and diagnostics).
std::size_t image_pool_bytes();
//! Returns every pooled buffer to the system.
void image_pool_release();

namespace detail {
//! ImageF's deleter: large buffers return to the pool (defined outside ImageF so that it is
//! default-constructible where ImageF is still incomplete).
struct ImageFree {
    std::size_t bytes = 0;  //!< allocated (rounded) size
    void operator()(float* p) const;
};
}  // namespace detail

//! Tag of the ImageF constructor that leaves the values unspecified: for outputs that the caller
//! overwrites completely (stage outputs), where filling would only add a pass over the memory.
struct Uninitialized {};
inline constexpr Uninitialized kUninitialized{};

//! std::allocator whose value-initialisation (vector::resize(n), vector(n)) leaves trivial values
//! unspecified, as kUninitialized does for images: for buffers a decoder then fills completely
//! (8-bit texture codes), where zeroing first would only add a pass over fresh memory.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};
template <class T>
using UninitializedVector = std::vector<T, UninitializedAllocator<T>>;

//! Interleaved float image, 1..4 channels, row-major, no padding.
//!
//! Storage: large images (>= 2 MiB) are allocated 2 MiB-aligned and marked MADV_HUGEPAGE, so a
//! 1080p intermediate (8-33 MB) is first touched in a handful of huge-page faults instead of
//! thousands of 4 KiB ones (THP runs in `madvise` mode on our machines). Freed large buffers are
//! kept in a small process-wide pool (at most kImagePoolBytes) and handed to the next image of the
//! same byte size, so per-frame temporaries do not make the kernel clear fresh pages every frame
//! (a fill still writes every value; kUninitialized means "unspecified", as before).
//! See docs/performance.md.
class ImageF {
public:
    ImageF() = default;
    ImageF(int w, int h, int channels, float fill = 0.0f);
    //! Values unspecified: every value must be written before it is read.
    ImageF(int w, int h, int channels, Uninitialized);
    ImageF(const ImageF& o);
    ImageF& operator=(const ImageF& o);
    //! A moved-from image is empty (0 x 0 x 0): with the defaulted moves it kept its shape without
    //! storage, so ensure_output() on it wrote through a null pointer (found when the render job
    //! started handing a frame's converted image to the writer; tests/core/image_test.cpp).
    ImageF(ImageF&& o) noexcept
        : w_(std::exchange(o.w_, 0)), h_(std::exchange(o.h_, 0)), c_(std::exchange(o.c_, 0)),
          n_(std::exchange(o.n_, 0)), pixels_(std::move(o.pixels_)),
          stamp_(o.stamp_.exchange(0, std::memory_order_relaxed)) {}
    ImageF& operator=(ImageF&& o) noexcept {
        if (this != &o) {
            w_ = std::exchange(o.w_, 0);
            h_ = std::exchange(o.h_, 0);
            c_ = std::exchange(o.c_, 0);
            n_ = std::exchange(o.n_, 0);
            pixels_ = std::move(o.pixels_);
            stamp_.store(o.stamp_.exchange(0, std::memory_order_relaxed), std::memory_order_relaxed);
        }
        return *this;
    }

    int width() const { return w_; }
    int height() const { return h_; }
    int channels() const { return c_; }
    bool empty() const { return n_ == 0; }
    std::size_t num_values() const { return n_; }
    //! Mutable access (data, at, view) clears the content stamp.
    float* data() {
        clear_stamp();
        return pixels_.get();
    }
    const float* data() const { return pixels_.get(); }
    float& at(int x, int y, int c) {
        clear_stamp();
        return pixels_[(std::size_t(y) * w_ + x) * c_ + c];
    }
    float at(int x, int y, int c) const { return pixels_[(std::size_t(y) * w_ + x) * c_ + c]; }
    bool same_size(const ImageF& o) const { return w_ == o.w_ && h_ == o.h_; }

    //! Typed view; T must be float, glm::vec2, glm::vec3 or glm::vec4 matching channels().
    template <class T>
    View<T> view() {
        check_view(sizeof(T) / sizeof(float));
        return {reinterpret_cast<T*>(data()), w_, h_, w_};
    }
    template <class T>
    View<const T> view() const {
        check_view(sizeof(T) / sizeof(float));
        return {reinterpret_cast<const T*>(data()), w_, h_, w_};
    }

    //! Same size, channels and values (compared as floats, as std::vector's == did).
    bool operator==(const ImageF& o) const;

    //! Content stamp: a writer that knows exactly what it last wrote into this image (the
    //! rasterizer's frame, raster/raster.cpp) tags it with a non-zero value and, on its next write
    //! into the same image, may leave alone what it would write again. The stamp moves with the
    //! storage, a copy starts at 0, and every mutable access (data, at, view) clears it, so a
    //! stamped image holds the stamping writer's values — provided nobody writes through a pointer
    //! taken before the stamp was set (docs/raster.md "Background tiles kept between frames").
    std::uint64_t stamp() const { return stamp_.load(std::memory_order_relaxed); }
    void set_stamp(std::uint64_t s) { stamp_.store(s, std::memory_order_relaxed); }

private:
    using Free = detail::ImageFree;
    void allocate(int w, int h, int channels);
    void check_view(std::size_t c) const;
    int w_ = 0, h_ = 0, c_ = 0;
    std::size_t n_ = 0;
    std::unique_ptr<float[], Free> pixels_;
    //! Atomic so that threads taking data() of one image at once do not race; stored only when
    //! set (an unstamped image's cache line is only read), relaxed: a stamp orders nothing.
    std::atomic<std::uint64_t> stamp_{0};
    void clear_stamp() {
        if (stamp_.load(std::memory_order_relaxed) != 0) stamp_.store(0, std::memory_order_relaxed);
    }
};

//! Makes img a w x h x c image, reusing its storage when it already has that shape (a caller
//! running every frame then writes into the same pages). Contents are unspecified: a new image is
//! not filled, so the caller must write every value (stage outputs, the CLI's converted image).
inline void ensure_output(ImageF& img, int w, int h, int c) {
    if (img.width() != w || img.height() != h || img.channels() != c) img = ImageF(w, h, c, kUninitialized);
}

//! rgb = the first three channels of the 4-channel rgba (ensure_output, then a plain copy of three
//! of every four values, which the compiler vectorises).
inline void rgb_of(const ImageF& rgba, ImageF& rgb) {
    ensure_output(rgb, rgba.width(), rgba.height(), 3);
    const std::size_t n = std::size_t(rgba.width()) * std::size_t(rgba.height());
    const float* s = rgba.data();
    float* d = rgb.data();
    for (std::size_t i = 0; i < n; ++i) {
        d[3 * i + 0] = s[4 * i + 0];
        d[3 * i + 1] = s[4 * i + 1];
        d[3 * i + 2] = s[4 * i + 2];
    }
}

//! Copies n floats with non-temporal stores where dst is 32-byte aligned (the ends plain): the
//! destination's lines are not read first, a third less memory traffic than memcpy for data that
//! is not read back soon (the G-buffer's row streaming, a stage's copied background chunks). The
//! caller orders the stores before another thread reads them (stream_fence() at its task's end).
inline void stream_copy(float* dst, const float* src, std::size_t n) {
    std::size_t i = 0;
    for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 31) != 0; ++i) dst[i] = src[i];
#ifdef __AVX__
    for (; i + 8 <= n; i += 8) _mm256_stream_ps(dst + i, _mm256_loadu_ps(src + i));
#endif
    for (; i < n; ++i) dst[i] = src[i];
}

//! Orders this thread's stream_copy stores before its later stores (sfence).
inline void stream_fence() {
#ifdef __AVX__
    _mm_sfence();
#endif
}

}  // namespace aq
