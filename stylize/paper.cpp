// stylize/paper.cpp — paper substrates (spec §4 "paper substrate"; WC17 §3.3, WC18 §4).
//
// Every paper becomes a 3-channel texture in the MNPR layout: R,G = normal x,y encoded 0.5-centred
// (n*0.5 + 0.5), B = height, all in [0,1]. Two source layouts:
//   "mnpr"   the texture already holds RG normal + B height (MNPR's rough_default_2k.jpg);
//   "height" a height/displacement map (ambientCG Paper001_*_Displacement.jpg): channel 0 is the
//            height, normals are derived with wrapped central differences (see derive_normals).
// The source is decoded once per (file, layout) and cached; prepare_paper then tiles (wraps) it to
// the output size at the requested scale and applies MNPR's roughness adjust.
#include "stylize/paper.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <cstdint>
#include <filesystem>
#include <future>
#include <mutex>
#include <utility>

#include "core/input.h"
#include "core/io.h"
#include "stylize/kernels.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize {

namespace {

//! Strength k of the height gradient when deriving normals from a displacement map (height in
//! [0,1] units per texel). Measured on MNPR's own paper, whose B channel is its height: by least
//! squares R - 0.5 = -1.04 dh/dx (corr. 0.76) and G - 0.5 = +1.36 dh/drow (corr. 0.91), i.e. n.xy
//! is about 2..2.7 times the height gradient; we take k = 2 (docs/stylize.md "Paper preparation").
constexpr float kHeightNormalStrength = 2.0f;

//! Wrapped index into [0, n).
inline int wrap(int i, int n) {
    int m = i % n;
    return m < 0 ? m + n : m;
}

//! Normals from a height field by wrapped central differences (the paper tiles, so the
//! neighbourhood wraps too): gx = (h[x+1] - h[x-1]) / 2, gr = (h[row+1] - h[row-1]) / 2 and
//! n = normalize(-k*gx, +k*gr, 1): x to the right, y up (rows go down), the convention MNPR's own
//! texture follows (see kHeightNormalStrength). Encodes n.xy*0.5 + 0.5 in R,G and copies the
//! height into B. A flat field gives (0.5, 0.5, h); every value lies in [0,1].
ImageF derive_normals(const ImageF& src, float strength) {
    const int w = src.width(), h = src.height(), c = src.channels();
    ImageF out(w, h, 3, kUninitialized);  // every value is written below
    auto height = [&](int x, int y) { return src.data()[(std::size_t(wrap(y, h)) * w + wrap(x, w)) * c]; };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float dx = (height(x + 1, y) - height(x - 1, y)) * 0.5f;
            const float dr = (height(x, y + 1) - height(x, y - 1)) * 0.5f;
            const glm::vec3 n = glm::normalize(glm::vec3(-strength * dx, strength * dr, 1.0f));
            out.at(x, y, 0) = n.x * 0.5f + 0.5f;
            out.at(x, y, 1) = n.y * 0.5f + 0.5f;
            out.at(x, y, 2) = height(x, y);
        }
    return out;
}

//! Converts a decoded file to the MNPR layout (3 channels) according to `layout`. Takes the
//! decoded image by value: a 3-channel "mnpr" file is moved, not copied (a 2k paper is 50 MB of
//! floats, and fresh pages cost ~2 ms per MB on our VMs: docs/performance.md "Design decisions
//! that hold").
ImageF to_mnpr_layout(ImageF img, const std::string& layout, const std::string& path) {
    if (layout == "mnpr") {
        if (img.channels() < 3)
            throw Error("paper '" + path + "': layout \"mnpr\" needs 3 channels (RG normal, B height), file has " +
                        std::to_string(img.channels()));
        if (img.channels() == 3) return img;
        ImageF out(img.width(), img.height(), 3, kUninitialized);
        for (int y = 0; y < img.height(); ++y)
            for (int x = 0; x < img.width(); ++x)
                for (int k = 0; k < 3; ++k) out.at(x, y, k) = img.at(x, y, k);
        return out;
    }
    if (layout == "height") return derive_normals(img, kHeightNormalStrength);
    throw Error("paper '" + path + "': unknown layout \"" + layout + "\" (expected \"mnpr\" or \"height\")");
}

std::mutex& cache_mutex() {
    static std::mutex mu;
    return mu;
}

using PaperFuture = std::shared_future<std::shared_ptr<const ImageF>>;
//! Decoded paper files by layout|path. An entry is a future: a second reader of a file that is
//! being decoded (prefetch_paper on another thread) waits for it instead of decoding it again.
struct CacheEntry {
    PaperFuture decoded;
    std::uint64_t serial = 0;  //!< which decode made the entry (a failed one removes only its own)
};
std::map<std::string, CacheEntry>& paper_cache() {
    static std::map<std::string, CacheEntry> cache;
    return cache;
}
//! The record of each cached paper's file read (by cache key, under cache_mutex): announced again
//! to the live InputCaptures when the cache hands the paper out (core/input.h note_cached_input).
std::map<std::string, std::vector<InputRecord>>& paper_reads() {
    static std::map<std::string, std::vector<InputRecord>> reads;
    return reads;
}

//! The decoded paper file, from the cache or decoded here (the first reader decodes; later and
//! concurrent readers of the same key wait for it). A failed decode is not kept: its waiters get
//! the error, the next reader tries again.
std::shared_ptr<const ImageF> load_cached(const std::string& path, const std::string& layout) {
    std::mutex& mu = cache_mutex();
    auto& cache = paper_cache();
    const std::string key = layout + "|" + path;
    static std::uint64_t next_serial = 0;  // under mu
    std::promise<std::shared_ptr<const ImageF>> promise;
    PaperFuture future;
    std::uint64_t serial = 0;
    bool decode_here = false;
    {
        std::lock_guard<std::mutex> lock(mu);
        auto it = cache.find(key);
        decode_here = it == cache.end();
        if (decode_here) {
            serial = ++next_serial;
            it = cache.emplace(key, CacheEntry{promise.get_future().share(), serial}).first;
        }
        future = it->second.decoded;
    }
    if (decode_here) {
        try {
            ImageF img;
            std::vector<InputRecord> reads;
            try {
                InputCapture capture;  // other threads' reads land in it too: only the paper's are kept
                img = read_image(path);
                std::error_code ec;
                const std::string abs = std::filesystem::absolute(path, ec).lexically_normal().string();
                for (const InputRecord& r : capture.records())
                    if (r.path == abs) reads.push_back(r);
            } catch (const Error& e) {
                throw Error(std::string("paper file '") + path + "' could not be read: " + e.what());
            }
            {
                std::lock_guard<std::mutex> lock(mu);
                paper_reads()[key] = std::move(reads);
            }
            promise.set_value(std::make_shared<const ImageF>(to_mnpr_layout(std::move(img), layout, path)));
        } catch (...) {
            promise.set_exception(std::current_exception());
            std::lock_guard<std::mutex> lock(mu);
            auto it = cache.find(key);
            if (it != cache.end() && it->second.serial == serial) cache.erase(it);
        }
    }
    std::shared_ptr<const ImageF> paper = future.get();  // the decoded paper, or the decoder's error
    if (!decode_here) {
        std::lock_guard<std::mutex> lock(mu);
        if (auto it = paper_reads().find(key); it != paper_reads().end())
            for (const InputRecord& r : it->second) note_cached_input(r);
    }
    return paper;
}

}  // namespace

void clear_paper_cache() {
    std::lock_guard<std::mutex> lock(cache_mutex());
    paper_cache().clear();
    paper_reads().clear();
}

std::future<void> prefetch_paper(const PaperSpec& spec) {
    if (spec.file.empty()) return {};
    return std::async(std::launch::async, [file = spec.file, layout = spec.layout] {
        try {
            (void)load_cached(file, layout);
        } catch (...) {
            // prepare_paper reads the file again and reports the error itself
        }
    });
}

ImageF prepare_paper(const PaperSpec& spec, int width, int height, const Exec& ex) {
    check_image_size(width, height, "paper");
    if (spec.file.empty()) throw Error("paper: no file given");
    if (!std::isfinite(spec.scale) || spec.scale < 0.1f || spec.scale > 10.0f)
        throw Error("paper '" + spec.file + "': scale " + std::to_string(spec.scale) + " outside [0.1, 10]");
    if (!std::isfinite(spec.roughness) || spec.roughness < 0.0f || spec.roughness > 5.0f)
        throw Error("paper '" + spec.file + "': roughness " + std::to_string(spec.roughness) + " outside [0, 5]");
    const auto tex_ptr = load_cached(spec.file, spec.layout);
    const ImageF& tex = *tex_ptr;
    const int tw = tex.width(), th = tex.height();
    const float r = spec.roughness;
    ImageF out(width, height, 3, kUninitialized);  // both branches below write every value
    const float* t = tex.data();
    float* o = out.data();
    // MNPR's adjust-load: (tex - 0.5) * roughness + 0.5, saturated so the texture stays in [0,1].
    auto adjust = [r](float v) { return sat((v - 0.5f) * r + 0.5f); };
    if (spec.scale == 1.0f) {
        // One texel per pixel: an exact wrapped copy, in runs of whole texture rows (no division
        // per pixel; a one-shot render prepares its paper on the critical path).
        toolkit::for_each_row_block(ex, height, [&](int y0, int y1) {
            for (int y = y0; y < y1; ++y) {
                const float* trow = t + std::size_t(y % th) * tw * 3;
                float* d = o + std::size_t(y) * width * 3;
                for (int x0 = 0; x0 < width; x0 += tw) {
                    const std::size_t n = std::size_t(std::min(tw, width - x0)) * 3;
                    for (std::size_t i = 0; i < n; ++i) d[std::size_t(x0) * 3 + i] = adjust(trow[i]);
                }
            }
        });
        return out;
    }
    // Other scales: output pixel centre (x + 0.5) maps to texel coordinate (x + 0.5) / scale; the
    // texture is sampled bilinearly with texel centres at +0.5 and wrapping taps (GL_REPEAT).
    const float inv = 1.0f / spec.scale;
    toolkit::for_each_row_block(ex, height, [&](int ya, int yb) {
        for (int y = ya; y < yb; ++y) {
            const float fy = (float(y) + 0.5f) * inv - 0.5f;
            const float y0f = std::floor(fy);
            const float ty = fy - y0f;
            const int y0 = wrap(int(y0f), th), y1 = wrap(int(y0f) + 1, th);
            for (int x = 0; x < width; ++x) {
                const float fx = (float(x) + 0.5f) * inv - 0.5f;
                const float x0f = std::floor(fx);
                const float tx = fx - x0f;
                const int x0 = wrap(int(x0f), tw), x1 = wrap(int(x0f) + 1, tw);
                const float* a = t + (std::size_t(y0) * tw + x0) * 3;
                const float* b = t + (std::size_t(y0) * tw + x1) * 3;
                const float* c = t + (std::size_t(y1) * tw + x0) * 3;
                const float* d = t + (std::size_t(y1) * tw + x1) * 3;
                float* dst = o + (std::size_t(y) * width + x) * 3;
                for (int k = 0; k < 3; ++k) dst[k] = adjust(maths::bilerp(a[k], b[k], c[k], d[k], tx, ty));
            }
        }
    });
    return out;
}

ImageF flat_paper(int width, int height) {
    check_image_size(width, height, "flat paper");
    // MNPR layout: normal x, normal y, height; the flat paper's values are named in paper.h.
    static_assert(kFlatPaperNormal == kFlatPaperHeight, "one fill value serves all three channels");
    return ImageF(width, height, 3, kFlatPaperNormal);
}

float paper_height_spread(const ImageF& paper, const Exec& ex) {
    if (paper.channels() < 3) throw Error("paper: no height channel");
    const int w = paper.width(), h = paper.height();
    const std::size_t pc = std::size_t(paper.channels());
    std::vector<float> row_max(std::size_t(std::max(h, 0)), 0.0f);  // per row: NaN wins, then the maximum
    toolkit::for_each_row_block(ex, h, [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            const float* r = paper.data() + std::size_t(y) * w * pc + 2;
            float m = 0.0f;
            bool nan = false;
            for (int x = 0; x < w; ++x) {
                const float d = std::abs(r[std::size_t(x) * pc] - 0.5f);
                nan |= d != d;
                m = d > m ? d : m;
            }
            row_max[std::size_t(y)] = nan ? std::numeric_limits<float>::quiet_NaN() : m;
        }
    });
    float m = 0.0f;
    for (const float v : row_max) {
        if (v != v) return v;
        m = v > m ? v : m;
    }
    return m;
}

}  // namespace aq::stylize
