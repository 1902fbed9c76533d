// app/grid.h — `aquarelle grid` (issue 14 item 2; docs/grid.md): the combinations of styles,
// stage variants and parameter values rendered side by side into a labelled contact sheet, and
// optionally a report folder (HTML: one column per combination, one row per pipeline step with
// thumbnails and timings, the parameters that differ, diff heatmaps and metrics against a baseline).
//
// Combinations are the cartesian product of the axes in the order given: --styles, then each
// --variant STAGE=a,b, then each --set STEP.PARAM=x,y,z. Each style's combinations share one
// G-buffer (a style's default art-direction decides its control targets, so styles do not share
// one). Layout: the last axis with more than one value runs along the columns, the others along
// the rows; combination k is cell (k / columns, k % columns).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "app/render_job.h"
#include "core/image.h"

namespace aq::app {

inline constexpr int kMaxGridCombinations = 64;  //!< more is refused before rendering (docs/grid.md)

struct GridOptions {
    RenderOptions base;  //!< scene, size, frame, control, threads, ... (style, out, targets unused)
    std::vector<std::string> styles;                                            //!< default: the scene's style
    std::vector<std::pair<std::string, std::vector<std::string>>> variant_axes;  //!< STAGE -> variants
    std::vector<std::pair<std::string, std::vector<std::string>>> set_axes;      //!< STEP.PARAM -> values
    std::string out;         //!< the contact sheet (PNG or EXR)
    std::string report_dir;  //!< the report folder, or empty
    int baseline = 0;        //!< report: the column the others are compared with
    //! --cells DIR: also write each combination's image as DIR/cell_KKKK.exr (exact floats).
    std::string cells_dir;
    //! --shard I/N: render only the combinations k with k mod N == I into --cells (no sheet).
    int shard_index = 0, shard_count = 1;
    //! --from-cells: assemble the sheet from --cells DIR (written by shards) without rendering.
    bool from_cells = false;
};

//! One combination: its style, assignments and label ("wc18, edge_darken.intensity=2").
struct GridCell {
    std::string style;
    RenderOptions::Combination assignments;
};

//! Every combination in order, and the layout. Throws cli::UsageError on malformed axes, repeated
//! values or more than kMaxGridCombinations combinations — before anything is rendered.
std::vector<GridCell> grid_cells(const GridOptions& g, int* rows, int* columns);

//! Places the cell images (same size, RGB) into a sheet of rows x columns with a label strip
//! above each (OpenImageIO text rendering, DejaVu Sans from fonts-dejavu-core).
ImageF contact_sheet(const std::vector<ImageF>& cells, const std::vector<std::string>& labels, int rows, int columns);

//! Geometry of contact_sheet(), for tests and the report.
inline constexpr int kSheetMargin = 8, kSheetLabelHeight = 24;

//! Renders the grid: the sheet to g.out, the report to g.report_dir. Throws aq::Error.
void run_grid(const GridOptions& g, const Reporter& report);

}  // namespace aq::app
