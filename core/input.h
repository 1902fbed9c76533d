// core/input.h — the one way Aquarelle reads a file it was given: regular files only, size-capped,
// read before parsing; a path policy for files that one input names (glTF buffers and images);
// a record of every file read so an output can never overwrite an input of the same run.
//
// Every reader of the project (glTF and GLB, scene files, style/pipeline JSON, papers, control
// textures, `compare` inputs) goes through read_input_file(), so the rules are stated once and
// documented in docs/limits.md ("Reading files").
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace aq {

//! Size caps, checked with fstat on the opened file before a byte is read (docs/limits.md).
inline constexpr std::uintmax_t kMaxModelFileBytes = 2'000'000'000;  //!< .gltf/.glb and external buffers
inline constexpr std::uintmax_t kMaxImageFileBytes = 512u << 20;     //!< an encoded image (paper, texture, compare input)
inline constexpr std::uintmax_t kMaxJsonFileBytes = 64u << 20;       //!< scene, style and pipeline files

//! One file read by this process through read_input_file() or check_input_file(): the path it
//! was first read by (absolute, lexically normalised), its size and the SHA-256 of the bytes read.
struct InputRecord {
    std::string path;
    std::uintmax_t bytes = 0;
    std::string sha256;
};

//! Reads the whole file at `path` into memory. Refuses (aq::Error "WHAT 'PATH': reason") anything
//! that is not a regular file once opened (FIFOs, devices, folders: opened non-blocking, so a FIFO
//! never blocks), files larger than max_bytes, and short reads. Records the file as an input of
//! this run (see is_input_of_run()).
//! `record`, when given, receives this read's record (path, size, SHA-256 of the bytes returned).
std::vector<unsigned char> read_input_file(const std::string& path, std::uintmax_t max_bytes, const std::string& what,
                                           InputRecord* record = nullptr);
//! The same, as text.
std::string read_input_text(const std::string& path, std::uintmax_t max_bytes, const std::string& what);

//! Checks that `path` names an existing regular file of at most max_bytes, without reading it, and
//! records it as an input of the run (for readers that must open the file themselves, e.g. formats
//! OpenImageIO reads only by name). Throws aq::Error like read_input_file().
void check_input_file(const std::string& path, std::uintmax_t max_bytes, const std::string& what);

//! Every file read so far, one record per file (by identity: dev, inode), sorted by path, so the
//! list does not depend on the order in which threads read them (provenance manifests,
//! app/manifest.h).
std::vector<InputRecord> inputs_read();

//! Collects the record of every file read while it lives, by any thread, in the order read (a
//! file read twice appears twice): what a computation depended on (the content cache, core/cache.h).
//! Captures may nest or overlap; each sees every read during its life.
class InputCapture {
public:
    InputCapture();
    ~InputCapture();
    InputCapture(const InputCapture&) = delete;
    InputCapture& operator=(const InputCapture&) = delete;
    std::vector<InputRecord> records() const;

private:
    std::vector<InputRecord> records_;
};

//! Adds `r` to the live InputCaptures: for a cache in memory that hands out what it decoded from
//! a file read earlier in the process (the paper cache), so a capture lists every file its work
//! depended on, as a fresh process would have read it.
void note_cached_input(const InputRecord& r);

//! Drops `path` from inputs_read() (it stays protected from overwriting): for files a command
//! reads about a render rather than for it (`reproduce` reading the manifest).
void forget_input_record(const std::string& path);

//! True when `path` is (the same inode as) a file read as an input by this process.
bool is_input_of_run(const std::string& path);
//! Records a file as an input of this run (readers that do not go through read_input_file()).
void note_input_of_run(const std::string& path);

//! Where files named inside a model (glTF buffer and image URIs) may be: by default inside the
//! model's own folder tree after `..`, percent-decoding and symbolic links are resolved
//! (docs/limits.md "Path policy"); `allow_outside` lifts the confinement (CLI --allow-outside-files).
struct PathPolicy {
    std::filesystem::path root;  //!< the model's folder
    bool allow_outside = false;
};
//! Empty string when `candidate` is allowed by the policy; else the reason it is refused.
std::string path_policy_violation(const PathPolicy& policy, const std::string& candidate);

}  // namespace aq
