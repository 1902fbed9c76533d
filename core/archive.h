// core/archive.h — binary (de)serialisation for the content cache (core/cache.h): one `fields`
// function per struct, read by both directions.
//
// A struct is archived by an overload found by argument-dependent lookup,
//     template <class Ar> void fields(Ar& ar, Material& m) { ar(m.name, m.base_color, ...); }
// which the Writer calls on a const object (through a const_cast: it only reads) and the Reader
// on the object it fills. Trivially copyable values are their bytes, host order (an entry is only
// read by the binary that wrote it: its key names the build, core/cache.h); strings, vectors, maps,
// optionals and ImageF carry their sizes. The Reader checks every size against the bytes left
// before it allocates, so a damaged entry is an aq::Error, never a crash or a huge allocation.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "core/image.h"

namespace aq::archive {

//! Receives the bytes a Writer produces (a file, core/cache.cpp).
struct Sink {
    virtual ~Sink() = default;
    virtual void write(const void* data, std::size_t bytes) = 0;
};

template <class T>
inline constexpr bool kRaw = std::is_trivially_copyable_v<T> && !std::is_pointer_v<T>;

template <class T>
struct IsVector : std::false_type {};
template <class T, class A>
struct IsVector<std::vector<T, A>> : std::true_type {};

class Writer {
public:
    explicit Writer(Sink& sink) : sink_(sink) {}
    template <class... T>
    void operator()(const T&... v) {
        (put(v), ...);
    }
    void bytes(const void* p, std::size_t n) {
        if (n) sink_.write(p, n);
    }

private:
    void count(std::size_t n) {
        const std::uint64_t c = n;
        bytes(&c, sizeof c);
    }
    template <class T>
    void put(const T& v) {
        if constexpr (kRaw<T>) {
            bytes(&v, sizeof v);
        } else if constexpr (std::is_same_v<T, std::string>) {
            count(v.size());
            bytes(v.data(), v.size());
        } else if constexpr (IsVector<T>::value) {
            count(v.size());
            if constexpr (kRaw<typename T::value_type>)
                bytes(v.data(), v.size() * sizeof(typename T::value_type));
            else
                for (const auto& e : v) put(e);
        } else if constexpr (std::is_same_v<T, ImageF>) {
            const std::int32_t s[3] = {v.width(), v.height(), v.channels()};
            bytes(s, sizeof s);
            bytes(v.data(), v.num_values() * sizeof(float));
        } else {
            fields(*this, const_cast<T&>(v));  // NOLINT: the writer only reads
        }
    }
    template <class T, std::size_t N>
    void put(const std::array<T, N>& a) {
        for (const auto& e : a) put(e);
    }
    template <class T>
    void put(const std::optional<T>& o) {
        put(std::uint8_t(o.has_value()));
        if (o) put(*o);
    }
    template <class K, class V>
    void put(const std::map<K, V>& m) {
        count(m.size());
        for (const auto& [k, v] : m) put(k), put(v);
    }

    Sink& sink_;
};

//! Delivers the bytes a Reader reads, in order (a file, core/cache.cpp; memory).
struct Source {
    virtual ~Source() = default;
    //! Copies the next n bytes to out; called only with n <= left().
    virtual void read(void* out, std::size_t n) = 0;
    virtual std::size_t left() const = 0;
};

//! Bytes in memory.
class MemorySource final : public Source {
public:
    MemorySource(const void* data, std::size_t size) : p_(static_cast<const unsigned char*>(data)), left_(size) {}
    void read(void* out, std::size_t n) override {
        if (n) std::memcpy(out, p_, n);
        p_ += n;
        left_ -= n;
    }
    std::size_t left() const override { return left_; }

private:
    const unsigned char* p_;
    std::size_t left_;
};

//! Reads what a Writer wrote. Throws aq::Error ("cache entry: ...") on any size beyond the bytes
//! left, before allocating for it.
class Reader {
public:
    explicit Reader(Source& src) : src_(src) {}
    template <class... T>
    void operator()(T&... v) {
        (get(v), ...);
    }
    std::size_t left() const { return src_.left(); }
    void bytes(void* out, std::size_t n) {
        need(n);
        src_.read(out, n);
    }

private:
    void need(std::size_t n) const {
        if (n > left()) throw Error("cache entry: truncated (" + std::to_string(n) + " bytes wanted, " + std::to_string(left()) + " left)");
    }
    //! An element count, checked against the bytes left at `min_bytes` per element.
    std::size_t count(std::size_t min_bytes) {
        std::uint64_t c = 0;
        bytes(&c, sizeof c);
        if (c > left() / (min_bytes ? min_bytes : 1)) throw Error("cache entry: count " + std::to_string(c) + " exceeds its bytes");
        return std::size_t(c);
    }
    template <class T>
    void get(T& v) {
        if constexpr (kRaw<T>) {
            bytes(&v, sizeof v);
        } else if constexpr (std::is_same_v<T, std::string>) {
            v.resize(count(1));
            bytes(v.data(), v.size());
        } else if constexpr (IsVector<T>::value) {
            using E = typename T::value_type;
            if constexpr (kRaw<E>) {
                v.resize(count(sizeof(E)));
                bytes(v.data(), v.size() * sizeof(E));
            } else {
                v.clear();
                v.resize(count(1));
                for (auto& e : v) get(e);
            }
        } else if constexpr (std::is_same_v<T, ImageF>) {
            std::int32_t s[3];
            bytes(s, sizeof s);
            if (s[0] == 0 && s[1] == 0 && s[2] == 0) {
                v = ImageF();
                return;
            }
            check_image_size(s[0], s[1], "cache entry image");
            if (s[2] < 1 || s[2] > 4) throw Error("cache entry: image of " + std::to_string(s[2]) + " channels");
            const std::size_t n = std::size_t(s[0]) * std::size_t(s[1]) * std::size_t(s[2]);
            need(n * sizeof(float));
            v = ImageF(s[0], s[1], s[2], kUninitialized);
            bytes(v.data(), n * sizeof(float));
        } else {
            fields(*this, v);
        }
    }
    template <class T, std::size_t N>
    void get(std::array<T, N>& a) {
        for (auto& e : a) get(e);
    }
    template <class T>
    void get(std::optional<T>& o) {
        std::uint8_t has = 0;
        get(has);
        if (has > 1) throw Error("cache entry: bad optional flag");
        if (!has) {
            o.reset();
            return;
        }
        o.emplace();
        get(*o);
    }
    template <class K, class V>
    void get(std::map<K, V>& m) {
        m.clear();
        const std::size_t n = count(1);
        for (std::size_t i = 0; i < n; ++i) {
            K k{};
            get(k);
            get(m[k]);
        }
    }

    Source& src_;
};

}  // namespace aq::archive
