// raster/binning.cpp — vertex stage, chunked triangle setup and binning (docs/raster.md "Tiles, traversal, determinism"): setups are produced per chunk of consecutive triangles and bins list them per chunk, so a tile visits triangles in submission order.
#include "raster/raster_internal.h"

#include <algorithm>

#include <tbb/task_arena.h>

#include "raster/tiles.h"

namespace aq::raster::detail {

const scene::Material& default_material() {
    static const scene::Material m;
    return m;
}

namespace {

// Calls f(inst, prim) for every primitive prepare draws, in submission order (instances, then
// their mesh's primitives), counting instances whose mesh is missing.
template <class F>
void for_each_drawn(const scene::Scene& sc, const DrawFilter* filter, std::size_t* bad_mesh, F&& f) {
    for (const scene::Instance& inst : sc.instances) {
        if (inst.mesh < 0 || inst.mesh >= int(sc.meshes.size())) {
            if (bad_mesh) ++*bad_mesh;
            continue;
        }
        for (const scene::Primitive& p : sc.meshes[inst.mesh].primitives) {
            if (p.positions.empty() || p.indices.size() < 3) continue;
            if (filter && !(*filter)(inst, p)) continue;
            f(inst, p);
        }
    }
}

// fr.draws: one per drawn primitive, its buffers sized (reusing the previous frame's: every
// element is rewritten before it is read), material resolved, constant base colour computed.
void collect_draws(Frame& fr, const scene::Scene& sc, const DrawFilter* filter, std::vector<std::string>* warnings) {
    std::vector<DrawVertices> old_draws = std::move(fr.draws);
    fr.draws.clear();
    std::size_t next_draw = 0, bad_material = 0, bad_mesh = 0, missing_tangents = 0;
    for_each_drawn(sc, filter, &bad_mesh, [&](const scene::Instance& inst, const scene::Primitive& p) {
        DrawVertices dv = next_draw < old_draws.size() ? std::move(old_draws[next_draw++]) : DrawVertices{};
        dv.prim = &p;
        if (p.material >= 0 && p.material < int(sc.materials.size())) {
            dv.mat = &sc.materials[p.material];
        } else {
            dv.mat = &default_material();
            ++bad_material;
        }
        dv.object_id = inst.object_id;
        const std::size_t n = p.positions.size();
        // The base colour is the draw's constant when interpolate() gives every fragment
        // COLOR_0 = 1 and no texture colour: computed here once, from such a fragment.
        dv.const_base = p.colors.size() != n && (p.uv0.size() != n || !texture_of(fr.ctx, dv.mat->base_color_texture));
        if (dv.const_base) dv.base = base_color_working(fr.ctx, *dv.mat, FragmentInput{});
        dv.clip.resize(n);
        dv.view.resize(n);
        dv.snap.resize(n);
        dv.view_tangent.clear();
        if (p.tangents.size() == n) dv.view_tangent.resize(n);
        else if (dv.mat->normal_texture.texture >= 0) ++missing_tangents;
        fr.draws.push_back(std::move(dv));
    });
    if (bad_mesh) warnings->push_back(std::to_string(bad_mesh) + " instance(s) reference a missing mesh: skipped");
    if (bad_material)
        warnings->push_back(std::to_string(bad_material) + " primitive(s) reference a missing material: default material used");
    if (missing_tangents)
        warnings->push_back(std::to_string(missing_tangents) + " primitive(s) with a normal map have no tangents: normal map ignored");
}

// The vertex stage: per-draw matrices (float, computed once; docs/raster.md), vertices in jobs of
// kVertexGrain.
void transform_draws(Frame& fr, const scene::Scene& sc, const glm::mat4& view, const DrawFilter* filter, bool parallel) {
    struct Job {
        std::uint32_t draw;
        std::size_t begin, end;
    };
    std::vector<Job> jobs;
    std::vector<glm::mat4> mv(fr.draws.size());
    std::vector<glm::mat3> nm(fr.draws.size());
    std::size_t d = 0;
    for_each_drawn(sc, filter, nullptr, [&](const scene::Instance& inst, const scene::Primitive& p) {
        mv[d] = view * inst.world;
        nm[d] = glm::transpose(glm::inverse(glm::mat3(mv[d])));
        for (std::size_t b = 0; b < p.positions.size(); b += kVertexGrain)
            jobs.push_back({std::uint32_t(d), b, std::min(p.positions.size(), b + kVertexGrain)});
        ++d;
    });
    run_for(parallel, jobs.size(), [&](std::size_t j) {
        const Job& jb = jobs[j];
        transform_vertices(fr.fp, mv[jb.draw], nm[jb.draw], fr.draws[jb.draw], jb.begin, jb.end);
    });
}

// fr.chunks: consecutive triangles of the submission sequence (schedule only: a tile visits its
// triangles in submission order however they are chunked): large frames in kChunkTris chunks,
// small ones in about kChunksPerThread per thread. The previous frame's chunks are reused, emptied.
void make_chunks(Frame& fr, bool parallel) {
    std::vector<Chunk> old_chunks = std::move(fr.chunks);
    fr.chunks.clear();
    std::size_t next_chunk = 0, total_tris = 0;
    for (const DrawVertices& dv : fr.draws) total_tris += dv.prim->indices.size() / 3;
    const std::size_t workers = parallel ? std::size_t(std::max(1, tbb::this_task_arena::max_concurrency())) : 1;
    const std::uint32_t chunk_tris = std::uint32_t(
        std::clamp<std::size_t>(total_tris / (workers * kChunksPerThread) + 1, kMinChunkTris, kChunkTris));
    for (std::uint32_t d = 0; d < fr.draws.size(); ++d) {
        const std::uint32_t ntri = std::uint32_t(fr.draws[d].prim->indices.size() / 3);
        for (std::uint32_t b = 0; b < ntri;) {
            if (fr.chunks.empty() || fr.chunks.back().size == chunk_tris) {
                if (next_chunk < old_chunks.size()) {
                    Chunk& r = fr.chunks.emplace_back(std::move(old_chunks[next_chunk++]));
                    r.segments.clear();
                    r.size = 0;
                    r.tris.clear();
                    r.clips.clear();
                    r.bin_offsets.clear();
                    r.bin_items.clear();
                    r.fine_offsets.clear();
                    r.fine_items.clear();
                    r.micro.clear();
                    r.bounds.clear();
                    r.bin_bounds.clear();
                    r.fine_bounds.clear();
                    r.counters = SetupCounters{};
                } else {
                    fr.chunks.emplace_back();
                }
            }
            Chunk& c = fr.chunks.back();
            const std::uint32_t e = std::min(ntri, b + (chunk_tris - c.size));
            c.segments.push_back({d, b, e});
            c.size += e - b;
            b = e;
        }
    }
}

// One chunk's setup and binning in one pass: (tile, setup index) pairs, then the counting sort by
// tile (raster/tiles.h add_to_bins, sort_bins: each tile's list stays in submission order). The
// 104-byte setups are written once and not re-read here.
void setup_and_bin(Frame& fr, Chunk& c) {
    const int ntiles = fr.grid.count();
    std::vector<std::uint64_t>& pairs = c.pairs;
    std::vector<std::uint64_t>& fine = c.fine_pairs;  // the sub-pixel setups (coverage pass only)
    pairs.clear();
    fine.clear();
    pairs.reserve(c.size);
    c.bin_offsets.assign(std::size_t(ntiles) + 1, 0);
    c.fine_offsets.assign(fr.sopt.keep_subpixel ? std::size_t(ntiles) + 1 : 0, 0);
    // An item into the tiles of r: the traversal's bins, or the sub-pixel ones.
    auto bin_item = [&](const PixelRect& r, bool sub, std::uint32_t item) {
        add_to_bins(fr.grid.tiles_x, {r.x0, r.y0, r.x1, r.y1}, item, (sub ? c.fine_offsets : c.bin_offsets).data(),
                    sub ? fine : pairs);
    };
    for (const Chunk::Segment& sg : c.segments) {
        const DrawVertices& dv = fr.draws[sg.draw];
        for (std::uint32_t t = sg.begin; t < sg.end;) {
            const std::uint32_t te = std::min(sg.end, t + kSetupBatch);
            std::size_t k = c.tris.size(), km = c.micro.size();
            setup_triangles(dv, sg.draw, t, te, fr.fp.vp, fr.sopt, c.tris, c.clips, c.counters,
                            fr.sopt.keep_subpixel ? &c.micro : nullptr);
            t = te;
            // Compact sub-pixel records: fine bins by their coverage bounds (tagged items).
            for (; km < c.micro.size(); ++km) {
                const SubpixelTri& m = c.micro[km];
                bin_item({m.x0, m.y0, m.x1, m.y1}, true, std::uint32_t(km) | Chunk::kMicroItem);
            }
            for (; k < c.tris.size(); ++k) {
                const TriSetup& st = c.tris[k];
                // The tiles of the pixel-centre bounds (the traversal's), or with keep_subpixel
                // of the pixels whose samples it may cover (the coverage pass's; they hold the
                // pixel-centre bounds, setup.h). A sub-pixel triangle that can cover no sample
                // is not binned.
                PixelRect r{st.x0, st.y0, st.x1, st.y1};
                if (fr.sopt.keep_subpixel) {
                    r = coverage_bounds(st, fr.fp.vp.width, fr.fp.vp.height);
                    c.bounds.push_back({std::int16_t(r.x0), std::int16_t(r.y0), std::int16_t(r.x1), std::int16_t(r.y1)});
                }
                bin_item(r, st.subpixel(), std::uint32_t(k));
            }
        }
    }
    // With keep_subpixel each entry's bounds go beside it (read in setup order here, so that the
    // coverage pass reads them in bin order instead of one scattered load per entry).
    auto sort = [&](std::vector<std::uint32_t>& offsets, std::vector<std::uint32_t>& items,
                    std::vector<Chunk::Bounds>& bounds, const std::vector<std::uint64_t>& ps) {
        if (!fr.sopt.keep_subpixel) {
            sort_bins(ntiles, offsets, items, ps, [](std::uint32_t, std::uint32_t) {});
            return;
        }
        bounds.resize(ps.size());
        sort_bins(ntiles, offsets, items, ps, [&](std::uint32_t at, std::uint32_t item) {
            if (item & Chunk::kMicroItem) {
                const SubpixelTri& m = c.micro[item & ~Chunk::kMicroItem];
                bounds[at] = {m.x0, m.y0, m.x1, m.y1};
            } else {
                bounds[at] = c.bounds[item];
            }
        });
    };
    sort(c.bin_offsets, c.bin_items, c.bin_bounds, pairs);
    if (!c.fine_offsets.empty()) sort(c.fine_offsets, c.fine_items, c.fine_bounds, fine);
}

// What setup dropped, as warnings; the counts on stderr when profiling.
void report_setup(const Frame& fr, const PhaseTimer& timer, std::vector<std::string>* warnings) {
    SetupCounters total;
    std::size_t nsetup = 0, nbinned = 0;
    for (const Chunk& c : fr.chunks) {
        total.add(c.counters);
        nsetup += c.tris.size() + c.micro.size();
        nbinned += c.bin_items.size();
    }
    if (timer.on) std::fprintf(stderr, "  raster triangles set up %zu, bin entries %zu\n", nsetup, nbinned);
    if (total.non_finite)
        warnings->push_back(std::to_string(total.non_finite) + " triangle(s) with non-finite vertex positions dropped");
    if (total.bad_index)
        warnings->push_back(std::to_string(total.bad_index) + " triangle(s) with out-of-range indices dropped");
    if (total.clip_unstable)
        warnings->push_back(std::to_string(total.clip_unstable) +
                            " triangle(s) dropped: clipping produced non-finite or out-of-range vertices");
}

}  // namespace

// Vertex stage and chunked setup (+ binning on the fast path).
void prepare(Frame& fr, const scene::Scene& sc, const scene::Camera& cam, bool parallel, bool bin,
             std::vector<std::string>* warnings, PhaseTimer& timer, const DrawFilter* filter) {
    collect_draws(fr, sc, filter, warnings);
    transform_draws(fr, sc, cam.view, filter, parallel);
    timer.lap("vertex");
    make_chunks(fr, parallel);
    run_for(parallel, fr.chunks.size(), [&](std::size_t ci) {
        Chunk& c = fr.chunks[ci];
        c.tris.reserve(c.size);
        if (bin) {
            setup_and_bin(fr, c);
            return;
        }
        for (const Chunk::Segment& sg : c.segments)
            for (std::uint32_t t = sg.begin; t < sg.end; ++t)
                setup_triangle(fr.draws[sg.draw], sg.draw, t, fr.fp.vp, fr.sopt, c.tris, c.clips, c.counters);
    });
    report_setup(fr, timer, warnings);
}

}  // namespace aq::raster::detail
