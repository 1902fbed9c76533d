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
#include <utility>
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
// or, for several outputs, static constexpr std::array<int, M> kOutputs and
//   static void pixel(const Pixel<F>* in, Pixel<F>* out, const Params& p);

namespace detail {
//! The channel counts of K's outputs (kOutputs, or the one kOutput).
template <class K>
constexpr auto outputs_of() {
    if constexpr (requires { K::kOutputs; })
        return K::kOutputs;
    else
        return std::array<int, 1>{K::kOutput};
}

template <class K, class F>
inline void call(const Pixel<F>* in, Pixel<F>* out, const typename K::Params& p) {
    if constexpr (requires { K::kOutputs; })
        K::pixel(in, out, p);
    else
        K::pixel(in, out[0], p);
}

//! Pixel i of every input, one value per channel.
template <class K>
inline void load_one(const std::vector<const ImageF*>& in, std::size_t i, Pixel<float>* px) {
    for (std::size_t k = 0; k < K::kInputs.size(); ++k) {
        const int c = K::kInputs[k];
        const float* s = in[k]->data() + i * std::size_t(c);
        for (int ch = 0; ch < c; ++ch) px[k][std::size_t(ch)] = s[ch];
    }
}

//! Pixels i..i+7 of one C-channel image: channel ch of pixel i + l in lane l (values moved only).
template <int C>
inline void load_eight_of(const float* s, Pixel<simd::v8f>& px) {
    if constexpr (C == 1 || C == 3 || C == 4) {
        for (int ch = 0; ch < C; ++ch) px[std::size_t(ch)] = simd::strided8<C>(s + ch);
    } else {
        for (int ch = 0; ch < C; ++ch)
            for (int l = 0; l < 8; ++l) px[std::size_t(ch)][l] = s[l * C + ch];
    }
}

//! Pixels i..i+7 of every input.
template <class K, std::size_t... I>
inline void load_eight(const std::vector<const ImageF*>& in, std::size_t i, Pixel<simd::v8f>* px, std::index_sequence<I...>) {
    (load_eight_of<K::kInputs[I]>(in[I]->data() + i * std::size_t(K::kInputs[I]), px[I]), ...);
}

//! Lanes 0..7 of px as pixels o[0..8) of a C-channel image.
template <int C>
inline void store_eight_of(float* o, const Pixel<simd::v8f>& px) {
    if constexpr (C == 1) {
        simd::store8(o, px[0]);
    } else if constexpr (C == 4) {
        alignas(32) float ch[4][8];
        for (int c = 0; c < 4; ++c) simd::store8(ch[c], px[std::size_t(c)]);
        toolkit::store_rgba8(o, ch[0], ch[1], ch[2], ch[3]);
    } else {
        for (int c = 0; c < C; ++c)
            for (int l = 0; l < 8; ++l) o[l * C + c] = px[std::size_t(c)][l];
    }
}

template <class K, std::size_t... I>
inline void store_eight(ImageF* const* out, std::size_t i, const Pixel<simd::v8f>* px, std::index_sequence<I...>) {
    constexpr auto co = outputs_of<K>();
    (store_eight_of<co[I]>(out[I]->data() + i * std::size_t(co[I]), px[I]), ...);
}
}  // namespace detail

//! outs = K applied to every pixel of `in` (every input the size of in[0]; each output allocated
//! at that size with its declared channels); the reference traversal runs the plain loop, the fast
//! one the eight-lane rows. A row window (Exec::rows) computes its rows only, the outputs keeping
//! the full size.
template <class K>
void run_pointwise(ImageF* const* outs, const std::vector<const ImageF*>& in, const typename K::Params& p, const Exec& ex) {
    constexpr std::size_t N = K::kInputs.size();
    constexpr auto co = detail::outputs_of<K>();
    constexpr std::size_t M = co.size();
    const int w = in[0]->width(), h = in[0]->height();
    for (std::size_t m = 0; m < M; ++m) ensure_output(*outs[m], w, h, co[m]);
    auto one = [&](std::size_t i) {
        Pixel<float> px[N] = {}, o[M] = {};
        detail::load_one<K>(in, i, px);
        detail::call<K>(px, o, p);
        for (std::size_t m = 0; m < M; ++m)
            for (int ch = 0; ch < co[m]; ++ch) outs[m]->data()[i * std::size_t(co[m]) + std::size_t(ch)] = o[m][std::size_t(ch)];
    };
    for_each_row_block(ex, h, [&](int y0, int y1) {
        const std::size_t i0 = std::size_t(y0) * std::size_t(w), i1 = std::size_t(y1) * std::size_t(w);
        std::size_t i = i0;
        if (ex.traversal != Traversal::Reference)
            for (; i + 8 <= i1; i += 8) {
                Pixel<simd::v8f> px[N] = {}, o[M] = {};
                detail::load_eight<K>(in, i, px, std::make_index_sequence<N>{});
                detail::call<K>(px, o, p);
                detail::store_eight<K>(outs, i, o, std::make_index_sequence<M>{});
            }
        for (; i < i1; ++i) one(i);
    });
}

//! The one-output form.
template <class K>
void run_pointwise(ImageF& out, const std::vector<const ImageF*>& in, const typename K::Params& p, const Exec& ex) {
    ImageF* const outs[1] = {&out};
    run_pointwise<K>(outs, in, p, ex);
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
