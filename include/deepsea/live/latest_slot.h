#pragma once
/// \file The hand-over between a middleware's callbacks and the render thread: one waiting
/// frame, the latest. A frame that arrives while another waits replaces it (counted), so the
/// output lags the input by at most the frame being rendered, whatever the input's rate.

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

namespace deepsea {

template <class T>
class LatestSlot {
public:
    /// Leaves `value` for take(); true when it replaced a frame that was still waiting.
    bool put(T value) {
        bool replaced = false;
        {
            const std::lock_guard<std::mutex> lock(m_mutex);
            replaced = m_value.has_value();
            if (replaced) ++m_replaced;
            m_value = std::move(value);
        }
        m_ready.notify_one();
        return replaced;
    }

    /// The waiting frame, waiting for one; nothing once closed.
    std::optional<T> take() {
        std::unique_lock<std::mutex> lock(m_mutex);
        m_ready.wait(lock, [&] { return m_value.has_value() || m_closed; });
        if (m_closed) return std::nullopt;
        std::optional<T> out = std::move(m_value);
        m_value.reset();
        return out;
    }

    /// Wakes take() for good (shutdown).
    void close() {
        {
            const std::lock_guard<std::mutex> lock(m_mutex);
            m_closed = true;
        }
        m_ready.notify_all();
    }

    /// Frames replaced before they were rendered.
    std::uint64_t replaced() const {
        const std::lock_guard<std::mutex> lock(m_mutex);
        return m_replaced;
    }

private:
    mutable std::mutex m_mutex;
    std::condition_variable m_ready;
    std::optional<T> m_value;
    bool m_closed = false;
    std::uint64_t m_replaced = 0;
};

}  // namespace deepsea
