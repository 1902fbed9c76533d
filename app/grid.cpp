// app/grid.cpp — see grid.h.
#include "app/grid.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "app/cli_args.h"
#include "app/visualize.h"
#include "core/build_info.h"
#include "core/compare.h"
#include "core/hash.h"
#include "core/input.h"
#include "core/io.h"
#include "core/json_file.h"
#include "core/oiio.h"

namespace aq::app {

namespace fs = std::filesystem;

namespace {

//! DejaVu Sans from Debian's fonts-dejavu-core (scripts/setup.sh installs it): a fixed file, so the
//! labels' pixels do not depend on which fonts a machine happens to have.
constexpr const char* kLabelFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
constexpr int kLabelFontSize = 15, kMinLabelFontSize = 9;
constexpr int kThumbWidth = 200;  //!< report thumbnails

//! A thumbnail kThumbWidth wide (OpenImageIO's resize filter), aspect kept.
ImageF thumbnail(const ImageF& img) {
    const int tw = std::min(kThumbWidth, img.width());
    const int th = std::max(1, int(std::lround(double(img.height()) * tw / img.width())));
    ImageF dst(tw, th, img.channels(), kUninitialized);
    if (const std::string e = oiio().resize(img.data(), img.width(), img.height(), img.channels(), tw, th, dst.data());
        !e.empty())
        throw Error("grid: thumbnail: " + e);
    return dst;
}

std::string html_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '<') o += "&lt;";
        else if (c == '>') o += "&gt;";
        else if (c == '&') o += "&amp;";
        else if (c == '"') o += "&quot;";
        else o += c;
    }
    return o;
}

std::string fmt(const char* f, double v) {
    char s[64];
    std::snprintf(s, sizeof s, f, v);
    return s;
}

//! What one rendered combination leaves for the sheet and the report.
struct CellResult {
    ImageF image;                     //!< the final image, as --out would receive it
    std::vector<double> step_ms;
    std::vector<std::string> step_labels;
    std::vector<ImageF> step_thumbs;  //!< first output of each step (report only)
    std::map<std::string, std::string> params;  //!< "step.param" -> value (report only)
};

//! What made combination k of a grid: a cell written by a shard carries it in a sidecar
//! (cell_KKKK.exr.json, with the SHA-256 of the cell's bytes), and --from-cells refuses a cell whose
//! identity is not the assembling command's (another study, size, frame, ...; docs/grid.md).
nlohmann::json cell_identity(const GridOptions& g, const std::vector<GridCell>& cells, std::size_t k) {
    const RenderOptions& o = g.base;
    const bool procedural = o.scene.rfind("procedural:", 0) == 0;
    std::error_code ec;
    const fs::path scene = procedural ? fs::path(o.scene) : fs::absolute(o.scene, ec).lexically_normal();
    return {{"aquarelle_grid_cell", 1},
            {"scene", scene.string()},
            {"style", cells[k].style},
            {"variants", cells[k].assignments.variants},
            {"sets", cells[k].assignments.sets},
            {"combination", k},
            {"combinations", cells.size()},
            {"width", o.width},
            {"height", o.height},
            {"frame", o.frame_first},
            {"control", o.neutral_control ? "neutral" : "default"},
            {"working_space", o.working_space == WorkingSpace::Linear ? "linear" : "display"},
            {"build", build_info().describe()}};
}

//! Reads cell k written by a shard, refused unless its sidecar names the same identity and the
//! SHA-256 of the bytes read.
ImageF read_cell(const std::string& path, const nlohmann::json& identity) {
    const std::string side = path + ".json";
    std::error_code ec;
    if (!fs::is_regular_file(side, ec))
        throw Error("grid --from-cells: '" + path + "' has no sidecar '" + side + "' (write the cells with this version's --shard)");
    nlohmann::json meta = read_json_file(side, "grid cell sidecar");
    if (!meta.is_object() || !meta.contains("sha256") || !meta.at("sha256").is_string())
        throw Error("grid --from-cells: '" + side + "' is not a grid cell sidecar");
    const std::string sha = meta.at("sha256").get<std::string>();
    meta.erase("sha256");
    if (meta != identity) {
        const nlohmann::json patch = nlohmann::json::diff(identity, meta);
        std::string what = patch.empty() ? "" : patch.front().value("path", std::string("/"));
        const auto ptr = nlohmann::json::json_pointer(what.empty() ? "/" : what);
        throw Error("grid --from-cells: '" + path + "' was made by another grid (" + what.substr(1) + ": " +
                    (meta.contains(ptr) ? meta.at(ptr).dump() : std::string("(absent)")) + ", this command: " +
                    (identity.contains(ptr) ? identity.at(ptr).dump() : std::string("(absent)")) +
                    "); give the axes, size and options the shards were run with");
    }
    const std::vector<unsigned char> bytes = read_input_file(path, kMaxModelFileBytes, "grid cell");
    if (sha256_hex(bytes.data(), bytes.size()) != sha)
        throw Error("grid --from-cells: '" + path + "' is not the file its sidecar describes (SHA-256 differs): "
                    "a shard was interrupted or another run wrote the folder; render that shard again");
    return decode_image(bytes.data(), bytes.size(), path);
}

//! The sidecar of a written cell: its identity and the SHA-256 of its file's bytes.
void write_cell_sidecar(const std::string& path, nlohmann::json identity, const std::string& sha) {
    identity["sha256"] = sha;
    const std::string text = identity.dump(2) + "\n";
    write_file_atomically(path + ".json", text.data(), text.size());
}

}  // namespace

std::vector<GridCell> grid_cells(const GridOptions& g, int* rows, int* columns) {
    struct Axis {
        std::string name;
        std::vector<std::string> values;
        int kind;  // 0 style, 1 variant, 2 set
    };
    std::vector<Axis> axes;
    axes.push_back({"--styles", g.styles.empty() ? std::vector<std::string>{""} : g.styles, 0});
    for (const auto& [stage, values] : g.variant_axes) axes.push_back({stage, values, 1});
    for (const auto& [param, values] : g.set_axes) axes.push_back({param, values, 2});
    long long n = 1;
    for (const Axis& a : axes) {
        if (a.values.empty()) throw cli::UsageError("grid: axis '" + a.name + "' has no values");
        std::set<std::string> seen;
        for (const std::string& v : a.values)
            if (!seen.insert(v).second) throw cli::UsageError("grid: " + a.name + ": '" + v + "' given twice");
        n *= (long long)a.values.size();
        if (n > kMaxGridCombinations)
            throw cli::UsageError("grid: more than " + std::to_string(kMaxGridCombinations) +
                                  " combinations (docs/grid.md); split the study over several grids");
    }
    int last_varying = -1;
    for (std::size_t i = 0; i < axes.size(); ++i)
        if (axes[i].values.size() > 1) last_varying = int(i);
    *columns = last_varying < 0 ? 1 : int(axes[std::size_t(last_varying)].values.size());
    *rows = int(n) / *columns;
    std::vector<GridCell> cells;
    for (long long k = 0; k < n; ++k) {
        GridCell c;
        long long rest = k;
        std::vector<std::size_t> idx(axes.size());
        for (std::size_t i = axes.size(); i-- > 0;) {  // the last axis varies fastest
            idx[i] = std::size_t(rest % (long long)axes[i].values.size());
            rest /= (long long)axes[i].values.size();
        }
        std::string label;
        for (std::size_t i = 0; i < axes.size(); ++i) {
            const std::string& v = axes[i].values[idx[i]];
            std::string part;
            if (axes[i].kind == 0) {
                c.style = v;
                part = v.empty() ? "" : v;
            } else if (axes[i].kind == 1) {
                c.assignments.variants.push_back(axes[i].name + "=" + v);
                part = axes[i].name + "=" + v;
            } else {
                c.assignments.sets.push_back(axes[i].name + "=" + v);
                part = axes[i].name + "=" + v;
            }
            if ((axes[i].values.size() > 1 || (axes[i].kind == 0 && axes.size() == 1)) && !part.empty())
                label += (label.empty() ? "" : ", ") + part;
        }
        c.assignments.label = label.empty() ? (c.style.empty() ? "default" : c.style) : label;
        cells.push_back(std::move(c));
    }
    return cells;
}

ImageF contact_sheet(const std::vector<ImageF>& cells, const std::vector<std::string>& labels, int rows, int columns) {
    if (cells.empty() || rows * columns != int(cells.size()) || labels.size() != cells.size())
        throw Error("grid: contact sheet: " + std::to_string(cells.size()) + " cells for " + std::to_string(rows) + " x " +
                    std::to_string(columns));
    const int w = cells[0].width(), h = cells[0].height();
    const int cw = w + kSheetMargin, ch = h + kSheetLabelHeight + kSheetMargin;
    ImageF sheet(columns * cw + kSheetMargin, rows * ch + kSheetMargin, 3, 1.0f);  // white
    const float black[3] = {0.0f, 0.0f, 0.0f};
    const oiio_module::Api& io = oiio();
    std::error_code ec;
    const std::string font = fs::exists(kLabelFont, ec) ? kLabelFont : "DejaVuSans";
    for (std::size_t k = 0; k < cells.size(); ++k) {
        const ImageF& c = cells[k];
        if (c.width() != w || c.height() != h || c.channels() < 3) throw Error("grid: contact sheet: cells of different sizes");
        const int x0 = kSheetMargin + int(k % std::size_t(columns)) * cw, y0 = kSheetMargin + int(k / std::size_t(columns)) * ch;
        for (int y = 0; y < h; ++y)  // the cell's RGB below its label
            for (int x = 0; x < w; ++x)
                for (int i = 0; i < 3; ++i) sheet.at(x0 + x, y0 + kSheetLabelHeight + y, i) = c.at(x, y, i);
        // The label fits the cell: a smaller size first (down to kMinLabelFontSize), then cut
        // with "..." at the end.
        std::string text = labels[k];
        int size = kLabelFontSize;
        auto width_of = [&](const std::string& t, int sz) {
            return std::max(io.text_width(t.c_str(), sz, font.c_str()), 0);
        };
        while (size > kMinLabelFontSize && width_of(text, size) > w - 4) --size;
        while (text.size() > 3 && width_of(text, size) > w - 4) text = text.substr(0, text.size() - (text.size() > 4 && text.compare(text.size() - 3, 3, "...") == 0 ? 4 : 1)) + "...";
        if (const std::string e = io.render_text(sheet.data(), sheet.width(), sheet.height(), x0 + 2,
                                                 y0 + kSheetLabelHeight - 7, text.c_str(), size, font.c_str(), black, x0,
                                                 x0 + w, y0, y0 + kSheetLabelHeight);
            !e.empty())
            throw Error("grid: cannot draw the labels (" + e + "); install fonts-dejavu-core (scripts/setup.sh)");
    }
    return sheet;
}

namespace {

//! The path of combination k's cell file in --cells DIR.
std::string cell_path(const GridOptions& g, std::size_t k) {
    char name[32];
    std::snprintf(name, sizeof name, "/cell_%04zu.exr", k);
    return g.cells_dir + name;
}

//! Throws cli::UsageError when the sheet (--out) is one of the report's own files.
void check_sheet_outside_report(const GridOptions& g) {
    std::error_code ec;
    const fs::path rdir = fs::weakly_canonical(g.report_dir, ec);
    const fs::path out = fs::weakly_canonical(g.out, ec);
    const fs::path rel = out.lexically_relative(rdir);
    const std::string first = rel.empty() ? "" : rel.begin()->string();
    if (!rel.empty() && first != ".." && (rel == "index.html" || first == "img" || first.rfind("img.", 0) == 0))
        throw cli::UsageError("grid: --out '" + g.out + "' is one of the report's own files (index.html, img*/); put the "
                              "sheet elsewhere");
}

//! Renders this shard's combinations into results (and their cells with --cells): every style's
//! job prepared (names, values and ranges of every combination checked) before any rendering
//! starts; a shard keeps only its combinations (k mod N == I).
void render_cells(const GridOptions& g, const std::vector<GridCell>& cells, std::vector<CellResult>& results,
                  const Reporter& report) {
    const bool with_report = !g.report_dir.empty();
    std::vector<RenderJob> jobs;
    std::vector<std::vector<std::size_t>> cell_of;  // per job: style index -> combination k
    for (std::size_t k = 0; k < cells.size();) {
        RenderOptions o = g.base;
        o.style = cells[k].style;
        o.style_given = !o.style.empty();
        o.keep_intermediates = with_report;
        std::vector<std::size_t> mine;
        std::size_t e = k;
        for (; e < cells.size() && cells[e].style == cells[k].style; ++e)
            if (int(e) % g.shard_count == g.shard_index) {
                o.combinations.push_back(cells[e].assignments);
                mine.push_back(e);
            }
        k = e;
        if (mine.empty()) continue;
        jobs.push_back(prepare_render(o, report));
        cell_of.push_back(std::move(mine));
    }
    if (!g.cells_dir.empty()) ensure_directory(g.cells_dir);
    if (with_report) ensure_directory(g.report_dir);
    for (std::size_t j = 0; j < jobs.size(); ++j) {
        RenderJob& job = jobs[j];
        run_render(job, [&](RenderedImage& img) {
            const std::size_t k = cell_of[j][img.style_index];
            CellResult& r = results[k];
            r.image = img.final_image();
            r.step_ms = img.step_ms;
            if (!g.cells_dir.empty())
                write_cell_sidecar(cell_path(g, k), cell_identity(g, cells, k), write_image(cell_path(g, k), r.image));
            report.progress("[grid " + std::to_string(k + 1) + "/" + std::to_string(cells.size()) + "] " +
                            cells[k].assignments.label);
            if (!with_report) return;
            const stylize::CompiledPipeline& c = job.compiled[img.style_index];
            for (const stylize::CompiledStep& s : c.steps) {
                r.step_labels.push_back(s.label);
                const std::string id = s.label.substr(0, s.label.find(' '));
                for (const auto& [p, v] : s.params) r.params[id + "." + p] = fmt("%.9g", v);
                r.step_thumbs.push_back(s.outputs.empty() || !img.targets.has(s.outputs[0])
                                            ? ImageF()
                                            : thumbnail(visualize_target(s.outputs[0], img.targets.get(s.outputs[0]))));
            }
        }, report);
    }
}

//! The "Parameters that differ between columns" rows of the report.
std::string differing_params(const std::vector<CellResult>& results) {
    std::set<std::string> keys;
    for (const CellResult& r : results)
        for (const auto& [k, v] : r.params) keys.insert(k);
    std::string diff_rows;
    for (const std::string& key : keys) {
        std::set<std::string> vals;
        for (const CellResult& r : results) vals.insert(r.params.count(key) ? r.params.at(key) : "-");
        if (vals.size() < 2) continue;
        diff_rows += "<tr><th>" + html_escape(key) + "</th>";
        for (const CellResult& r : results) diff_rows += "<td>" + html_escape(r.params.count(key) ? r.params.at(key) : "-") + "</td>";
        diff_rows += "</tr>\n";
    }
    return diff_rows;
}

//! DIR/index.html and its images in DIR/img.TAG/ (relative links: the folder is self-contained),
//! TAG from the sheet's pixels. Written as a set: the new images first, in a folder no old
//! index.html names, then the sheet, then index.html (atomically: readers see the old report or
//! the new one), then the image folders of older reports are removed.
void write_report(const GridOptions& g, const std::vector<GridCell>& cells, const std::vector<CellResult>& results,
                  const ImageF& sheet, int rows, int columns, const Reporter& report) {
    const std::string img_dir = "img." + sha256_hex(sheet).substr(0, 12);
    ensure_directory(g.report_dir + "/" + img_dir);
    const std::size_t n = cells.size(), b = std::size_t(g.baseline);
    std::size_t max_steps = 0;
    for (const CellResult& r : results) max_steps = std::max(max_steps, r.step_labels.size());
    std::string h = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Aquarelle grid</title>\n<style>"
                    "body{font-family:sans-serif;font-size:13px}table{border-collapse:collapse}td,th{border:1px solid #ccc;"
                    "padding:4px;vertical-align:top;text-align:left}img{display:block;width:200px}.b{background:#eef}"
                    "</style></head><body>\n<h1>Aquarelle grid</h1>\n<p>Scene <code>" + html_escape(g.base.scene) + "</code>, " +
                    std::to_string(n) + " combination(s), baseline: column " + std::to_string(g.baseline) + ". Contact sheet: <code>" +
                    html_escape(g.out) + "</code>. Timings are wall times of each step in this run (one run; not a benchmark).</p>\n";
    const std::string diff_rows = differing_params(results);
    h += "<table>\n<tr><th></th>";
    for (std::size_t k = 0; k < n; ++k)
        h += std::string("<th") + (k == b ? " class=\"b\"" : "") + ">" + std::to_string(k) + ": " + html_escape(cells[k].assignments.label) +
             (k == b ? " (baseline)" : "") + "</th>";
    h += "</tr>\n<tr><th>final</th>";
    for (std::size_t k = 0; k < n; ++k) {
        const std::string f = img_dir + "/c" + std::to_string(k) + "_final.png";
        write_image(g.report_dir + "/" + f, thumbnail(results[k].image));
        h += "<td><img src=\"" + f + "\"></td>";
    }
    h += "</tr>\n<tr><th>vs baseline</th>";
    for (std::size_t k = 0; k < n; ++k) {
        if (k == b) {
            h += "<td class=\"b\">baseline</td>";
            continue;
        }
        const CompareStats s = compare_images(results[b].image, results[k].image, 1.0 / 255.0);
        const std::string f = img_dir + "/c" + std::to_string(k) + "_diff.png";
        write_image(g.report_dir + "/" + f, thumbnail(diff_heatmap(results[b].image, results[k].image)));
        h += "<td><img src=\"" + f + "\">mean abs " + fmt("%.5f", s.mean_abs) + "<br>max abs " + fmt("%.4f", s.max_abs) +
             "<br>over 1/255 " + fmt("%.2f", 100.0 * s.frac_over) + " %<br>PSNR " + fmt("%.2f", s.psnr) + " dB</td>";
    }
    h += "</tr>\n";
    for (std::size_t i = 0; i < max_steps; ++i) {
        h += "<tr><th>step " + std::to_string(i) + "</th>";
        for (std::size_t k = 0; k < n; ++k) {
            const CellResult& r = results[k];
            if (i >= r.step_labels.size()) {
                h += "<td>-</td>";
                continue;
            }
            h += "<td>" + html_escape(r.step_labels[i]) + "<br>" + (i < r.step_ms.size() ? fmt("%.1f ms", r.step_ms[i]) : "");
            if (!r.step_thumbs[i].empty()) {
                const std::string f = img_dir + "/c" + std::to_string(k) + "_s" + std::to_string(i) + ".png";
                write_image(g.report_dir + "/" + f, r.step_thumbs[i]);
                h += "<img src=\"" + f + "\">";
            }
            h += "</td>";
        }
        h += "</tr>\n";
    }
    h += "</table>\n<h2>Parameters that differ between columns</h2>\n";
    if (diff_rows.empty()) {
        h += "<p>None (the columns differ in style or variant only).</p>\n";
    } else {
        h += "<table>\n<tr><th>step.param</th>";
        for (std::size_t k = 0; k < n; ++k) h += "<th>" + std::to_string(k) + "</th>";
        h += "</tr>\n" + diff_rows + "</table>\n";
    }
    h += "</body></html>\n";
    write_image(g.out, sheet);
    report.progress("wrote " + g.out + " (" + std::to_string(rows) + " x " + std::to_string(columns) + ")");
    write_file_atomically(g.report_dir + "/index.html", h.data(), h.size());
    std::error_code ec;
    for (fs::directory_iterator it(g.report_dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string n = it->path().filename().string();
        if (n != img_dir && (n == "img" || n.rfind("img.", 0) == 0) && it->is_directory()) {
            std::error_code rm;
            fs::remove_all(it->path(), rm);
        }
    }
    report.progress("wrote " + g.report_dir + "/index.html");
}

}  // namespace

void run_grid(const GridOptions& g, const Reporter& report) {
    int rows = 0, columns = 0;
    const std::vector<GridCell> cells = grid_cells(g, &rows, &columns);
    const bool with_report = !g.report_dir.empty();
    if (with_report && (g.baseline < 0 || g.baseline >= int(cells.size())))
        throw cli::UsageError("grid: --baseline " + std::to_string(g.baseline) + " is not a combination (0.." +
                              std::to_string(cells.size() - 1) + ")");
    // Every output checked before anything is written (docs/grid.md "Writing"); the report folder
    // is made once every job is prepared.
    if (with_report) check_sheet_outside_report(g);
    std::vector<CellResult> results(cells.size());
    if (g.from_cells) {
        // Assemble the sheet from the cells a (sharded) run wrote; nothing is rendered.
        for (std::size_t k = 0; k < cells.size(); ++k) results[k].image = read_cell(cell_path(g, k), cell_identity(g, cells, k));
    } else {
        render_cells(g, cells, results, report);
        if (g.shard_count > 1) return;  // a shard writes its cells only (docs/grid.md "Sharding")
    }
    std::vector<ImageF> images;
    std::vector<std::string> labels;
    for (std::size_t k = 0; k < cells.size(); ++k) {
        images.push_back(results[k].image);
        labels.push_back(cells[k].assignments.label);
    }
    const ImageF sheet = contact_sheet(images, labels, rows, columns);
    if (!with_report) {
        write_image(g.out, sheet);
        report.progress("wrote " + g.out + " (" + std::to_string(rows) + " x " + std::to_string(columns) + ")");
        return;
    }
    write_report(g, cells, results, sheet, rows, columns, report);
}

}  // namespace aq::app
