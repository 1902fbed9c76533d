// raster/foliage_cache.cpp — the LD06 foliage abstraction through the content cache.
#include "raster/foliage.h"

#include <cstdio>

#include "scenes/scene_archive.h"

namespace aq::raster {

static_assert(sizeof(AbstractedScene) == 536 && sizeof(ImplicitSurface) == 96,
              "AbstractedScene or ImplicitSurface changed: archive its new members below, then update these sizes");

template <class Ar>
void fields(Ar& ar, ImplicitSurface& s) {
    ar(s.positions, s.normals, s.indices, s.grid_nodes, s.field_max, s.threshold, s.inside_fraction);
}
template <class Ar>
void fields(Ar& ar, AbstractedScene& a) {
    ar(a.scene, a.surface, a.height, a.radius, a.foliage_points, a.foliage_triangles, a.leaf_share, a.threshold, a.crown_ratio,
       a.abstracted, a.texture_technique, a.surface_object_id, a.foliage_object_id, a.surface_material, a.foliage_material);
}

std::string foliage_params_key(const FoliageParams& p) {
    // Every parameter by value (%a: exact floats), never the struct's bytes (padding).
    char params[200];
    std::snprintf(params, sizeof params, "abstract=%d T=%a r=%a relative=%d cells=%d fit=%d technique=%s", int(p.abstract),
                  double(p.threshold), double(p.radius), int(p.relative), p.cells_per_radius, int(p.fit), technique_name(p.technique));
    return params;
}

std::shared_ptr<const AbstractedScene> abstract_foliage_cached(const scene::Scene& sc, const FoliageParams& p, const Exec& ex,
                                                               std::vector<std::string>* warnings, const cache::Store* store,
                                                               const std::string& scene_key, std::vector<std::string>* notes) {
    if (!store || scene_key.empty()) return abstract_foliage(sc, p, ex, warnings);
    const std::string key = cache::key({"foliage", scene_key, foliage_params_key(p)});
    std::string problem;
    if (std::optional<cache::Entry> e = store->find("foliage", key, &problem)) {
        std::vector<std::string> w;
        auto a = std::make_shared<AbstractedScene>();
        const std::string bad = store->read("foliage", key, *e, [&](archive::Reader& r) {
            r(w, *a);
            return true;
        });
        if (bad.empty()) {
            if (warnings) warnings->insert(warnings->end(), w.begin(), w.end());
            return a;
        }
        if (notes) notes->push_back(bad);
    } else if (!problem.empty() && notes) {
        notes->push_back(problem);
    }
    std::vector<std::string> w;
    std::shared_ptr<const AbstractedScene> a = abstract_foliage(sc, p, ex, &w);
    const std::string why = store->store("foliage", key, [&](archive::Writer& wr) { wr(w, *a); });
    if (!why.empty() && notes) notes->push_back(why);
    if (warnings) warnings->insert(warnings->end(), w.begin(), w.end());
    return a;
}

}  // namespace aq::raster
