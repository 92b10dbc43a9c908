#include "deflate_runs.h"

#include <libdeflate.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <queue>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace deepsea::io_detail {

namespace {

constexpr std::size_t kBlock = 65535;  // input bytes a block: a stored block's most
constexpr int kSymbols = 286;          // literals, end of block, lengths 3-258
constexpr int kMaxBits = 12;           // four codes go out together (deflate allows 15)
constexpr int kMinRun = 4;             // shorter runs cost more as a match than as literals
constexpr int kMaxRun = 258;

constexpr std::array<int, 29> kLengthBase = {3,  4,  5,  6,   7,   8,   9,   10,  11, 13,
                                             15, 17, 19, 23,  27,  31,  35,  43,  51, 59,
                                             67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr std::array<int, 29> kLengthExtra = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                              2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};

/// Length l (3-258) as its symbol's index (0-28) past 257.
struct LengthTable {
    std::array<std::uint8_t, kMaxRun + 1> code{};
    LengthTable() {
        for (int c = 0; c < 29; ++c)
            for (int l = kLengthBase[c]; l < (c < 28 ? kLengthBase[c + 1] : kMaxRun + 1); ++l)
                code[l] = std::uint8_t(c);  // 258 has its own symbol, 285 (284's reach 257)
    }
};
const LengthTable kLengths;

/// The run of in[i - 1] starting at in[i] (i > 0): its length if at least kMinRun and within
/// `end`, else 0.
inline int run_at(const std::uint8_t* in, std::size_t i, std::size_t end) {
    if (end - i < std::size_t(kMinRun)) return 0;
    const std::uint8_t b = in[i - 1];
    std::uint32_t four;
    std::memcpy(&four, in + i, 4);
    if (four != b * 0x01010101u) return 0;
    const std::size_t stop = std::min(end, i + kMaxRun);
    std::size_t j = i + 4;
    while (j < stop && in[j] == b) ++j;
    return int(j - i);
}

/// Splits in[begin, end) into literals and runs as run_at finds them, for `v`:
/// v.literals(p, n) for n bytes at p, v.run(length). With SSE2, 16 bytes at a time where no
/// run starts among them (noise: nearly everywhere), found from which bytes equal the one
/// before.
template <class Visitor>
void scan(const std::uint8_t* in, std::size_t begin, std::size_t end, Visitor& v) {
    std::size_t i = begin;
    if (i == 0 && i < end) v.literals(in + i++, 1);  // nothing before the stream's first byte
    while (i < end) {
#if defined(__SSE2__)
        // Bit j of `same`: in[i + j] == in[i + j - 1], for j < 32; a run starts at j where
        // bits j to j + 3 are set.
        if (end - i >= 32) {
            const auto cmp = [&](std::size_t at) {
                const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + at));
                const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(in + at - 1));
                return std::uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(a, b)));
            };
            const std::uint32_t same = cmp(i) | cmp(i + 16) << 16;
            const std::uint32_t starts = same & same >> 1 & same >> 2 & same >> 3 & 0xffffu;
            if (!starts) {
                v.literals(in + i, 16);
                i += 16;
                continue;
            }
            // Literals up to the first start, then the run.
            const int first = __builtin_ctz(starts);
            if (first) v.literals(in + i, first);
            i += std::size_t(first);
            const int run = run_at(in, i, end);
            v.run(run);
            i += std::size_t(run);
            continue;
        }
#endif
        const int run = run_at(in, i, end);
        if (run) {
            v.run(run);
            i += std::size_t(run);
        } else {
            v.literals(in + i++, 1);
        }
    }
}

/// Code lengths of at most kMaxBits for the counts (0 for unused symbols): Huffman's, the
/// longest folded back as miniz does (tdefl_huffman_enforce_max_code_size).
void code_lengths(const std::array<std::uint32_t, kSymbols>& count,
                  std::array<std::uint8_t, kSymbols>& len) {
    len.fill(0);
    using Node = std::pair<std::uint64_t, int>;
    std::priority_queue<Node, std::vector<Node>, std::greater<>> heap;
    std::array<int, 2 * kSymbols> parent{};
    std::vector<int> used;
    for (int s = 0; s < kSymbols; ++s) {
        if (count[s]) {
            heap.push({count[s], s});
            used.push_back(s);
        }
    }
    if (used.size() == 1) {  // a one-symbol code: one bit
        len[used[0]] = 1;
        return;
    }
    int next = kSymbols;
    while (heap.size() > 1) {
        const Node a = heap.top();
        heap.pop();
        const Node b = heap.top();
        heap.pop();
        parent[a.second] = parent[b.second] = next;
        heap.push({a.first + b.first, next++});
    }
    const int root = next - 1;
    std::array<int, 33> at_length{};
    std::array<int, 2 * kSymbols> depth{};
    for (int n = root - 1; n >= kSymbols; --n) depth[n] = depth[parent[n]] + 1;
    for (const int s : used) ++at_length[std::min(32, depth[parent[s]] + 1)];
    for (int i = kMaxBits + 1; i <= 32; ++i) at_length[kMaxBits] += at_length[i];
    std::uint32_t total = 0;
    for (int i = kMaxBits; i > 0; --i) total += std::uint32_t(at_length[i]) << (kMaxBits - i);
    while (total != (1u << kMaxBits)) {
        --at_length[kMaxBits];
        for (int i = kMaxBits - 1; i > 0; --i) {
            if (at_length[i]) {
                --at_length[i];
                at_length[i + 1] += 2;
                break;
            }
        }
        --total;
    }
    // The least frequent symbols get the longest codes.
    std::stable_sort(used.begin(), used.end(), [&](int a, int b) { return count[a] < count[b]; });
    std::size_t k = 0;
    for (int l = kMaxBits; l > 0; --l)
        for (int j = 0; j < at_length[l]; ++j) len[used[k++]] = std::uint8_t(l);
}

/// Canonical codes (RFC 1951, 3.2.2), bit-reversed for LSB-first output.
void canonical_codes(const std::array<std::uint8_t, kSymbols>& len,
                     std::array<std::uint16_t, kSymbols>& code) {
    std::array<int, kMaxBits + 1> count{}, next{};
    for (const std::uint8_t l : len) ++count[l];
    count[0] = 0;
    for (int b = 1, c = 0; b <= kMaxBits; ++b) next[b] = c = (c + count[b - 1]) << 1;
    for (int s = 0; s < kSymbols; ++s) {
        if (!len[s]) continue;
        unsigned c = unsigned(next[len[s]]++), r = 0;
        for (int b = 0; b < len[s]; ++b, c >>= 1) r = (r << 1) | (c & 1);
        code[s] = std::uint16_t(r);
    }
}

/// LSB-first bits into `out`, whole 64-bit words stored (the buffer keeps 8 bytes of margin).
struct BitWriter {
    std::uint8_t* out;
    std::uint64_t buf = 0;
    int bits = 0;
    void put(std::uint32_t value, int n) {  // n + 7 <= 57
        buf |= std::uint64_t(value) << bits;
        bits += n;
        std::memcpy(out, &buf, 8);
        out += bits >> 3;
        buf >>= bits & ~7;
        bits &= 7;
    }
    void align() {
        if (bits) put(0, 8 - bits);
    }
};

// The block header: 4-bit codes for code lengths 0-15 (the code-length code: 16-18 unused).
constexpr int kHeaderBits = 3 + 5 + 5 + 4 + 19 * 3 + (kSymbols + 2) * 4;

/// Codes in[begin, end) as one block after w's bits (the last block if `last`); returns the
/// writer after it. Taken and returned by value, so that its state stays in registers.
BitWriter put_block(BitWriter w, const std::uint8_t* in, std::size_t begin, std::size_t end,
                    bool last) {
    // Literals counted in four tables in turn: a byte that repeats does not wait on its own
    // counter's last increment.
    struct Counter {
        std::array<std::array<std::uint32_t, 256>, 4> lits{};
        std::array<std::uint32_t, 29> lengths{};
        std::uint64_t extra = 0, matches = 0;
        void literals(const std::uint8_t* p, int n) {
            int j = 0;
            for (; j + 4 <= n; j += 4) {
                ++lits[0][p[j]];
                ++lits[1][p[j + 1]];
                ++lits[2][p[j + 2]];
                ++lits[3][p[j + 3]];
            }
            for (; j < n; ++j) ++lits[0][p[j]];
        }
        void run(int length) {
            const int c = kLengths.code[length];
            ++lengths[c];
            extra += std::uint64_t(kLengthExtra[c]);
            ++matches;
        }
    } counter;
    scan(in, begin, end, counter);
    std::array<std::uint32_t, kSymbols> count{};
    for (int s = 0; s < 256; ++s) {
        const auto& l = counter.lits;
        count[s] = l[0][s] + l[1][s] + l[2][s] + l[3][s];
    }
    for (int c = 0; c < 29; ++c) count[257 + c] = counter.lengths[c];
    const std::uint64_t extra = counter.extra, matches = counter.matches;
    count[256] = 1;
    std::array<std::uint8_t, kSymbols> len{};
    code_lengths(count, len);
    std::uint64_t coded = kHeaderBits + extra + matches;  // each match: distance code 0, 1 bit
    for (int s = 0; s < kSymbols; ++s) coded += std::uint64_t(count[s]) * len[s];
    const std::uint64_t stored = 3 + (7 - ((w.bits + 2) & 7)) + 32 + 8 * (end - begin);
    if (stored <= coded) {
        w.put(last ? 1 : 0, 3);  // stored
        w.align();
        const std::uint32_t n = std::uint32_t(end - begin);
        w.put(n | (~n & 0xffffu) << 16, 32);
        std::memcpy(w.out, in + begin, n);
        w.out += n;
        return w;
    }
    std::array<std::uint16_t, kSymbols> code{};
    canonical_codes(len, code);
    w.put((last ? 1 : 0) | 2 << 1, 3);  // dynamic Huffman codes
    w.put(kSymbols - 257, 5);
    w.put(2 - 1, 5);   // two distance codes of one bit (a complete code): only 0 is used
    w.put(19 - 4, 4);  // every code-length code length, in RFC 1951's order
    static constexpr int kOrder[19] = {16, 17, 18, 0, 8,  7, 9,  6, 10, 5,
                                       11, 4,  12, 3, 13, 2, 14, 1, 15};
    for (const int s : kOrder) w.put(s < 16 ? 4 : 0, 3);
    // Code length s as 4-bit canonical code s, bit-reversed.
    const auto rev4 = [](unsigned s) {
        return (s & 1) << 3 | (s & 2) << 1 | (s & 4) >> 1 | s >> 3;
    };
    for (int s = 0; s < kSymbols; ++s) w.put(rev4(len[s]), 4);
    w.put(rev4(1), 4);
    w.put(rev4(1), 4);
    struct Encoder {
        BitWriter w;
        std::array<std::uint32_t, 256> lit;  // code | length << 16
        const std::array<std::uint16_t, kSymbols>& code;
        const std::array<std::uint8_t, kSymbols>& len;
        void literals(const std::uint8_t* p, int n) {
            // Four codes of at most 12 bits, joined before they go after the buffer's at
            // most 7 bits: 55 bits, one store.
            std::uint64_t buf = w.buf;
            int bits = w.bits;
            std::uint8_t* out = w.out;
            int j = 0;
            for (; j + 4 <= n; j += 4) {
                const std::uint32_t a = lit[p[j]], b = lit[p[j + 1]], c = lit[p[j + 2]],
                                    d = lit[p[j + 3]];
                const int la = int(a >> 16), lb = int(b >> 16), lc = int(c >> 16);
                const std::uint64_t v = std::uint64_t(a & 0xffff) |
                                        std::uint64_t(b & 0xffff) << la |
                                        std::uint64_t(c & 0xffff) << (la + lb) |
                                        std::uint64_t(d & 0xffff) << (la + lb + lc);
                buf |= v << bits;
                bits += la + lb + lc + int(d >> 16);
                std::memcpy(out, &buf, 8);
                out += bits >> 3;
                buf >>= bits & ~7;
                bits &= 7;
            }
            for (; j < n; ++j) {
                const std::uint32_t a = lit[p[j]];
                buf |= std::uint64_t(a & 0xffff) << bits;
                bits += int(a >> 16);
                std::memcpy(out, &buf, 8);
                out += bits >> 3;
                buf >>= bits & ~7;
                bits &= 7;
            }
            w.buf = buf;
            w.bits = bits;
            w.out = out;
        }
        void run(int length) {
            const int c = kLengths.code[length];
            const int s = 257 + c;
            // The length's code, its extra bits, then distance code 0 (distance 1): one bit 0.
            w.put(code[s] | std::uint32_t(length - kLengthBase[c]) << len[s],
                  len[s] + kLengthExtra[c] + 1);
        }
    } enc{w, {}, code, len};
    for (int s = 0; s < 256; ++s) enc.lit[s] = code[s] | std::uint32_t(len[s]) << 16;
    scan(in, begin, end, enc);
    w = enc.w;
    w.put(code[256], len[256]);
    return w;
}

}  // namespace

std::size_t deflate_runs_bound(std::size_t size) {
    return size + 6 * (size / kBlock + 1) + 2 + 4 + 8;
}

std::size_t deflate_runs(const std::uint8_t* in, std::size_t size, std::uint8_t* out) {
    out[0] = 0x78;  // deflate, 32 KiB window
    out[1] = 0x01;  // fastest; (0x78 << 8 | 0x01) is a multiple of 31
    BitWriter w{out + 2};
    std::size_t begin = 0;
    do {
        const std::size_t end = std::min(size, begin + kBlock);
        w = put_block(w, in, begin, end, end == size);
        begin = end;
    } while (begin < size);
    w.align();
    const std::uint32_t adler = libdeflate_adler32(1, in, size);
    for (int k = 3; k >= 0; --k) *w.out++ = std::uint8_t(adler >> (8 * k));
    return std::size_t(w.out - out);
}

}  // namespace deepsea::io_detail
