#include "rl/distributed/gloo_communicator.h"

#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <torch/csrc/distributed/c10d/ProcessGroupGloo.hpp>
#include <torch/csrc/distributed/c10d/TCPStore.hpp>

namespace rlt {

namespace {

using std::chrono::milliseconds;

class GlooCommunicator : public Communicator {
 public:
  explicit GlooCommunicator(const LaunchSettings& s) : settings_(s) {
    const auto timeout = milliseconds(int64_t(s.timeout_seconds * 1000));
    const std::string master = s.master_addr + ":" + std::to_string(s.master_port);
    try {
      c10d::TCPStoreOptions options;
      options.port = uint16_t(s.master_port);
      options.isServer = s.rank == 0;
      options.numWorkers = s.world_size;
      options.waitWorkers = false;
      options.timeout = timeout;
      store_ = c10::make_intrusive<c10d::TCPStore>(s.master_addr, options);
    } catch (const std::exception& e) {
      throw std::runtime_error("rank " + std::to_string(s.rank) + ": cannot " +
                               (s.rank == 0 ? "listen on " : "reach the master at ") + master +
                               " within " + std::to_string(int(s.timeout_seconds)) + " s (" +
                               first_line(e.what()) + ")");
    }
    check_launch();
    auto options = c10d::ProcessGroupGloo::Options::create();
    options->timeout = timeout;
    options->devices.push_back(device());
    try {
      group_ = c10::make_intrusive<c10d::ProcessGroupGloo>(store_, s.rank, s.world_size, options);
    } catch (const std::exception& e) {
      fail("connecting the ranks", e);
    }
  }

  int rank() const override { return settings_.rank; }
  int world_size() const override { return settings_.world_size; }

  void all_reduce_sum(torch::Tensor& tensor, const char* what) override {
    std::vector<at::Tensor> list{tensor};
    try {
      group_->allreduce(list)->wait();
    } catch (const std::exception& e) {
      fail(what, e);
    }
  }

  void broadcast(torch::Tensor& tensor, int root, const char* what) override {
    std::vector<at::Tensor> list{tensor};
    c10d::BroadcastOptions options;
    options.rootRank = root;
    try {
      group_->broadcast(list, options)->wait();
    } catch (const std::exception& e) {
      fail(what, e);
    }
  }

 private:
  static std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

  // the network device Gloo connects through, as PyTorch picks it: GLOO_SOCKET_IFNAME's interface,
  // loopback when the master is on it (one machine), else what this host's name resolves to
  std::shared_ptr<gloo::transport::Device> device() const {
    if (const char* name = std::getenv("GLOO_SOCKET_IFNAME"); name && *name)
      return c10d::ProcessGroupGloo::createDeviceForInterface(name);
    if (settings_.master_addr.rfind("127.", 0) == 0 || settings_.master_addr == "localhost")
      return c10d::ProcessGroupGloo::createDeviceForHostname("127.0.0.1");
    return c10d::ProcessGroupGloo::createDefaultDevice();
  }

  // every rank was launched with the same WORLD_SIZE, and no RANK twice
  void check_launch() {
    const std::string me = std::to_string(settings_.rank),
                      mine = std::to_string(settings_.world_size);
    int64_t claims = 0;
    std::vector<std::string> sizes;  // [world_size] each rank's WORLD_SIZE
    try {
      claims = store_->add("rlt/rank/" + me, 1);
      store_->set("rlt/world_size/" + me, bytes(mine));
      std::vector<std::string> keys;
      for (int r = 0; r < settings_.world_size; ++r)
        keys.push_back("rlt/world_size/" + std::to_string(r));
      store_->wait(keys);
      for (const auto& key : keys) {
        const auto value = store_->get(key);
        sizes.emplace_back(value.begin(), value.end());
      }
    } catch (const std::exception& e) {
      throw std::runtime_error(
          "rank " + me + ": not every one of the " + mine + " ranks joined within " +
          std::to_string(int(settings_.timeout_seconds)) + " s (" + first_line(e.what()) + ")");
    }
    if (claims != 1) throw std::runtime_error("two processes were launched with RANK=" + me);
    for (int r = 0; r < settings_.world_size; ++r)
      if (sizes[r] != mine)
        throw std::runtime_error("rank " + std::to_string(r) + " was launched with WORLD_SIZE=" +
                                 sizes[r] + ", rank " + me + " with WORLD_SIZE=" + mine);
  }

  static std::vector<uint8_t> bytes(const std::string& s) {
    return std::vector<uint8_t>(s.begin(), s.end());
  }

  // A collective failed: the ranks still running say so in the store, and those that do not
  // within a few seconds are named. When the store itself is gone, rank 0 (which holds it) is.
  [[noreturn]] void fail(const char* what, const std::exception& e) {
    const std::string me = std::to_string(settings_.rank);
    std::string missing;
    try {
      const std::string generation = std::to_string(++failures_);
      store_->set("rlt/alive/" + generation + "/" + me, bytes("1"));
      std::this_thread::sleep_for(std::chrono::seconds(2));
      for (int r = 0; r < settings_.world_size; ++r)
        if (!store_->check({"rlt/alive/" + generation + "/" + std::to_string(r)}))
          missing += (missing.empty() ? "" : ", ") + std::to_string(r);
    } catch (const std::exception&) {
      missing = "0 (the master, which holds the store)";
    }
    throw std::runtime_error("rank " + me + ": " + what + " failed: rank " +
                             (missing.empty() ? std::string("?") : missing) +
                             " stopped answering (" + first_line(e.what()) + ")");
  }

  LaunchSettings settings_;
  c10::intrusive_ptr<c10d::TCPStore> store_;
  c10::intrusive_ptr<c10d::ProcessGroupGloo> group_;
  int failures_ = 0;
};

}  // namespace

std::unique_ptr<Communicator> connect_gloo(const LaunchSettings& settings) {
  return std::make_unique<GlooCommunicator>(settings);
}

}  // namespace rlt
