// raster/resolve.cpp — SSAA resolve (docs/raster.md "Supersampling").
#include "raster/raster_internal.h"

namespace aq::raster::detail {

// ---- SSAA resolve (docs/raster.md "Supersampling") -------------------------------------------

Targets resolve(const Targets& hi, int K, int W, int H, float bg_depth, const Exec& ex) {
    Targets lo = allocate_targets(W, H, bg_depth);
    const int HW = W * K;
    const float inv_total = 1.0f / float(K * K);
    const TargetPtrsOf<const float> hp = pointers(hi);
    const float *hc = hp.color(), *hd = hp.depth(), *hn = hp.normal(), *hid = hp.id(), *hdf = hp.diffuse(),
                *hsp = hp.specular();
    const float* hctrl[4] = {hp.ctrl(0), hp.ctrl(1), hp.ctrl(2), hp.ctrl(3)};
    TargetPtrs lp = pointers(lo);
    Exec e = ex;
    for_each_tile(e, Roi{0, 0, W, H}, [&](Roi r) {
        std::vector<std::size_t> cov;
        std::vector<float> ids;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) {
                cov.clear();
                ids.clear();
                for (int sy = 0; sy < K; ++sy)
                    for (int sx = 0; sx < K; ++sx) {
                        const std::size_t j = std::size_t(y * K + sy) * HW + (x * K + sx);
                        ids.push_back(hid[j]);
                        if (hc[4 * j + 3] > 0.0f) cov.push_back(j);
                    }
                const std::size_t i = std::size_t(y) * W + x;
                // object_id: majority of all K*K samples (background 0 included); ties go to the
                // value met first in row-major sample order.
                float best = ids[0];
                int best_n = 0;
                for (std::size_t a = 0; a < ids.size(); ++a) {
                    int n = 0;
                    for (std::size_t b2 = 0; b2 < ids.size(); ++b2) n += ids[b2] == ids[a];
                    if (n > best_n) {
                        best_n = n;
                        best = ids[a];
                    }
                }
                lp.id()[i] = best;
                if (cov.empty()) continue;  // background values already in place
                const float n = float(cov.size());
                const float alpha = float(cov.size()) * inv_total;
                glm::vec3 c(0), nn(0);
                glm::vec3 cc[4] = {glm::vec3(0), glm::vec3(0), glm::vec3(0), glm::vec3(0)};
                float dmin = std::numeric_limits<float>::infinity(), df = 0, sp = 0;
                for (std::size_t j : cov) {
                    c = c + glm::vec3(hc[4 * j], hc[4 * j + 1], hc[4 * j + 2]);
                    for (int k = 0; k < 4; ++k)
                        cc[k] = cc[k] + glm::vec3(hctrl[k][4 * j], hctrl[k][4 * j + 1], hctrl[k][4 * j + 2]);
                    nn = nn + glm::vec3(hn[3 * j], hn[3 * j + 1], hn[3 * j + 2]);
                    dmin = std::min(dmin, hd[j]);
                    df = df + hdf[j];
                    sp = sp + hsp[j];
                }
                c = c / n;
                lp.color()[4 * i] = c.x; lp.color()[4 * i + 1] = c.y; lp.color()[4 * i + 2] = c.z;
                lp.color()[4 * i + 3] = alpha;
                for (int k = 0; k < 4; ++k) {
                    const glm::vec3 v = cc[k] / n;
                    float* q = lp.ctrl(k) + 4 * i;
                    q[0] = v.x; q[1] = v.y; q[2] = v.z; q[3] = alpha;
                }
                nn = normalize3(nn / n);
                lp.normal()[3 * i] = nn.x; lp.normal()[3 * i + 1] = nn.y; lp.normal()[3 * i + 2] = nn.z;
                lp.depth()[i] = dmin;
                lp.diffuse()[i] = df / n;
                lp.specular()[i] = sp / n;
            }
    });
    return lo;
}

}  // namespace aq::raster::detail
