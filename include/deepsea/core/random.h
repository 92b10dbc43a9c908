#pragma once
/// \file A small, fast, deterministic random number generator for Monte Carlo work.

#include <cstdint>

namespace deepsea {

/// SplitMix64 (Steele, Lea, Flood 2014): 64-bit state, passes BigCrush, and any 64-bit seed
/// (a hash of a column index, say) starts an independent-looking stream. Results of a Monte
/// Carlo bake depend only on the seeds, never on the thread that ran them.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : m_state(seed) {}

    std::uint64_t next() {
        std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1).
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }

private:
    std::uint64_t m_state;
};

/// Mixes several integers into one seed (for per-column streams).
inline std::uint64_t mix_seed(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0) {
    Rng r(a ^ (b * 0xd1342543de82ef95ull) ^ (c * 0x9e3779b97f4a7c15ull));
    r.next();
    return r.next();
}

}  // namespace deepsea
