// core/cache.cpp — the content cache's folder: atomic entries with a CRC-64, LRU eviction.
#include "core/cache.h"

#include <dirent.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <isa-l/crc64.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/build_info.h"
#include "core/hash.h"

namespace aq::cache {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'A', 'Q', 'C', 'A', 'C', 'H', 'E', '\n'};
struct Header {
    char magic[8];
    std::uint32_t format;
    std::uint32_t reserved;
    std::uint64_t payload_bytes;
    std::uint64_t crc;  //!< CRC-64 (ECMA-182, reflected: ISA-L crc64_ecma_refl) of the payload
};
static_assert(sizeof(Header) == 32);
constexpr const char* kSuffix = ".aqc";
constexpr const char* kTempPrefix = ".tmp-";
//! A temporary file older than this was left by a killed writer: eviction deletes it.
constexpr auto kStaleTemp = std::chrono::hours(1);

std::string errno_text() { return std::strerror(errno); }

//! The file (executable or shared library) this code was loaded from: its size and modification
//! time name the build in every key, beside the commit (a rebuilt dirty tree keeps its commit).
std::string binary_identity() {
    static const std::string id = [] {
        const BuildInfo& b = build_info();
        std::string s = b.version + "|" + b.commit + (b.dirty ? "|dirty" : "") + "|" + b.flags;
        Dl_info info{};
        struct stat st {};
        const bool found = dladdr(reinterpret_cast<void*>(&binary_identity), &info) != 0 && info.dli_fname &&
                           ::stat(info.dli_fname, &st) == 0;
        if (found || ::stat("/proc/self/exe", &st) == 0)
            s += "|" + std::to_string(st.st_size) + "|" + std::to_string(st.st_mtim.tv_sec) + "." + std::to_string(st.st_mtim.tv_nsec);
        return s;
    }();
    return id;
}

//! Buffered writes to a file descriptor, with the running CRC of everything written.
class FileSink final : public archive::Sink {
public:
    explicit FileSink(int fd) : fd_(fd) { buf_.reserve(kBuffer); }
    void write(const void* data, std::size_t n) override {
        const auto* p = static_cast<const unsigned char*>(data);
        crc_ = crc64_ecma_refl(crc_, p, n);
        total_ += n;
        if (buf_.size() + n > kBuffer) flush();
        if (n >= kBuffer) {
            write_all(p, n);
            return;
        }
        buf_.insert(buf_.end(), p, p + n);
    }
    void flush() {
        write_all(buf_.data(), buf_.size());
        buf_.clear();
    }
    std::uint64_t crc() const { return crc_; }
    std::uint64_t total() const { return total_; }

private:
    static constexpr std::size_t kBuffer = std::size_t(1) << 20;
    void write_all(const unsigned char* p, std::size_t n) {
        while (n) {
            const ssize_t w = ::write(fd_, p, n);
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0) throw Error("cannot write: " + (w < 0 ? errno_text() : std::string("no space")));
            p += w;
            n -= std::size_t(w);
        }
    }
    int fd_;
    std::vector<unsigned char> buf_;
    std::uint64_t crc_ = 0, total_ = 0;
};

}  // namespace

std::optional<Config> config_from_environment() {
    Config c;
    const char* dir = std::getenv("AQUARELLE_CACHE_DIR");
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    const char* home = std::getenv("HOME");
    if (dir && *dir) {
        if (std::string(dir) == "off") return std::nullopt;
        c.dir = dir;
    } else if (xdg && *xdg) {
        c.dir = std::string(xdg) + "/aquarelle";
    } else if (home && *home) {
        c.dir = std::string(home) + "/.cache/aquarelle";
    } else {
        return std::nullopt;
    }
    if (const char* mb = std::getenv("AQUARELLE_CACHE_MAX_MB"); mb && *mb) {
        char* end = nullptr;
        errno = 0;
        const unsigned long long v = std::strtoull(mb, &end, 10);
        if (*end || errno || v > (std::uintmax_t(1) << 44) || mb[0] == '-')
            throw Error("AQUARELLE_CACHE_MAX_MB '" + std::string(mb) + "': expected a whole number of MiB");
        c.max_bytes = std::uintmax_t(v) << 20;
    }
    return c;
}

std::string key(std::initializer_list<std::string_view> parts) {
    std::string buf = "aquarelle-cache " + std::to_string(kFormat) + "\n" + binary_identity() + "\n";
    for (std::string_view p : parts) {
        buf += std::to_string(p.size());
        buf += ':';
        buf.append(p.data(), p.size());
    }
    return sha256_hex(buf.data(), buf.size());
}

Entry::Entry(const unsigned char* map, std::size_t map_bytes, std::size_t header_bytes)
    : map_(map), size_(map_bytes), header_(header_bytes) {}
Entry::Entry(Entry&& o) noexcept : map_(std::exchange(o.map_, nullptr)), size_(o.size_), header_(o.header_) {}
Entry::~Entry() {
    if (map_) ::munmap(const_cast<unsigned char*>(map_), size_);
}

Store::Store(Config c) : c_(std::move(c)) {}

std::string Store::path(const std::string& kind, const std::string& key) const {
    return c_.dir + "/" + kind + "-" + key + kSuffix;
}

std::optional<Entry> Store::find(const std::string& kind, const std::string& key, std::string* problem) const {
    const std::string p = path(kind, key);
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) return std::nullopt;
    struct stat st {};
    std::string bad;
    const unsigned char* map = nullptr;
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        bad = "not a regular file";
    } else if (std::size_t(st.st_size) < sizeof(Header)) {
        bad = "truncated (" + std::to_string(st.st_size) + " bytes)";
    } else {
        void* m = ::mmap(nullptr, std::size_t(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
        if (m == MAP_FAILED) {
            ::close(fd);
            return std::nullopt;  // cannot map (address space, limits): a miss, the entry may be fine
        }
        map = static_cast<const unsigned char*>(m);
        Header h;
        std::memcpy(&h, map, sizeof h);
        const std::size_t payload = std::size_t(st.st_size) - sizeof h;
        if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.format != kFormat)
            bad = "not an entry of this format";
        else if (h.payload_bytes != payload)
            bad = "truncated (" + std::to_string(payload) + " of " + std::to_string(h.payload_bytes) + " bytes)";
        else if (crc64_ecma_refl(0, map + sizeof h, payload) != h.crc)
            bad = "damaged (CRC-64 mismatch)";
    }
    if (!bad.empty()) {
        if (map) ::munmap(const_cast<unsigned char*>(map), std::size_t(st.st_size));
        ::close(fd);
        ::unlink(p.c_str());
        if (problem) *problem = "cache entry '" + p + "' is " + bad + ": deleted, computed again";
        return std::nullopt;
    }
    (void)::futimens(fd, nullptr);  // used now (LRU); a read-only cache still serves
    ::close(fd);
    return Entry(map, std::size_t(st.st_size), sizeof(Header));
}

std::string Store::store(const std::string& kind, const std::string& key,
                         const std::function<void(archive::Writer&)>& fill) const {
    std::error_code ec;
    fs::create_directories(c_.dir, ec);
    if (ec) return "not cached: folder '" + c_.dir + "' cannot be created: " + ec.message();
    std::string tmp = c_.dir + "/" + kTempPrefix + kind + "-XXXXXX";
    const int fd = ::mkostemp(tmp.data(), O_CLOEXEC);
    if (fd < 0) return "not cached: folder '" + c_.dir + "' is not writable: " + errno_text();
    std::string why;
    try {
        Header h{};
        std::memcpy(h.magic, kMagic, sizeof kMagic);
        h.format = kFormat;
        if (::write(fd, &h, sizeof h) != ssize_t(sizeof h)) throw Error("cannot write: " + errno_text());
        FileSink sink(fd);
        archive::Writer w(sink);
        fill(w);
        sink.flush();
        h.payload_bytes = sink.total();
        h.crc = sink.crc();
        if (h.payload_bytes + sizeof h > c_.max_bytes)
            throw Error("an entry of " + std::to_string(h.payload_bytes >> 20) + " MiB exceeds the bound of " +
                        std::to_string(c_.max_bytes >> 20) + " MiB");
        if (::pwrite(fd, &h, sizeof h, 0) != ssize_t(sizeof h)) throw Error("cannot write: " + errno_text());
    } catch (const std::exception& e) {
        why = e.what();
    }
    if (::close(fd) != 0 && why.empty()) why = "cannot write: " + errno_text();
    const std::string final_path = path(kind, key);
    if (why.empty() && ::rename(tmp.c_str(), final_path.c_str()) != 0) why = "cannot rename: " + errno_text();
    if (!why.empty()) {
        ::unlink(tmp.c_str());
        return "not cached in '" + c_.dir + "': " + why;
    }
    evict(final_path);
    return {};
}

void Store::evict(const std::string& keep) const {
    struct Item {
        std::int64_t mtime_ns;
        std::uintmax_t bytes;
        std::string path;
    };
    std::vector<Item> items;
    std::uintmax_t total = 0;
    const auto now = std::chrono::system_clock::now().time_since_epoch();
    const std::int64_t stale_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now - kStaleTemp).count();
    DIR* d = ::opendir(c_.dir.c_str());
    if (!d) return;
    while (const dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        const bool entry = name.size() > 4 && name.compare(name.size() - 4, 4, kSuffix) == 0;
        const bool temp = name.rfind(kTempPrefix, 0) == 0;
        if (!entry && !temp) continue;
        const std::string p = c_.dir + "/" + name;
        struct stat st {};
        if (::lstat(p.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
        const std::int64_t t = std::int64_t(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
        if (temp) {
            if (t < stale_ns) ::unlink(p.c_str());
            continue;
        }
        items.push_back({t, std::uintmax_t(st.st_size), p});
        total += std::uintmax_t(st.st_size);
    }
    ::closedir(d);
    if (total <= c_.max_bytes) return;
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
        return a.mtime_ns != b.mtime_ns ? a.mtime_ns < b.mtime_ns : a.path < b.path;
    });
    for (const Item& it : items) {
        if (total <= c_.max_bytes) break;
        if (it.path == keep) continue;
        if (::unlink(it.path.c_str()) == 0 || errno == ENOENT) total -= it.bytes;
    }
}

}  // namespace aq::cache
