#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <vector>

#include "deepsea/colour/srgb.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define DEEPSEA_AVX2_ENCODER 1
#endif

namespace deepsea {

namespace {

constexpr int kShift8 = 15;  ///< the 8-bit table's buckets: floats with the same bits >> 15

/// The integer code OpenImageIO stores for a linear value v in [0, 1]: linear_to_srgb, then
/// scaled and rounded in float as its float-to-integer conversion does.
int srgb_code(float v, int codes) { return int(linear_to_srgb(v) * float(codes) + 0.5f); }

/// srgb_code of every float without a pow per pixel, and bit-identical to it: thresholds[k] is
/// the smallest float whose code is k (found once by bisection over the floats' bit patterns,
/// the code being monotone), and a table indexed by a float's upper bits gives the code at the
/// start of its bucket, from which at most a few thresholds are stepped over.
class SrgbEncoder {
public:
    explicit SrgbEncoder(int codes) : m_codes(codes), m_shift(codes > 255 ? 10 : kShift8) {
        m_threshold.resize(std::size_t(codes) + 2);
        const std::uint32_t one = 0x3f800000u;
        m_threshold[0] = 0;
        for (int k = 1; k <= codes; ++k) {
            std::uint32_t lo = 0, hi = one;  // code(lo) < k <= code(hi)
            while (hi - lo > 1) {
                const std::uint32_t mid = lo + (hi - lo) / 2;
                (srgb_code(from_bits(mid), codes) >= k ? hi : lo) = mid;
            }
            m_threshold[k] = hi;
        }
        m_threshold[codes + 1] = one + 1;  // never reached
        m_start.resize((one >> m_shift) + 1);
        int k = 0;
        for (std::size_t b = 0; b < m_start.size(); ++b) {
            const std::uint32_t bits = std::uint32_t(b) << m_shift;
            while (k < codes && m_threshold[k + 1] <= bits) ++k;
            m_start[b] = std::uint16_t(k);
        }
        // The most thresholds any bucket holds (its values' codes run from its start to the
        // next bucket's start): 1 for 8 bits, so a code is one table read and one comparison.
        for (std::size_t b = 0; b + 1 < m_start.size(); ++b)
            m_steps = std::max(m_steps, int(m_start[b + 1]) - int(m_start[b]));
        m_steps = std::max(m_steps, codes - int(m_start.back()));
        if (m_steps == 1) {
            // A bucket's start code and where in the bucket its one threshold lies, in one
            // word, so that the vector path reads one table, not two, for a value.
            m_entry.resize(m_start.size());
            const std::uint32_t inside = (1u << m_shift) - 1;
            for (std::size_t b = 0; b < m_start.size(); ++b) {
                const int k = m_start[b];
                const std::uint32_t next = m_threshold[std::size_t(k) + 1];
                const std::uint32_t low = next >> m_shift == b ? next & inside : inside + 1;
                m_entry[b] = std::uint32_t(k) << 16 | low;
            }
        }
    }

    /// The code of a linear value: non-finite values and values <= 0 give 0, above 1 the top.
    /// Without branches on the value (noisy images would mispredict them): out-of-range values
    /// look up bucket 0 and are replaced at the end.
    int operator()(float v) const {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        const bool bad =
            (bits & 0x7f800000u) == 0x7f800000u || bits >= 0x80000000u;  // NaN, inf, < 0
        const bool top = bits >= 0x3f800000u;
        const std::uint32_t x = bad || top ? 0u : bits;
        int k = m_start[x >> m_shift];
        for (int s = 0; s < m_steps; ++s) k += m_threshold[std::size_t(k) + 1] <= x ? 1 : 0;
        return bad ? 0 : top ? m_codes : k;
    }

    /// out[i] = operator()(float(in[i] * exposure)) for i < n, 8 codes at a time where the
    /// CPU has AVX2 and a code is one step from its bucket's start (8 bits): one gather of
    /// the buckets' entries and a comparison for 8 values. Returns how many it did (a
    /// multiple of 8; 0 without AVX2). One gather instead of two (the start, then the
    /// threshold after it): 1.9 ms instead of 3.1 for an 800x800 frame's values (thread CPU,
    /// best of 30), the same codes for all 2^32 floats. Intrinsics, not the runtime's
    /// `#pragma omp simd` + DEEPSEA_CLONES: the entry's two halves are unpacked with shifts
    /// and masks on 32-bit lanes, which such a loop would not keep in one gather.
    std::size_t encode_vector(const float* in, std::size_t n, double exposure,
                              std::uint8_t* out) const {
#if defined(DEEPSEA_AVX2_ENCODER)
        static const bool avx2 = __builtin_cpu_supports("avx2");
        if (avx2 && m_steps == 1 && m_codes == 255) {
            if (const Exposed* t = exposed(exposure)) return t->encode_avx2(in, n, out);
            return encode8_avx2(in, n, exposure, out);
        }
#endif
        (void)in, (void)n, (void)exposure, (void)out;
        return 0;
    }

private:
#if defined(DEEPSEA_AVX2_ENCODER)
    /// The 8-bit encoder for one exposure e, on the input's bits u (not on float(v * e)'s): the
    /// code of float(double(v) * e) is monotone in u from 0 up to `inf`, the first u whose
    /// product is infinite (code 0 from there on, as NaNs and negative values), so its 255
    /// thresholds in u are found by bisection and tabled per bucket of u as the encoder's own
    /// are. The same codes as encode8_avx2 without its conversions to double and back, which
    /// cost about a fifth of its time (docs/io-speed.md has the measurements and the check on
    /// all 2^32 floats). `ok` is false where a bucket would hold two thresholds or the top
    /// code is never reached (an exposure below about 3e-39): encode8_avx2 does those.
    struct Exposed {
        double exposure = 0.0;
        bool ok = false;
        std::uint32_t first = 0, top = 0, inf = 0;  ///< u of code 1, of code 255, of inf
        std::uint32_t base = 0;                     ///< the bucket of `first`
        std::vector<std::uint32_t> entry;           ///< per bucket from `base`, as m_entry

        Exposed(const SrgbEncoder& enc, double e) : exposure(e) {
            const auto product = [e](std::uint32_t u) { return float(double(from_bits(u)) * e); };
            const auto code = [&](std::uint32_t u) { return enc(product(u)); };
            std::uint32_t lo = 0, hi = 0x7f800000u;  // finite(product(lo)), not at hi
            if (std::isinf(product(hi - 1))) {
                while (hi - lo > 1) {
                    const std::uint32_t mid = lo + (hi - lo) / 2;
                    (std::isinf(product(mid)) ? hi : lo) = mid;
                }
            }
            inf = hi;
            if (inf == 0 || code(inf - 1) < enc.m_codes) return;
            std::vector<std::uint32_t> u(std::size_t(enc.m_codes) + 2, inf);
            for (int k = 1; k <= enc.m_codes; ++k) {
                std::uint32_t a = 0, b = inf - 1;  // code(a) < k <= code(b)
                if (code(a) >= k) return;
                while (b - a > 1) {
                    const std::uint32_t mid = a + (b - a) / 2;
                    (code(mid) >= k ? b : a) = mid;
                }
                u[k] = b;
            }
            first = u[1];
            top = u[std::size_t(enc.m_codes)];
            const int shift = enc.m_shift;
            const std::uint32_t inside = (1u << shift) - 1;
            base = first >> shift;
            entry.resize((top >> shift) - base + 1);
            std::size_t k = 0;  // thresholds u[1 .. k] lie at or before the bucket's start
            for (std::uint32_t b = base; b <= top >> shift; ++b) {
                const std::uint32_t start = b << shift;
                while (k < std::size_t(enc.m_codes) && u[k + 1] <= start) ++k;
                if (k + 2 <= std::size_t(enc.m_codes) && u[k + 2] >> shift == b) return;
                const std::uint32_t next = u[k + 1];
                const std::uint32_t low = next >> shift == b ? next & inside : inside + 1;
                entry[b - base] = std::uint32_t(k) << 16 | low;
            }
            ok = true;
        }

        /// As encode8_avx2, for this table's exposure.
        __attribute__((target("avx2"))) std::size_t encode_avx2(const float* in, std::size_t n,
                                                                std::uint8_t* out) const {
            const __m256i one = _mm256_set1_epi32(1), top_code = _mm256_set1_epi32(255);
            const __m256i below_first = _mm256_set1_epi32(int(first - 1));
            const __m256i below_top = _mm256_set1_epi32(int(top - 1));
            const __m256i top_end = _mm256_set1_epi32(int(inf));
            const __m256i top_start = _mm256_set1_epi32(int(top));
            const __m256i bucket0 = _mm256_set1_epi32(int(base));
            const __m256i low16 = _mm256_set1_epi32(0xffff);
            const __m256i inside = _mm256_set1_epi32((1 << kShift8) - 1);
            const int* e = reinterpret_cast<const int*>(entry.data());
            std::size_t i = 0;
            for (; i + 8 <= n; i += 8) {
                // Signed comparisons: a negative float's bits are a negative int (code 0).
                const __m256i u = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in + i));
                const __m256i mid = _mm256_and_si256(_mm256_cmpgt_epi32(u, below_first),
                                                     _mm256_cmpgt_epi32(top_start, u));
                const __m256i top_lanes = _mm256_and_si256(_mm256_cmpgt_epi32(u, below_top),
                                                           _mm256_cmpgt_epi32(top_end, u));
                const __m256i at =
                    _mm256_and_si256(mid, _mm256_sub_epi32(_mm256_srli_epi32(u, kShift8), bucket0));
                const __m256i en = _mm256_i32gather_epi32(e, at, 4);
                const __m256i below =
                    _mm256_cmpgt_epi32(_mm256_and_si256(en, low16), _mm256_and_si256(u, inside));
                __m256i k =
                    _mm256_add_epi32(_mm256_srli_epi32(en, 16), _mm256_andnot_si256(below, one));
                k = _mm256_or_si256(_mm256_and_si256(k, mid),
                                    _mm256_and_si256(top_lanes, top_code));
                const __m128i k16 =
                    _mm_packus_epi32(_mm256_castsi256_si128(k), _mm256_extracti128_si256(k, 1));
                _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(k16, k16));
            }
            return i;
        }
    };

    /// The Exposed table of `exposure` (8 bits), made on first use and kept: a sequence encodes
    /// every row with one exposure. Null where there is none (see Exposed::ok), for exposures
    /// that are not finite and positive, and past 16 exposures (each table is about 13 KB).
    const Exposed* exposed(double exposure) const {
        if (!(exposure > 0.0) || !std::isfinite(exposure)) return nullptr;
        thread_local const Exposed* last = nullptr;
        if (last && last->exposure == exposure) return last->ok ? last : nullptr;
        std::lock_guard<std::mutex> lock(m_mutex);
        const Exposed* found = nullptr;
        for (const auto& t : m_exposed)
            if (t->exposure == exposure) found = t.get();
        if (!found) {
            if (m_exposed.size() >= 16) return nullptr;
            m_exposed.push_back(std::make_unique<Exposed>(*this, exposure));
            found = m_exposed.back().get();
        }
        last = found;
        return found->ok ? found : nullptr;
    }

    __attribute__((target("avx2"))) std::size_t encode8_avx2(const float* in, std::size_t n,
                                                             double exposure,
                                                             std::uint8_t* out) const {
        const __m256d e = _mm256_set1_pd(exposure);
        const __m256i exponent = _mm256_set1_epi32(0x7f800000), one = _mm256_set1_epi32(0x3f800000);
        const __m256i top_code = _mm256_set1_epi32(m_codes), low16 = _mm256_set1_epi32(0xffff);
        const __m256i step = _mm256_set1_epi32(1), zero = _mm256_setzero_si256();
        const __m256i inside = _mm256_set1_epi32((1 << m_shift) - 1);
        const int* entry = reinterpret_cast<const int*>(m_entry.data());
        std::size_t i = 0;
        for (; i + 8 <= n; i += 8) {
            // float(v * exposure) in double, as operator() is given it
            const __m128 lo =
                _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_cvtps_pd(_mm_loadu_ps(in + i)), e));
            const __m128 hi =
                _mm256_cvtpd_ps(_mm256_mul_pd(_mm256_cvtps_pd(_mm_loadu_ps(in + i + 4)), e));
            const __m256i bits = _mm256_castps_si256(_mm256_set_m128(hi, lo));
            // NaN or inf (all exponent bits), or negative (sign bit: below zero as an int)
            const __m256i bad =
                _mm256_or_si256(_mm256_cmpeq_epi32(_mm256_and_si256(bits, exponent), exponent),
                                _mm256_cmpgt_epi32(zero, bits));
            const __m256i top =
                _mm256_andnot_si256(bad, _mm256_cmpgt_epi32(bits, _mm256_sub_epi32(one, step)));
            const __m256i x = _mm256_andnot_si256(_mm256_or_si256(bad, top), bits);
            // the bucket's start code, plus one where x is at or past its threshold
            const __m256i e = _mm256_i32gather_epi32(entry, _mm256_srli_epi32(x, m_shift), 4);
            const __m256i below =
                _mm256_cmpgt_epi32(_mm256_and_si256(e, low16), _mm256_and_si256(x, inside));
            __m256i k =
                _mm256_add_epi32(_mm256_srli_epi32(e, 16), _mm256_andnot_si256(below, step));
            k = _mm256_blendv_epi8(k, top_code, top);
            k = _mm256_andnot_si256(bad, k);
            const __m128i k16 =
                _mm_packus_epi32(_mm256_castsi256_si128(k), _mm256_extracti128_si256(k, 1));
            _mm_storel_epi64(reinterpret_cast<__m128i*>(out + i), _mm_packus_epi16(k16, k16));
        }
        return i;
    }
#endif
    static float from_bits(std::uint32_t b) {
        float f;
        std::memcpy(&f, &b, 4);
        return f;
    }
    int m_codes, m_shift;
    int m_steps = 0;
    std::vector<std::uint32_t> m_threshold;  ///< as float bit patterns (ordered like the floats)
    std::vector<std::uint16_t> m_start;
    /// Per bucket, where m_steps is 1: its start code << 16 | its threshold's lower m_shift
    /// bits (1 << m_shift where the next threshold lies in a later bucket).
    std::vector<std::uint32_t> m_entry;
#if defined(DEEPSEA_AVX2_ENCODER)
    mutable std::mutex m_mutex;
    mutable std::vector<std::unique_ptr<Exposed>> m_exposed;
#endif
};

const SrgbEncoder& srgb_encoder(int bits) {
    if (bits == 8) {
        static const SrgbEncoder e8(255);
        return e8;
    }
    static const SrgbEncoder e16(65535);
    return e16;
}

}  // namespace

void srgb_encode(const float* linear, std::size_t n, double exposure, std::uint8_t* codes) {
    // Integer codes straight from the table (OpenImageIO's float to integer conversion of
    // linear_to_srgb without a pow per value), times the exposure as apply_exposure rounds it.
    const SrgbEncoder& enc = srgb_encoder(8);
    const std::size_t done = enc.encode_vector(linear, n, exposure, codes);
    for (std::size_t i = done; i < n; ++i)
        codes[i] = std::uint8_t(enc(float(linear[i] * exposure)));
}

void srgb_encode(const float* linear, std::size_t n, double exposure, std::uint16_t* codes) {
    const SrgbEncoder& enc = srgb_encoder(16);
    for (std::size_t i = 0; i < n; ++i) codes[i] = std::uint16_t(enc(float(linear[i] * exposure)));
}

}  // namespace deepsea
