// raster/visibility.h — the depth test of one triangle over a block of pixels: the one visibility
// loop of the tiled traversals (the G-buffer's tiles, the raster passes' deferred resolve;
// docs/raster.md "Visibility").
//
// Per pixel it is exactly the reference traversal's test: inside (edge_values / inside, the
// top-left rule), then perspective_bary's depth, written where it is less than the buffer's (the
// first of equal depths stays). The fast schedule tests eight pixels at once (AVX2) where every
// edge value of the block fits in int32 — then each lane's value, its float conversion, the
// division and the depth are the scalar operations bit for bit: blocks of 2 to 8 pixels of a
// triangle under 64 px in one register (most bins of a dense mesh), larger blocks eight pixels of
// a row per step; it falls back to the plain loop otherwise (single pixels, edge values beyond
// int32 on large triangles, builds without AVX2).
#pragma once

#include <cstdint>

#include "raster/setup.h"

namespace aq::raster {

//! The fragment a pixel of a tile shows: the setup chunk and the setup index in it.
struct TileRef {
    std::uint32_t chunk, tri;
};

//! Which loop depth_test_triangle runs (tests compare them; the result is the same).
enum class VisibilitySchedule { Fast, Plain };

//! Depth-tests triangle t at the pixels [x0, x1] x [y0, y1] (inside t's bounds and inside the block
//! whose top-left pixel is (X0, Y0); zbuf and ids hold that block, row-major with row stride
//! `stride`): where the pixel is inside t and t's depth there is less than zbuf, zbuf takes the
//! depth and ids takes `ref`. No alpha test (callers test alpha-masked triangles per pixel).
void depth_test_triangle(const TriSetup& t, int X0, int Y0, int stride, int x0, int x1, int y0, int y1,
                         float* zbuf, TileRef* ids, TileRef ref,
                         VisibilitySchedule schedule = VisibilitySchedule::Fast);

}  // namespace aq::raster
