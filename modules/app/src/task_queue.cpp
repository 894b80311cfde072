#include <sched.h>
#include <superloc/app/task_queue.h>

#include <thread>
#include <utility>
#include <vector>

namespace superloc::app {

TaskQueue::TaskQueue(unsigned threads) : threads_(threads < 1 ? 1 : threads) {}

void TaskQueue::add(size_t key, std::function<void()> task) {
    {
        std::lock_guard<std::mutex> lock(m_);
        ready_.emplace(key, std::move(task));
    }
    cv_.notify_one();
}

void TaskQueue::work() {
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
        // Done when nothing is ready and nothing running could add more (or after an error,
        // once the running tasks have finished).
        cv_.wait(lock, [&] { return (!ready_.empty() && !error_) || running_ == 0; });
        if (error_ || ready_.empty()) break;
        auto task = std::move(ready_.begin()->second);
        ready_.erase(ready_.begin());
        ++running_;
        lock.unlock();
        std::exception_ptr e;
        try {
            task();
        } catch (...) {
            e = std::current_exception();
        }
        lock.lock();
        --running_;
        if (e && !error_) error_ = e;
        cv_.notify_all();
    }
    cv_.notify_all();
}

void TaskQueue::run() {
    std::vector<std::thread> helpers;
    for (unsigned i = 1; i < threads_; ++i) helpers.emplace_back([this] { work(); });
    work();
    for (auto& t : helpers) t.join();
    std::lock_guard<std::mutex> lock(m_);
    ready_.clear();
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

unsigned availableCores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (::sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0)
        return static_cast<unsigned>(CPU_COUNT(&set));
    const unsigned n = std::thread::hardware_concurrency();
    return n > 0 ? n : 1;
}

}  // namespace superloc::app
