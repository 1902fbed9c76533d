// app/manifest.h — provenance manifests (issue 14 item 1; docs/provenance.md): how each output
// image was made, and `aquarelle reproduce` to render it again and say whether it is identical.
//
// Every image `aquarelle render` writes to --out gets a sidecar `IMAGE.json` (e.g.
// `s_0003.png.json`) and the same manifest, without the "outputs" section, embedded in every file
// of that frame (the standard ImageDescription attribute: PNG tEXt "Description", EXR header),
// since a file cannot hold its own hash. A manifest holds: the build (version, git commit, compiler,
// determinism flags), the render request of this one image (scene, style, --set/--variant, size,
// frame or sweep value, control mode, working space, ...), every file the process read with its
// SHA-256, the compiled pipeline (every pass and step, variant, resolved parameter value, ports),
// and the SHA-256 of every file written for the image. It holds nothing that depends on the
// thread count, the traversal (--reference), sharding or the output folder (output files are named
// relative to the sidecar's folder), so equal renders give byte-equal manifests.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/render_job.h"

namespace aq::app {

inline constexpr int kManifestFormat = 1;  //!< "aquarelle_manifest" value this build writes and reads

//! A file written for one image: its path, the target it holds ("" for the --out image) and its
//! kind ("out", "exr" for --targets, "png" for --targets-png).
struct OutputFile {
    std::string path, target, kind;
};

//! The sidecar path of an image: IMAGE + ".json".
std::string manifest_path(const std::string& image_path);

//! The manifest of one rendered image, without "outputs": what is embedded in the files.
nlohmann::json manifest_core(const RenderJob& job, const RenderedImage& img);

//! core + "outputs": one entry per file (name relative to the sidecar's folder, target, kind,
//! SHA-256), in the order of `files` (sha256[i] belongs to files[i]).
nlohmann::json manifest_with_outputs(nlohmann::json core, const std::string& sidecar_path,
                                     const std::vector<OutputFile>& files, const std::vector<std::string>& sha256);

//! The one text form of a manifest (2-space indentation, trailing newline).
std::string manifest_text(const nlohmann::json& manifest);

//! `aquarelle reproduce` (docs/provenance.md "Reproducing an image").
struct ReproduceOptions {
    std::string manifest;
    //! Render into this folder and keep it: it must be new or empty (never the manifest's own
    //! folder); else a temporary folder, removed on every exit.
    std::string keep_dir;
    //! The user's own --allow-outside-files: a manifest whose request has it is refused without.
    bool allow_outside_files = false;
    int threads = 0;
    bool any_version = false;  //!< render even when the build differs from the manifest's
    bool quiet = false;
};

//! Bounds of what a manifest may list (docs/limits.md): a render reads a scene file, a style, a
//! model with its buffers and textures, a paper: tens of files; it writes the image and, with
//! --targets/--targets-png, two files per target: at most a few hundred.
inline constexpr std::size_t kMaxManifestInputs = 4096;
inline constexpr std::size_t kMaxManifestOutputs = 4096;

//! Exit status of reproduce when something differs (0: identical; 1: could not reproduce).
inline constexpr int kReproduceDiffers = 3;

struct ReproduceResult {
    int status = 0;                  //!< 0 identical, kReproduceDiffers otherwise
    std::vector<std::string> lines;  //!< the report, one line each ("identical" when status 0)
};

//! Checks the manifest (format, build, its lists bounded and well formed, every input present,
//! every output file beside it with its recorded SHA-256, the request strictly typed and within
//! the command line's ranges), renders the image again with the recorded request and compares:
//! the files the render read (the same set, the same SHA-256), the pipeline, and every output's
//! SHA-256 both ways (none missing, none extra); for the first differing output, the pixel metrics
//! of core/compare.h. Status 0 ("identical") only when all of that holds. Throws aq::Error when the
//! image cannot be reproduced at all (not a manifest, a malformed or out-of-range field, another
//! build without any_version, a missing input, --allow-outside-files not given again, a --keep
//! folder that is not new or empty).
ReproduceResult reproduce(const ReproduceOptions& options, const Reporter& report);

}  // namespace aq::app
