// stylize/schedule/pointwise.h — the shared schedule of pointwise stages (docs/stylize.md "Writing a
// stage"): a stage declares its parameters and writes its per-pixel maths once, over a lane type,
// and gets the plain reference loop (one pixel at a time in F = float), the fast schedule (oneTBB
// blocks of rows, eight pixels per step in F = simd::v8f, the block's last pixels one at a time),
// the registry entry, the parameter checking and its names for --set and pipeline files.
//
// The two schedules give the same bits because a kernel uses only the operations of core/lanes.h
// (+ - * /, comparisons, select, min_of, max_of, sat, ...), which compute in every lane what the
// scalar computes (docs/determinism.md).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/lanes.h"
#include "stylize/declare.h"
#include "stylize/schedule/rows.h"
#include "stylize/stage.h"
#include "stylize/stages/toolkit.h"

namespace aq::stylize::schedule {

//! One pixel's channels in lane type F; channels beyond a port's count read as 0 and are not
//! written.
template <class F>
using Pixel = std::array<F, 4>;

// A pointwise kernel is a struct K with
//   struct Params { ... };                   typed parameters, with their defaults
//   static ParamTable<Params> params();       their names, ranges and docs (written once)
//   static constexpr std::array<int, N> kInputs;  the channel count of each input port
//   static constexpr int kOutput;             the output's channel count
//   template <class F>
//   static void pixel(const Pixel<F>* in, Pixel<F>& out, const Params& p);   // the maths, once

namespace detail {
//! Pixel i of every input, one value per channel.
template <class K>
inline void load_one(const std::vector<const ImageF*>& in, std::size_t i, Pixel<float>* px) {
    for (std::size_t k = 0; k < K::kInputs.size(); ++k) {
        const int c = K::kInputs[k];
        const float* s = in[k]->data() + i * std::size_t(c);
        for (int ch = 0; ch < c; ++ch) px[k][std::size_t(ch)] = s[ch];
    }
}

//! Pixels i..i+7 of every input, channel ch of pixel i + l in lane l.
template <class K>
inline void load_eight(const std::vector<const ImageF*>& in, std::size_t i, Pixel<simd::v8f>* px) {
    for (std::size_t k = 0; k < K::kInputs.size(); ++k) {
        const int c = K::kInputs[k];
        const float* s = in[k]->data() + i * std::size_t(c);
        for (int ch = 0; ch < c; ++ch)
            for (int l = 0; l < 8; ++l) px[k][std::size_t(ch)][l] = s[l * c + ch];
    }
}
}  // namespace detail

//! out = K applied to every pixel of `in` (every input the size of in[0]); the reference traversal
//! runs the plain loop, the fast one the eight-lane rows. A row window (Exec::rows) computes its
//! rows only, the output keeping the full size.
template <class K>
void run_pointwise(ImageF& out, const std::vector<const ImageF*>& in, const typename K::Params& p, const Exec& ex) {
    constexpr std::size_t N = K::kInputs.size();
    constexpr int Co = K::kOutput;
    const int w = in[0]->width(), h = in[0]->height();
    ensure_output(out, w, h, Co);
    float* dst = out.data();
    auto one = [&](std::size_t i) {
        Pixel<float> px[N] = {}, o = {};
        detail::load_one<K>(in, i, px);
        K::pixel(px, o, p);
        for (int ch = 0; ch < Co; ++ch) dst[i * Co + std::size_t(ch)] = o[std::size_t(ch)];
    };
    for_each_row_block(ex, h, [&](int y0, int y1) {
        const std::size_t i0 = std::size_t(y0) * std::size_t(w), i1 = std::size_t(y1) * std::size_t(w);
        std::size_t i = i0;
        if (ex.traversal != Traversal::Reference)
            for (; i + 8 <= i1; i += 8) {
                Pixel<simd::v8f> px[N] = {}, o = {};
                detail::load_eight<K>(in, i, px);
                K::pixel(px, o, p);
                for (int ch = 0; ch < Co; ++ch)
                    for (int l = 0; l < 8; ++l) dst[(i + std::size_t(l)) * Co + std::size_t(ch)] = o[std::size_t(ch)][l];
            }
        for (; i < i1; ++i) one(i);
    });
}

//! The registry entry of a pointwise kernel: its ports (channel counts as K declares; throws
//! aq::Error otherwise), parameter table, run function (input checks, sizes, no aliasing), the
//! reference (the same kernel on one pixel at a time: SharedMaths) and row windows.
template <class K>
StageVariant pointwise_variant(std::string stage, std::string variant, std::string doc, std::vector<Port> inputs,
                               Port output) {
    const std::string key = stage + "/" + variant;
    if (inputs.size() != K::kInputs.size()) throw Error(key + ": the kernel reads " + std::to_string(K::kInputs.size()) + " inputs");
    for (std::size_t k = 0; k < inputs.size(); ++k) {
        if (inputs[k].channels != K::kInputs[k] || inputs[k].optional)
            throw Error(key + ": input '" + inputs[k].name + "' must be required with " + std::to_string(K::kInputs[k]) +
                        " channels, as the kernel reads");
    }
    if (output.channels != K::kOutput)
        throw Error(key + ": output '" + output.name + "' must have " + std::to_string(K::kOutput) + " channels");
    using P = typename K::Params;
    return declare({.stage = std::move(stage),
                    .variant = std::move(variant),
                    .doc = std::move(doc),
                    .inputs = inputs,
                    .outputs = {std::move(output)},
                    .reference = StageVariant::Reference::SharedMaths,
                    .row_halo = pointwise_rows},
                   K::params(), [key, inputs](StageIO& io, const P& p, const Exec& ex) {
                       for (std::size_t k = 0; k < io.in.size(); ++k) {
                           toolkit::check_same_size(*io.in[k], *io.in[0], key, inputs[k].name, inputs[0].name);
                           toolkit::check_not_alias(*io.out[0], io.in[k], key, inputs[k].name);
                       }
                       run_pointwise<K>(*io.out[0], io.in, p, ex);
                   });
}

}  // namespace aq::stylize::schedule
