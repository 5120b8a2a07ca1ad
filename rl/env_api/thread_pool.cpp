#include "rl/env_api/thread_pool.h"

#include <chrono>

namespace rlt {

namespace {
// the [begin, end) chunk of `n` items that thread `t` of `threads` handles
std::pair<int, int> chunk(int n, int threads, int t) {
  return {int(long(n) * t / threads), int(long(n) * (t + 1) / threads)};
}

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

constexpr auto kSpinBeforeSleep = std::chrono::microseconds(50);
}  // namespace

ThreadPool::ThreadPool(int threads) {
  for (int w = 1; w < threads; ++w) workers_.emplace_back([this, w] { worker_loop(w); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void ThreadPool::record_error(std::exception_ptr e) {
  std::lock_guard<std::mutex> lock(error_mutex_);
  if (!error_) error_ = e;
}

void ThreadPool::parallel_for(int n, const std::function<void(int)>& fn) {
  if (workers_.empty() || n <= 1) {
    for (int i = 0; i < n; ++i) fn(i);
    return;
  }
  // publish the job, then wake sleeping workers (spinning ones see the new generation)
  job_ = &fn;
  job_n_ = n;
  error_ = nullptr;
  pending_.store(static_cast<int>(workers_.size()));
  generation_.fetch_add(1);
  if (sleepers_.load() > 0) {
    std::lock_guard<std::mutex> lock(mutex_);
    wake_.notify_all();
  }
  try {
    auto [b, e] = chunk(n, size(), 0);
    for (int i = b; i < e; ++i) fn(i);
  } catch (...) {
    record_error(std::current_exception());
  }
  while (pending_.load() != 0) cpu_relax();
  job_ = nullptr;
  if (error_) std::rethrow_exception(error_);
}

void ThreadPool::worker_loop(int worker) {
  long seen = 0;
  for (;;) {
    // spin briefly for the next job, then sleep until one is published
    const auto spin_until = std::chrono::steady_clock::now() + kSpinBeforeSleep;
    int spins = 0;
    while (generation_.load() == seen && !stop_.load()) {
      cpu_relax();
      if ((++spins & 63) != 0 || std::chrono::steady_clock::now() < spin_until) continue;
      std::unique_lock<std::mutex> lock(mutex_);
      sleepers_.fetch_add(1);
      wake_.wait(lock, [&] { return generation_.load() != seen || stop_.load(); });
      sleepers_.fetch_sub(1);
    }
    if (stop_.load()) return;
    seen = generation_.load();
    try {
      auto [b, e] = chunk(job_n_, size(), worker);
      for (int i = b; i < e; ++i) (*job_)(i);
    } catch (...) {
      record_error(std::current_exception());
    }
    pending_.fetch_sub(1);
  }
}

}  // namespace rlt
