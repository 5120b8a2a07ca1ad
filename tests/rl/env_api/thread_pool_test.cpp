// ThreadPool: every index once, contiguous chunks, exceptions reach the caller.
#include "rl/env_api/thread_pool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace rlt {
namespace {

TEST(ThreadPoolTest, VisitsEveryIndexExactlyOnce) {
  for (int threads : {1, 2, 3, 8}) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.size(), std::max(threads, 1));
    for (int n : {0, 1, 2, 5, 64, 1000}) {
      std::vector<std::atomic<int>> visits(n);
      for (auto& v : visits) v = 0;
      pool.parallel_for(n, [&](int i) { ++visits[i]; });
      for (int i = 0; i < n; ++i)
        ASSERT_EQ(visits[i].load(), 1) << "threads " << threads << ", n " << n << ", i " << i;
    }
  }
}

TEST(ThreadPoolTest, RepeatedJobsReuseThePool) {
  ThreadPool pool(3);
  std::atomic<long> sum{0};
  for (int round = 0; round < 500; ++round) pool.parallel_for(10, [&](int i) { sum += i; });
  EXPECT_EQ(sum.load(), 500L * 45);
}

TEST(ThreadPoolTest, UsesSeveralThreadsAndTheCaller) {
  ThreadPool pool(2);
  std::mutex mutex;
  std::set<std::thread::id> ids;
  pool.parallel_for(2, [&](int) {
    std::lock_guard<std::mutex> lock(mutex);
    ids.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(ids.size(), 2u);
  EXPECT_TRUE(ids.count(std::this_thread::get_id()));
}

TEST(ThreadPoolTest, OneThreadRunsOnTheCaller) {
  ThreadPool pool(1);
  std::set<std::thread::id> ids;
  pool.parallel_for(10, [&](int) { ids.insert(std::this_thread::get_id()); });
  EXPECT_EQ(ids, std::set<std::thread::id>({std::this_thread::get_id()}));
}

TEST(ThreadPoolTest, ExceptionsPropagateFromWorkersAndCaller) {
  ThreadPool pool(4);
  // index 99 is in the last worker's chunk, index 0 in the caller's
  for (int bad : {99, 0}) {
    std::atomic<int> done{0};
    EXPECT_THROW(pool.parallel_for(100,
                                   [&](int i) {
                                     if (i == bad) throw std::runtime_error("bad index");
                                     ++done;
                                   }),
                 std::runtime_error);
    // the other chunks still ran to completion before the rethrow
    EXPECT_GE(done.load(), 75);
  }
  // the pool still works afterwards
  std::atomic<int> count{0};
  pool.parallel_for(100, [&](int) { ++count; });
  EXPECT_EQ(count.load(), 100);
}

}  // namespace
}  // namespace rlt
