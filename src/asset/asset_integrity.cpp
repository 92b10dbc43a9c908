// The integrity record: found in the raw bytes by its exact binary signature, verified with
// OpenSSL's SHA-256 before any OpenVDB code sees the file.

#include "deepsea/asset/asset_integrity.h"

#include <openssl/evp.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string_view>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {

constexpr std::size_t kSizeDigits = 16, kHashDigits = 64;
constexpr std::string_view kSizeKey = "size=", kHashKey = " sha256=";
constexpr std::size_t kValueLength = kSizeKey.size() + kSizeDigits + kHashKey.size() + kHashDigits;

/// OpenVDB's first eight bytes: the int64 magic number 0x56444220 ("VDB "), little-endian.
constexpr char kVdbMagic[8] = {' ', 'B', 'D', 'V', 0, 0, 0, 0};

std::string le32(std::uint32_t v) {
    std::string s(4, '\0');
    for (int b = 0; b < 4; ++b) s[b] = char((v >> (8 * b)) & 0xffu);
    return s;
}

/// How OpenVDB stores a string metadata entry: the name, the type name "string" and the value,
/// each preceded by its length as a little-endian uint32. No text inside the JSON metadata can
/// contain this (it has NUL bytes), so a match is the record and nothing else.
const std::string& signature() {
    static const std::string s = le32(std::uint32_t(std::strlen(kMetaIntegrity))) + kMetaIntegrity +
                                 le32(6) + "string" + le32(std::uint32_t(kValueLength)) +
                                 std::string(kSizeKey);
    return s;
}

/// Offset of the record's size digits in `head`, or npos.
std::size_t find_record(std::string_view head) {
    const std::size_t at = head.find(signature());
    if (at == std::string_view::npos) return at;
    const std::size_t digits = at + signature().size();
    if (digits + kValueLength - kSizeKey.size() > head.size()) return std::string_view::npos;
    return digits;
}

/// Offset of the hash digits, given the offset of the size digits.
std::size_t hash_digits(std::size_t size_digits) {
    return size_digits + kSizeDigits + kHashKey.size();
}

/// The placeholder's digits: what the hash is taken over.
void blank(std::string& bytes, std::size_t size_digits) {
    std::fill_n(bytes.begin() + std::ptrdiff_t(size_digits), kSizeDigits, '0');
    std::fill_n(bytes.begin() + std::ptrdiff_t(hash_digits(size_digits)), kHashDigits, '0');
}

class Sha256 {
public:
    Sha256() : m_ctx(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
        if (!m_ctx || EVP_DigestInit_ex(m_ctx.get(), EVP_sha256(), nullptr) != 1)
            throw Error("SHA-256 is not available (OpenSSL)");
    }
    void add(const char* p, std::size_t n) { EVP_DigestUpdate(m_ctx.get(), p, n); }
    std::string hex() {
        unsigned char md[EVP_MAX_MD_SIZE];
        unsigned int n = 0;
        EVP_DigestFinal_ex(m_ctx.get(), md, &n);
        static const char* digits = "0123456789abcdef";
        std::string out;
        for (unsigned int i = 0; i < n; ++i) {
            out += digits[md[i] >> 4];
            out += digits[md[i] & 15];
        }
        return out;
    }

private:
    std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> m_ctx;
};

bool all_of(std::string_view s, const char* set) {
    return s.find_first_not_of(set) == std::string_view::npos;
}

}  // namespace

std::string integrity_placeholder() {
    return std::string(kSizeKey) + std::string(kSizeDigits, '0') + std::string(kHashKey) +
           std::string(kHashDigits, '0');
}

IntegrityRecord seal_asset_bytes(std::string& bytes) {
    const std::size_t d =
        find_record(std::string_view(bytes).substr(0, std::min(bytes.size(), kIntegrityWindow)));
    if (d == std::string::npos)
        throw AssetError("seal_asset_bytes: no deepsea:integrity placeholder near the start");
    blank(bytes, d);
    IntegrityRecord r;
    r.size = bytes.size();
    Sha256 sha;
    sha.add(bytes.data(), bytes.size());
    r.sha256 = sha.hex();
    char size[kSizeDigits + 1];
    std::snprintf(size, sizeof size, "%016llu", static_cast<unsigned long long>(r.size));
    bytes.replace(d, kSizeDigits, size);
    bytes.replace(hash_digits(d), kHashDigits, r.sha256);
    return r;
}

IntegrityRecord verify_asset_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("cannot open asset " + path + ": " + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const auto length = std::uint64_t(std::max<std::streamoff>(in.tellg(), 0));
    in.seekg(0);
    std::string head(std::size_t(std::min<std::uint64_t>(length, kIntegrityWindow)), '\0');
    in.read(head.data(), std::streamsize(head.size()));
    head.resize(std::size_t(in.gcount()));
    if (in.bad()) throw IoError("cannot read asset " + path + ": " + std::strerror(errno));
    if (head.size() < sizeof kVdbMagic || head.compare(0, 8, kVdbMagic, 8) != 0)
        throw AssetError(path + ": not an OpenVDB file");
    const std::size_t d = find_record(head);
    if (d == std::string::npos) {
        const bool ours = head.find("deepsea:format") != std::string::npos ||
                          head.find("deepsea:bake") != std::string::npos;
        throw AssetError(path + (ours ? ": no integrity record (written by an older deepsea, "
                                        "re-saved by another tool, or damaged): re-bake it"
                                      : ": not a deepsea asset (no deepsea:integrity record)"));
    }
    const std::string_view size_text = std::string_view(head).substr(d, kSizeDigits);
    const std::string_view hash_text = std::string_view(head).substr(hash_digits(d), kHashDigits);
    if (!all_of(size_text, "0123456789") || !all_of(hash_text, "0123456789abcdef") ||
        std::string_view(head).substr(d + kSizeDigits, kHashKey.size()) != kHashKey) {
        throw AssetError(path + ": damaged asset (its integrity record is unreadable)");
    }
    IntegrityRecord want;
    want.size = std::stoull(std::string(size_text));
    want.sha256 = std::string(hash_text);

    // The file's length, then its hash, streamed (assets can be larger than the window).
    Sha256 sha;
    std::string first = head;
    blank(first, d);
    sha.add(first.data(), first.size());
    std::uint64_t have = first.size();
    std::string chunk(length > head.size() ? std::size_t(1) << 20 : 0, '\0');
    while (in && !chunk.empty()) {
        in.read(chunk.data(), std::streamsize(chunk.size()));
        const auto n = std::size_t(in.gcount());
        sha.add(chunk.data(), n);
        have += n;
    }
    if (in.bad()) throw IoError("cannot read asset " + path + ": " + std::strerror(errno));
    if (have != want.size) {
        throw AssetError(path + ": truncated or damaged asset (" + std::to_string(have) +
                         " bytes, written as " + std::to_string(want.size) + ")");
    }
    if (sha.hex() != want.sha256) {
        throw AssetError(path +
                         ": damaged or edited asset (its SHA-256 does not match the one "
                         "recorded when it was written)");
    }
    return want;
}

}  // namespace deepsea
