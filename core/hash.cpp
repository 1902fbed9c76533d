// core/hash.cpp
#include "core/hash.h"

#include <openssl/evp.h>

#include <cstdint>
#include <cstdio>

namespace aq {

namespace {
std::string hex(const unsigned char* d, unsigned n) {
    std::string s(n * 2, '0');
    for (unsigned i = 0; i < n; ++i) std::snprintf(&s[i * 2], 3, "%02x", d[i]);
    return s;
}
}  // namespace

std::string sha256_hex(const void* data, std::size_t bytes) {
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned n = 0;
    if (!EVP_Digest(data, bytes, md, &n, EVP_sha256(), nullptr)) throw Error("SHA-256 failed");
    return hex(md, n);
}

std::string sha256_hex(const ImageF& img) {
    EVP_MD_CTX* ctx = EVP_MD_CTX_new();
    const std::int32_t hdr[3] = {img.width(), img.height(), img.channels()};
    unsigned char md[EVP_MAX_MD_SIZE];
    unsigned n = 0;
    bool ok = ctx && EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr) &&
              EVP_DigestUpdate(ctx, hdr, sizeof hdr) &&
              EVP_DigestUpdate(ctx, img.data(), img.num_values() * sizeof(float)) &&
              EVP_DigestFinal_ex(ctx, md, &n);
    EVP_MD_CTX_free(ctx);
    if (!ok) throw Error("SHA-256 failed");
    return hex(md, n);
}

}  // namespace aq
