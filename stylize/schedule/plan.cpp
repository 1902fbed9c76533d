// stylize/schedule/plan.cpp — fused pairs, in-place steps and row groups of a compiled pipeline
// (plan.h).
#include "stylize/schedule/plan.h"

#include <algorithm>
#include <map>
#include <string>

namespace aq::stylize::schedule {

namespace {

// CompiledPipeline::fused_with_next: consecutive stage steps with a registered Fusion whose links
// carry every output of the first to the second alone.
void find_fusions(CompiledPipeline& c) {
    c.fused_with_next.assign(c.steps.size(), nullptr);
    for (std::size_t i = 0; i + 1 < c.steps.size(); ++i) {
        const CompiledStep& a = c.steps[i];
        const CompiledStep& b = c.steps[i + 1];
        if (a.pass || b.pass || (i > 0 && c.fused_with_next[i - 1])) continue;
        const Fusion* f = builtin_registry().fusion(a.variant->key(), b.variant->key());
        if (!f) continue;
        bool ok = true;
        std::vector<bool> linked(b.inputs.size(), false);
        for (const auto& [out, in] : f->links) {
            const int o = port_index(a.variant->outputs, out), k = port_index(b.variant->inputs, in);
            if (o < 0 || k < 0) {
                ok = false;
                break;
            }
            const std::string& t = a.outputs[std::size_t(o)];
            const auto last = c.last_read.find(t);
            ok = ok && b.inputs[std::size_t(k)] == t && t != c.output && last != c.last_read.end() && last->second == i + 1;
            linked[std::size_t(k)] = true;
        }
        // The consumer reads the producer's outputs through the links only.
        for (std::size_t k = 0; ok && k < b.inputs.size(); ++k)
            ok = linked[k] || std::find(a.outputs.begin(), a.outputs.end(), b.inputs[k]) == a.outputs.end();
        if (ok) c.fused_with_next[i] = f;
    }
}

// CompiledPipeline::in_place (after find_fusions).
void find_in_place(CompiledPipeline& c) {
    c.in_place.assign(c.steps.size(), -1);
    for (std::size_t i = 0; i < c.steps.size(); ++i) {
        const CompiledStep& r = c.steps[i];
        const StageVariant& v = *r.variant;
        if (r.pass || v.in_place_input.empty() || c.fused_with_next[i] || (i > 0 && c.fused_with_next[i - 1])) continue;
        const int k = port_index(v.inputs, v.in_place_input);  // both ports exist (Registry::add)
        const std::string& t = r.inputs[std::size_t(k)];
        const auto last = c.last_read.find(t);
        const bool intermediate = std::find(c.produced.begin(), c.produced.end(), t) != c.produced.end();
        if (!intermediate || t == c.output || last == c.last_read.end() || last->second != i ||
            std::count(r.inputs.begin(), r.inputs.end(), t) != 1)
            continue;
        c.in_place[i] = k;
    }
}

//! Halos above this many rows are not run in bands (a step reading that far is a whole-image step).
constexpr int kMaxRowHalo = 256;

// CompiledPipeline::row_groups (after find_in_place): maximal runs of two or more consecutive steps
// whose variants declare a row halo, outside fused pairs and raster passes.
void find_row_groups(CompiledPipeline& c) {
    const std::size_t n = c.steps.size();
    auto groupable = [&](std::size_t i) {
        const CompiledStep& r = c.steps[i];
        // A step in place that reads rows around its own (a positive halo) would read rows of the
        // band above already written: it runs alone, on the whole image.
        return !r.pass && r.variant->row_halo && !c.fused_with_next[i] && !(i > 0 && c.fused_with_next[i - 1]) &&
               r.variant->row_halo(r.params) >= 0 && r.variant->row_halo(r.params) <= kMaxRowHalo &&
               !(c.in_place[i] >= 0 && r.variant->row_halo(r.params) > 0);
    };
    for (std::size_t i = 0; i < n;) {
        std::size_t j = i;
        while (j < n && groupable(j)) ++j;
        if (j - i >= 2) {
            RowGroup g;
            g.first = i, g.last = j - 1;
            std::map<std::string, int> depth_of;  // in-group output -> depth of the step writing it
            for (std::size_t s = i; s < j; ++s) {
                const CompiledStep& r = c.steps[s];
                const int halo = r.variant->row_halo(r.params);
                int d = 0;
                for (const std::string& t : r.inputs)
                    if (auto it = depth_of.find(t); it != depth_of.end()) d = std::max(d, it->second + halo);
                // A step computing over its input in place (CompiledPipeline::in_place) overwrites
                // rows only after every earlier step of the group that reads that input has read
                // them for the last time: it stays behind each such reader by the reader's halo.
                if (const int k = c.in_place[s]; k >= 0)
                    for (std::size_t q = i; q < s; ++q) {
                        const CompiledStep& rq = c.steps[q];
                        if (std::find(rq.inputs.begin(), rq.inputs.end(), r.inputs[std::size_t(k)]) != rq.inputs.end())
                            d = std::max(d, g.depth[q - i] + rq.variant->row_halo(rq.params));
                    }
                for (const std::string& t : r.outputs) depth_of[t] = d;
                g.depth.push_back(d);
                g.max_depth = std::max(g.max_depth, d);
            }
            c.row_groups.push_back(std::move(g));
        }
        i = std::max(j, i + 1);
    }
}

}  // namespace

void plan(CompiledPipeline& c) {
    find_fusions(c);
    find_in_place(c);
    find_row_groups(c);
}

}  // namespace aq::stylize::schedule
