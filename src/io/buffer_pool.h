#pragma once
// Scratch buffers shared by the threads that make one kind of codec call (private to
// deepsea_io), in place of thread_local ones. A sequence's pipeline runs each stage on whichever
// worker is free, so thread_local buffers end up duplicated on every worker that ever ran the
// stage (at 1080p, 12 MB of PNG writer buffers per thread); a pool holds only as many as calls
// ever ran at once, and keeps them from frame to frame all the same.

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace deepsea::io_detail {

template <class T>
class BufferPool {
public:
    /// One buffer, given back to the pool when the lease ends.
    class Lease {
    public:
        Lease(BufferPool& pool, std::unique_ptr<T> item) : m_pool(pool), m_item(std::move(item)) {}
        ~Lease() { m_pool.give_back(std::move(m_item)); }
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        T& operator*() const { return *m_item; }
        T* operator->() const { return m_item.get(); }

    private:
        BufferPool& m_pool;
        std::unique_ptr<T> m_item;
    };

    /// A free buffer as the last user left it, or a new one.
    Lease take() {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (m_free.empty()) return Lease(*this, std::make_unique<T>());
        std::unique_ptr<T> item = std::move(m_free.back());
        m_free.pop_back();
        return Lease(*this, std::move(item));
    }

private:
    void give_back(std::unique_ptr<T> item) {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_free.push_back(std::move(item));
    }

    std::mutex m_mutex;
    std::vector<std::unique_ptr<T>> m_free;
};

}  // namespace deepsea::io_detail
