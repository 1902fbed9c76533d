// core/cache.h — the content-addressed cache of repeated work (issue 48 item 5): loaded scenes
// (geometry, decoded and mip-mapped textures) and abstracted LD06 foliage, kept between runs so
// that rendering the same asset again with other parameters skips the work that does not depend
// on them (docs/cache.md).
//
// An entry is one file `<dir>/<kind>-<key>.aqc`, the key the SHA-256 of everything that shaped
// it (cache::key). Written to a temporary file in the same folder and renamed into place, so a
// reader sees a whole entry or none, whatever runs at once (shards, a killed process); its
// header carries the payload's size and CRC-64, checked as the payload is read, so a damaged
// entry is detected, reported, deleted and recomputed — never used. Reading an entry is optional work: any failure (folder not
// writable, disk full, damaged entry) costs only the time it saves. The folder holds at most
// Config::max_bytes: after each write the least recently used entries (modification time, touched
// on every hit) are deleted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "core/archive.h"

namespace aq::cache {

//! Default size bound of the folder (AQUARELLE_CACHE_MAX_MB overrides): about twenty 4K-textured
//! models or a hundred plants.
inline constexpr std::uintmax_t kDefaultMaxBytes = std::uintmax_t(4) << 30;
//! Bumped whenever an entry's layout changes (the key also names the build: core/build_info.h).
inline constexpr std::uint32_t kFormat = 1;

struct Config {
    std::string dir;
    std::uintmax_t max_bytes = kDefaultMaxBytes;
};

//! The user's cache: AQUARELLE_CACHE_DIR, else $XDG_CACHE_HOME/aquarelle, else
//! $HOME/.cache/aquarelle; AQUARELLE_CACHE_MAX_MB for the bound. nullopt when none is known
//! (no HOME) or AQUARELLE_CACHE_DIR is "off". Throws aq::Error for a malformed AQUARELLE_CACHE_MAX_MB.
std::optional<Config> config_from_environment();

//! SHA-256 (hex) of the parts, each length-prefixed (so ("ab", "c") and ("a", "bc") differ), after
//! the cache format and the identity of the running build: the version, git commit and the
//! size and modification time of the executable or library that holds this code (a rebuilt binary
//! never reads its predecessor's entries).
std::string key(std::initializer_list<std::string_view> parts);

//! A found entry, read from its file (not mapped: the bytes land only in the objects read, so a
//! hit holds no second copy of a scene in memory). Read the payload through reader(), then call
//! finish(), which checks that all of it was read and that its CRC-64 is the header's: decoded
//! objects may be used only after finish() returned.
class Entry {
public:
    struct Impl;
    explicit Entry(std::unique_ptr<Impl> impl);
    Entry(Entry&& o) noexcept;
    Entry& operator=(Entry&&) = delete;
    ~Entry();
    archive::Reader& reader();
    //! Throws aq::Error ("cache entry: ...") when bytes are left or the CRC-64 differs.
    void finish();
    std::size_t payload_bytes() const;

private:
    std::unique_ptr<Impl> impl_;
};

class Store {
public:
    explicit Store(Config c);
    const Config& config() const { return c_; }
    //! The entry of `kind` and `key`, or nullopt: absent, or with a bad header (then deleted, and
    //! *problem says why when given). A hit marks the entry as used now (LRU).
    std::optional<Entry> find(const std::string& kind, const std::string& key, std::string* problem = nullptr) const;
    //! Reads a found entry: `read` takes the payload from the reader and returns true, or returns
    //! false having read a prefix that says the entry is not wanted (its inputs changed: a miss,
    //! nothing checked); after true, Entry::finish(). On any aq::Error (damage found while reading
    //! or by the CRC) the entry is deleted and the reason returned ("cache entry 'PATH' is damaged
    //! (...): deleted, computed again"); else empty.
    std::string read(const std::string& kind, const std::string& key, Entry& e,
                     const std::function<bool(archive::Reader&)>& read) const;
    //! Deletes an entry (absent: nothing happens).
    void remove(const std::string& kind, const std::string& key) const;
    //! Writes the entry `fill` produces, atomically, then deletes least recently used entries
    //! beyond the size bound (never the one just written, unless it alone exceeds the bound:
    //! then it is not kept). Returns an empty string, or the reason nothing was stored (the caller
    //! reports it as a warning: the cache is never needed for a correct result).
    std::string store(const std::string& kind, const std::string& key, const std::function<void(archive::Writer&)>& fill) const;
    //! The entry's path (tests).
    std::string path(const std::string& kind, const std::string& key) const;

private:
    void evict(const std::string& keep) const;
    Config c_;
};

}  // namespace aq::cache
