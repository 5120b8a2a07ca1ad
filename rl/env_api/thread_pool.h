// A fixed pool of worker threads that runs `parallel_for` over contiguous chunks of an index range.
//
// Environment steps are short (microseconds for classic control), so a job must start and finish
// with little latency: idle workers spin for a short while (about 50 us) watching for the next job
// before they sleep on a condition variable, and the caller spins until its workers are done.
#pragma once

#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace rlt {

class ThreadPool {
 public:
  // `threads` <= 1 runs everything on the calling thread.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }

  // Calls fn(i) for every i in [0, n), split into one contiguous chunk per thread (the calling
  // thread takes the first chunk). Returns when all calls are done; rethrows the first exception.
  void parallel_for(int n, const std::function<void(int)>& fn);

 private:
  void worker_loop(int worker);
  void record_error(std::exception_ptr e);

  std::vector<std::thread> workers_;
  const std::function<void(int)>* job_ = nullptr;  // written before generation_ is bumped
  int job_n_ = 0;
  std::atomic<long> generation_{0};  // one increment per job
  std::atomic<int> pending_{0};      // workers still running the current job
  std::atomic<int> sleepers_{0};     // workers blocked on wake_
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::mutex error_mutex_;
  std::exception_ptr error_;
};

}  // namespace rlt
