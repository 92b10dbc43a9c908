#pragma once
/// \file Pairs colour and depth messages by their header stamps, as message_filters'
/// synchronisers do, without a middleware: the ROS 1 node and a ROS 2 port share it.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <optional>
#include <utility>

namespace deepsea {

/// Exact: a colour and a depth frame pair when their stamps are equal (a simulator's RGB-D
/// sensor stamps both with the render time). Approximate: when the stamps differ by at most
/// the slop (two sensors, or a bag whose stamps jitter); each frame pairs with the other
/// stream's nearest stamp as soon as one is within the slop.
enum class PairPolicy { Exact, Approximate };

/// Holds up to `queue` unpaired frames a stream (older ones are dropped first). When a frame
/// pairs, the frames of either stream stamped before the pair are dropped: they can no longer
/// pair with anything newer (stamps grow). Every dropped frame is counted in unpaired().
/// One thread (the middleware's callbacks); C and D are the message handles.
template <class C, class D>
class StampPairer {
public:
    StampPairer(PairPolicy policy, std::int64_t slop_ns, std::size_t queue = 8)
        : m_slop(policy == PairPolicy::Exact ? 0 : slop_ns), m_queue(queue) {}

    /// A colour frame stamped `stamp_ns`: the pair it completes, or nothing (held).
    std::optional<std::pair<C, D>> add_color(std::int64_t stamp_ns, C color) {
        auto hit = take_match(m_depth, stamp_ns);
        if (!hit) {
            hold(m_color, stamp_ns, std::move(color));
            return std::nullopt;
        }
        drop_before(m_color, stamp_ns);
        return std::pair<C, D>{std::move(color), std::move(*hit)};
    }

    /// A depth frame stamped `stamp_ns`: the pair it completes, or nothing (held).
    std::optional<std::pair<C, D>> add_depth(std::int64_t stamp_ns, D depth) {
        auto hit = take_match(m_color, stamp_ns);
        if (!hit) {
            hold(m_depth, stamp_ns, std::move(depth));
            return std::nullopt;
        }
        drop_before(m_depth, stamp_ns);
        return std::pair<C, D>{std::move(*hit), std::move(depth)};
    }

    /// Frames dropped without a partner so far.
    std::uint64_t unpaired() const { return m_unpaired; }
    /// Frames held, waiting for a partner.
    std::size_t waiting() const { return m_color.size() + m_depth.size(); }

private:
    template <class T>
    using Queue = std::deque<std::pair<std::int64_t, T>>;

    /// The queued frame nearest to `stamp` within the slop, removed with every frame queued
    /// before it (counted); nothing when none is near enough.
    template <class T>
    std::optional<T> take_match(Queue<T>& q, std::int64_t stamp) {
        std::size_t best = q.size();
        std::int64_t best_dt = 0;
        for (std::size_t i = 0; i < q.size(); ++i) {
            const std::int64_t dt = std::llabs(q[i].first - stamp);
            if (dt <= m_slop && (best == q.size() || dt < best_dt)) {
                best = i;
                best_dt = dt;
            }
        }
        if (best == q.size()) return std::nullopt;
        T hit = std::move(q[best].second);
        const std::int64_t matched = q[best].first;
        q.erase(q.begin() + std::ptrdiff_t(best));
        drop_before(q, matched);
        return hit;
    }

    template <class T>
    void drop_before(Queue<T>& q, std::int64_t stamp) {
        const std::size_t before = q.size();
        q.erase(std::remove_if(q.begin(), q.end(), [&](const auto& e) { return e.first < stamp; }),
                q.end());
        m_unpaired += before - q.size();
    }

    template <class T>
    void hold(Queue<T>& q, std::int64_t stamp, T frame) {
        q.emplace_back(stamp, std::move(frame));
        while (q.size() > m_queue) {
            q.pop_front();
            ++m_unpaired;
        }
    }

    std::int64_t m_slop;
    std::size_t m_queue;
    Queue<C> m_color;
    Queue<D> m_depth;
    std::uint64_t m_unpaired = 0;
};

}  // namespace deepsea
