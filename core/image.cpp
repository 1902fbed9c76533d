// core/image.cpp — ImageF allocation with size limits, border names.
#include "core/image.h"

#include <atomic>

#include <sys/mman.h>

#include <algorithm>
#include <mutex>
#include <new>
#include <utility>
#include <vector>

namespace aq {

void check_image_size(int w, int h, const std::string& what) {
    if (w < 1 || h < 1)
        throw Error(what + ": size " + std::to_string(w) + "x" + std::to_string(h) +
                    " is empty; width and height must be at least 1");
    if (w > kMaxImageSide || h > kMaxImageSide ||
        std::int64_t(w) * std::int64_t(h) > kMaxImagePixels)
        throw Error(what + ": size " + std::to_string(w) + "x" + std::to_string(h) +
                    " exceeds the limit (" + std::to_string(kMaxImageSide) + " px per side, " +
                    std::to_string(kMaxImagePixels) + " px in all; see docs/limits.md)");
}

namespace {
//! x86-64 transparent huge page size. Buffers at least this large are aligned to it so that the
//! kernel can back them with huge pages from the first byte.
constexpr std::size_t kHugePage = std::size_t(2) << 20;
//! Alignment of smaller buffers: one AVX2 vector / cache line.
constexpr std::size_t kSmallAlign = 64;

//! Freed huge-page-aligned buffers, most recently freed last. A plain mutex: images are allocated
//! per stage call, not per pixel, so contention is negligible.
struct BufferPool {
    std::mutex m;
    std::vector<std::pair<std::size_t, float*>> free;
    std::size_t bytes = 0;
};
BufferPool& pool() {
    static BufferPool* p = new BufferPool;  // never destroyed: images may be freed during exit
    return *p;
}

float* pool_take(std::size_t rounded) {
    BufferPool& bp = pool();
    std::lock_guard<std::mutex> lock(bp.m);
    for (std::size_t i = bp.free.size(); i-- > 0;)
        if (bp.free[i].first == rounded) {
            float* p = bp.free[i].second;
            bp.free.erase(bp.free.begin() + std::ptrdiff_t(i));
            bp.bytes -= rounded;
            return p;
        }
    return nullptr;
}

std::atomic<std::size_t> g_pool_limit{kImagePoolBytes};

void pool_give(float* p, std::size_t rounded) {
    const std::size_t limit = g_pool_limit.load(std::memory_order_relaxed);
    if (rounded > limit) {
        std::free(p);
        return;
    }
    std::vector<float*> evicted;
    {
        BufferPool& bp = pool();
        std::lock_guard<std::mutex> lock(bp.m);
        bp.free.emplace_back(rounded, p);
        bp.bytes += rounded;
        std::size_t drop = 0;
        while (bp.bytes > limit) {
            bp.bytes -= bp.free[drop].first;
            evicted.push_back(bp.free[drop].second);
            ++drop;
        }
        bp.free.erase(bp.free.begin(), bp.free.begin() + std::ptrdiff_t(drop));
    }
    for (float* e : evicted) std::free(e);  // outside the lock
}
}  // namespace

std::size_t set_image_pool_limit(std::size_t bytes) { return g_pool_limit.exchange(bytes); }

std::size_t image_pool_bytes() {
    BufferPool& bp = pool();
    std::lock_guard<std::mutex> lock(bp.m);
    return bp.bytes;
}

void image_pool_release() {
    std::vector<std::pair<std::size_t, float*>> all;
    {
        BufferPool& bp = pool();
        std::lock_guard<std::mutex> lock(bp.m);
        all.swap(bp.free);
        bp.bytes = 0;
    }
    for (auto& [n, p] : all) std::free(p);
}

void detail::ImageFree::operator()(float* p) const {
    if (!p) return;
    if (bytes >= kHugePage)
        pool_give(p, bytes);
    else
        std::free(p);
}

void ImageF::allocate(int w, int h, int channels) {
    check_image_size(w, h);
    if (channels < 1 || channels > 4)
        throw Error("image: channel count " + std::to_string(channels) + " is not in [1, 4]");
    const std::size_t n = std::size_t(w) * h * channels;
    const std::size_t bytes = n * sizeof(float);
    const std::size_t align = bytes >= kHugePage ? kHugePage : kSmallAlign;
    const std::size_t rounded = (bytes + align - 1) / align * align;  // aligned_alloc needs a multiple
    float* p = align == kHugePage ? pool_take(rounded) : nullptr;
    if (!p) {
        p = static_cast<float*>(std::aligned_alloc(align, rounded));
        if (!p) throw std::bad_alloc();
        // A hint only (THP may be off, or the range already backed): failure changes nothing but speed.
        if (align == kHugePage) (void)madvise(p, rounded, MADV_HUGEPAGE);
    }
    pixels_ = std::unique_ptr<float[], Free>(p, Free{rounded});
    w_ = w;
    h_ = h;
    c_ = channels;
    n_ = n;
}

ImageF::ImageF(int w, int h, int channels, float fill) {
    allocate(w, h, channels);
    std::fill_n(pixels_.get(), n_, fill);
}

ImageF::ImageF(int w, int h, int channels, Uninitialized) { allocate(w, h, channels); }

ImageF::ImageF(const ImageF& o) {
    if (o.empty()) return;
    allocate(o.w_, o.h_, o.c_);
    std::copy_n(o.pixels_.get(), n_, pixels_.get());
}

ImageF& ImageF::operator=(const ImageF& o) {
    if (this != &o) {
        ImageF copy(o);
        *this = std::move(copy);
    }
    return *this;
}

bool ImageF::operator==(const ImageF& o) const {
    return w_ == o.w_ && h_ == o.h_ && c_ == o.c_ && n_ == o.n_ &&
           std::equal(pixels_.get(), pixels_.get() + n_, o.pixels_.get());
}

void ImageF::check_view(std::size_t c) const {
    if (c != std::size_t(c_))
        throw Error("image view of " + std::to_string(c) + " channels over an image of " +
                    std::to_string(c_) + " channels");
}

const char* border_name(Border b) { return b == Border::Clamp ? "clamp" : "mirror"; }

Border parse_border(const std::string& s) {
    if (s == "clamp") return Border::Clamp;
    if (s == "mirror") return Border::Mirror;
    throw Error("unknown border mode '" + s + "' (expected clamp or mirror)");
}

}  // namespace aq
