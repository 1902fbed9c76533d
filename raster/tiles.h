// raster/tiles.h — the screen tiles every tiled drawing in raster shares: the grid of kTile-pixel
// tiles over an image, binning of bounding-boxed primitives into them in submission order, and the
// parallel traversal that gives each tile one writer. Sprites (particles.cpp) and strokes
// (strokes.cpp) bin through bin_boxes; the triangle passes and the G-buffer bin their chunked
// triangles in binning.cpp and walk the same grid (tile_rect).
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
    TileGrid(int w, int h) : width(w), height(h), tiles_x((w + kTile - 1) / kTile), tiles_y((h + kTile - 1) / kTile) {}
    int count() const { return tiles_x * tiles_y; }
    TileRect rect(int tile) const { return tile_rect(tile, tiles_x, width, height); }
    //! The tile's pixels, for a grid of tiles_x columns over a w x h image.
    static TileRect tile_rect(int tile, int tiles_x, int w, int h) {
        const int x0 = (tile % tiles_x) * kTile, y0 = (tile / tiles_x) * kTile;
        return {x0, y0, std::min(x0 + kTile, w) - 1, std::min(y0 + kTile, h) - 1};
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

//! Bins primitives 0..n-1 by their pixel boxes: box(k) gives an inclusive TileRect within the image
//! (callers drop primitives with empty boxes before).
template <class BoxOf>
TileBins bin_boxes(const TileGrid& g, std::size_t n, BoxOf&& box) {
    TileBins b;
    b.offsets.assign(std::size_t(g.count()) + 1, 0);
    for (std::size_t k = 0; k < n; ++k) {
        const TileRect r = box(k);
        for (int j = r.y0 / kTile; j <= r.y1 / kTile; ++j)
            for (int i = r.x0 / kTile; i <= r.x1 / kTile; ++i) ++b.offsets[std::size_t(j * g.tiles_x + i) + 1];
    }
    for (int t = 0; t < g.count(); ++t) b.offsets[std::size_t(t) + 1] += b.offsets[std::size_t(t)];
    b.items.resize(b.offsets.back());
    std::vector<std::uint32_t> fill(b.offsets.begin(), b.offsets.end() - 1);
    for (std::size_t k = 0; k < n; ++k) {
        const TileRect r = box(k);
        for (int j = r.y0 / kTile; j <= r.y1 / kTile; ++j)
            for (int i = r.x0 / kTile; i <= r.x1 / kTile; ++i) b.items[fill[std::size_t(j * g.tiles_x + i)]++] = std::uint32_t(k);
    }
    return b;
}

//! f(tile index, its TileRect) for every tile of the grid, in parallel in ex's arena; each tile
//! is one task, so what it writes inside its rect has one writer.
template <class F>
void for_each_grid_tile(const Exec& ex, const TileGrid& g, F&& f) {
    with_arena(ex, [&] { tbb::parallel_for(0, g.count(), [&](int t) { f(t, g.rect(t)); }); });
}

}  // namespace aq::raster
