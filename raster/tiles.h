// raster/tiles.h — the one tile engine of raster: the grid of kTile-pixel tiles over an image,
// binning of bounding-boxed primitives into them in submission order, and the traversal
// (traverse_tiles: the plain reference loop, or every tile in parallel with one writer per tile).
// Sprites (particles.cpp) and strokes (strokes.cpp) bin through bin_boxes; the G-buffer and the
// triangle passes bin their chunked triangles with the same two halves (add_to_bins, sort_bins;
// binning.cpp). All four draw through traverse_tiles over a TileGrid.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <tbb/parallel_for.h>

#include "core/exec.h"
#include "raster/raster.h"

namespace aq::raster {

//! A tile's pixels, bounds inclusive and within the image.
struct TileRect {
    int x0, y0, x1, y1;
};

//! kTile x kTile tiles over a W x H image, row-major.
struct TileGrid {
    int width = 0, height = 0;  //!< the image
    int tiles_x = 0, tiles_y = 0;
    TileGrid() = default;
    TileGrid(int w, int h) : width(w), height(h), tiles_x((w + kTile - 1) / kTile), tiles_y((h + kTile - 1) / kTile) {}
    int count() const { return tiles_x * tiles_y; }
    //! The pixels of tile `tile`.
    TileRect rect(int tile) const {
        const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
        return {x0, y0, std::min(x0 + kTile, width) - 1, std::min(y0 + kTile, height) - 1};
    }
};

//! Primitives binned into the tiles their boxes touch, in submission order (a counting sort,
//! stable): tile t holds items[offsets[t] .. offsets[t + 1]).
struct TileBins {
    std::vector<std::uint32_t> offsets, items;
    std::span<const std::uint32_t> of(int tile) const {
        return {items.data() + offsets[std::size_t(tile)], items.data() + offsets[std::size_t(tile) + 1]};
    }
};

//! The first half of every binning in raster: item goes to each tile the pixel rect r touches, as
//! a (tile, item) pair, counted in counts[tile + 1] (the bins' offsets before sort_bins). An
//! empty rect (x0 > x1 or y0 > y1) adds nothing.
inline void add_to_bins(int tiles_x, const TileRect& r, std::uint32_t item, std::uint32_t* counts,
                        std::vector<std::uint64_t>& pairs) {
    if (r.x0 > r.x1 || r.y0 > r.y1) return;
    for (int ty = r.y0 / kTile; ty <= r.y1 / kTile; ++ty)
        for (int tx = r.x0 / kTile; tx <= r.x1 / kTile; ++tx) {
            const std::uint32_t tile = std::uint32_t(ty * tiles_x + tx);
            ++counts[tile + 1];
            pairs.push_back(std::uint64_t(tile) << 32 | item);
        }
}

//! The second half: a counting sort of the pairs (stable, so each tile keeps its items in the order
//! they were added) into offsets (counted by add_to_bins, ntiles + 1 of them) and items;
//! placed(at, item) for every item placed, in pair order (what a caller keeps beside the item).
template <class Placed>
void sort_bins(int ntiles, std::vector<std::uint32_t>& offsets, std::vector<std::uint32_t>& items,
               const std::vector<std::uint64_t>& pairs, Placed&& placed) {
    for (int i = 0; i < ntiles; ++i) offsets[std::size_t(i) + 1] += offsets[std::size_t(i)];
    items.resize(pairs.size());
    std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (const std::uint64_t p : pairs) {
        const std::uint32_t at = fill[p >> 32]++, item = std::uint32_t(p);
        items[at] = item;
        placed(at, item);
    }
}

//! Bins primitives 0..n-1 by their pixel boxes: box(k) gives an inclusive TileRect within the image
//! (an empty one: the primitive is not binned).
template <class BoxOf>
TileBins bin_boxes(const TileGrid& g, std::size_t n, BoxOf&& box) {
    TileBins b;
    b.offsets.assign(std::size_t(g.count()) + 1, 0);
    std::vector<std::uint64_t> pairs;
    pairs.reserve(n);
    for (std::size_t k = 0; k < n; ++k) add_to_bins(g.tiles_x, box(k), std::uint32_t(k), b.offsets.data(), pairs);
    sort_bins(g.count(), b.offsets, b.items, pairs, [](std::uint32_t, std::uint32_t) {});
    return b;
}

//! The one tile traversal of raster. Traversal::Reference: reference() once, on the calling
//! thread (the drawing's plain loop: every primitive in submission order over the whole image).
//! Fast: tile(tile index, its TileRect) for every tile of the grid, in parallel in ex's arena, each
//! tile one task, so what it writes inside its rect has one writer. Each drawing's tests compare
//! the two bit for bit.
template <class Reference, class Tile>
void traverse_tiles(const Exec& ex, const TileGrid& g, Reference&& reference, Tile&& tile) {
    if (ex.traversal == Traversal::Reference) {
        reference();
        return;
    }
    with_arena(ex, [&] { tbb::parallel_for(0, g.count(), [&](int t) { tile(t, g.rect(t)); }); });
}

}  // namespace aq::raster
