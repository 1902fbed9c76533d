// core/oiio_mem_reader.h — OpenImageIO's in-memory reader with every read bounded by the buffer
// (internal to core/io.cpp; a header so tests/core/mem_reader_test.cpp can test it directly).
//
// OpenImageIO 2.4's IOMemReader::pread checks `size + size_t(offset) > buffer size`, which wraps
// for -size < offset < 0, and then copies from before the buffer: a heap-buffer-overflow found
// by CI's fuzz smoke run through a BMP whose pixel offset was -2 (fuzz/README.md finding 6).
// Here the offset is checked first and the length is clamped to what is left, with no addition
// that can overflow. It stays an IOMemReader (proxytype "memreader"): OpenImageIO's JPEG reader
// accepts only that type and reads its buffer() directly, bounded by the buffer's size.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <OpenImageIO/filesystem.h>

namespace aq::detail {

class BoundedMemReader final : public OIIO::Filesystem::IOMemReader {
public:
    BoundedMemReader(const unsigned char* bytes, std::size_t size) : IOMemReader(bytes, size) {}
    std::size_t read(void* buf, std::size_t n) override {
        const std::size_t got = pread(buf, n, m_pos);
        m_pos += int64_t(got);
        return got;
    }
    std::size_t pread(void* buf, std::size_t n, int64_t offset) override {
        const int64_t size = int64_t(m_buf.size());
        if (offset < 0 || offset >= size || n == 0) return 0;
        const std::size_t got = std::min(n, std::size_t(size - offset));
        std::memcpy(buf, m_buf.data() + offset, got);
        return got;
    }
};

}  // namespace aq::detail
