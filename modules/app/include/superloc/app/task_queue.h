// Tasks run by a fixed number of threads (superloc-bench --jobs N): among the tasks ready, the one
// with the lowest key runs first, and a running task may add more, e.g. a sequence's localize runs
// once its data is ready. With one thread the tasks run on the calling thread in key order, one
// after the other.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <map>
#include <mutex>

namespace superloc::app {

class TaskQueue {
 public:
    /// `threads` >= 1: how many tasks run at once (the calling thread of run() is one of them).
    explicit TaskQueue(unsigned threads);

    /// Adds a task; `key` orders the ready tasks (lowest first; keys need not be unique, equal
    /// keys run in the order added). May be called from a running task.
    void add(size_t key, std::function<void()> task);

    /// Runs every task, including those added while running, and returns when none is left.
    /// A task that throws stops new tasks from starting; the ones running finish, then run()
    /// rethrows the first exception.
    void run();

 private:
    void work();
    unsigned threads_;
    std::mutex m_;
    std::condition_variable cv_;
    std::multimap<size_t, std::function<void()>> ready_;
    unsigned running_ = 0;
    std::exception_ptr error_;
};

/// The processors this process may run on (sched_getaffinity; at least 1).
unsigned availableCores();

}  // namespace superloc::app
