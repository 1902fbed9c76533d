// core/cache.h — the content-addressed cache of repeated work (issue 48 item 5): loaded scenes
// (geometry, decoded and mip-mapped textures) and abstracted LD06 foliage, kept between runs so
// that rendering the same asset again with other parameters skips the work that does not depend
// on them (docs/cache.md).
//
// An entry is one file `<dir>/<kind>-<key>.aqc`, the key the SHA-256 of everything that shaped
// it (cache::key). Written to a temporary file in the same folder and renamed into place, so a
// reader sees a whole entry or none, whatever runs at once (shards, a killed process); its
// header carries the payload's size and CRC-64, so a damaged entry is detected, reported, deleted
// and recomputed — never used. Reading an entry is optional work: any failure (folder not
// writable, disk full, damaged entry) costs only the time it saves. The folder holds at most
// Config::max_bytes: after each write the least recently used entries (modification time, touched
// on every hit) are deleted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
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

//! A found entry: its payload, mapped read-only while the Entry lives.
class Entry {
public:
    Entry(const unsigned char* map, std::size_t map_bytes, std::size_t header_bytes);
    Entry(Entry&& o) noexcept;
    Entry& operator=(Entry&&) = delete;
    Entry(const Entry&) = delete;
    ~Entry();
    archive::Reader reader() const { return {map_ + header_, size_ - header_}; }
    std::size_t payload_bytes() const { return size_ - header_; }

private:
    const unsigned char* map_;
    std::size_t size_, header_;
};

class Store {
public:
    explicit Store(Config c);
    const Config& config() const { return c_; }
    //! The entry of `kind` and `key`, or nullopt: absent, or damaged (then deleted, and *problem
    //! says why when given). A hit marks the entry as used now (LRU).
    std::optional<Entry> find(const std::string& kind, const std::string& key, std::string* problem = nullptr) const;
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
