// TensorBoard event files read back by a reader written apart from the writer: a bit-at-a-time
// CRC-32C, a generic protocol buffer decoder, and checks of the record framing.
#include "rl/trainer/tensorboard_writer.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "tests/rl/trainer/tensorboard_reader.h"

namespace rlt {
namespace {

namespace fs = std::filesystem;
using tensorboard_reader::crc_bitwise;
using tensorboard_reader::Event;
using tensorboard_reader::mask;
using tensorboard_reader::read_events;

class TensorBoardWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rlt_tensorboard_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST(Crc32cTest, KnownValues) {
  // the check value of CRC-32C, and the masked form TensorFlow's records carry
  EXPECT_EQ(crc32c("123456789", 9), 0xe3069283u);
  EXPECT_EQ(crc32c("", 0), 0u);
  EXPECT_EQ(masked_crc32c("123456789", 9), mask(0xe3069283u));
  std::string bytes;
  for (int i = 0; i < 1000; ++i) bytes.push_back(char(i * 37 + 11));
  EXPECT_EQ(crc32c(bytes.data(), bytes.size()), crc_bitwise(bytes));
}

TEST_F(TensorBoardWriterTest, EventsReadBackWithTheirStepsTagsAndValues) {
  std::string path;
  {
    TensorBoardWriter writer((dir_ / "Hider").string());
    path = writer.path();
    writer.add_scalars(50000, {{"Environment/Cumulative Reward", 1.5f},
                               {"Environment/Episode Length", 1024.f},
                               {"Self-play/ELO", 1234.25f}});
    writer.add_scalar(100000, "Environment/Lesson Number/level", 2.f);
    writer.add_scalar(int64_t(1) << 40, "Policy/Entropy", -0.125f);  // a step beyond 32 bits
  }
  EXPECT_EQ(fs::path(path).parent_path(), dir_ / "Hider");
  EXPECT_EQ(fs::path(path).filename().string().rfind("events.out.tfevents.", 0), 0u) << path;
  const std::vector<Event> events = read_events(path);
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[0].file_version, "brain.Event:2");
  EXPECT_TRUE(events[0].scalars.empty());
  EXPECT_EQ(events[1].step, 50000);
  EXPECT_EQ(events[1].scalars,
            (std::map<std::string, float>{{"Environment/Cumulative Reward", 1.5f},
                                          {"Environment/Episode Length", 1024.f},
                                          {"Self-play/ELO", 1234.25f}}));
  EXPECT_EQ(events[2].step, 100000);
  EXPECT_EQ(events[2].scalars.at("Environment/Lesson Number/level"), 2.f);
  EXPECT_EQ(events[3].step, int64_t(1) << 40);
  EXPECT_EQ(events[3].scalars.at("Policy/Entropy"), -0.125f);
  // wall times are seconds since 1970, in order
  EXPECT_GT(events[1].wall_time, 1.6e9);
  EXPECT_LE(events[1].wall_time, events[3].wall_time);
}

TEST_F(TensorBoardWriterTest, CorruptedBytesAreCaughtByTheReader) {
  // negative control: the reader's CRC checks are not vacuous
  std::string path;
  {
    TensorBoardWriter writer(dir_.string());
    path = writer.path();
    writer.add_scalar(1, "x", 1.f);
  }
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-6, std::ios::end);  // inside the last payload (its value)
    f.put('\x7f');
  }
  ::testing::TestPartResultArray failures;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &failures);
    read_events(path);
  }
  EXPECT_GE(failures.size(), 1);
}

TEST_F(TensorBoardWriterTest, TwoWritersInOneFolderWriteTwoFiles) {
  TensorBoardWriter first(dir_.string());
  TensorBoardWriter second(dir_.string());
  EXPECT_NE(first.path(), second.path());
}

TEST_F(TensorBoardWriterTest, UnwritableFolderIsAnError) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "file") << "x";
  EXPECT_THROW(TensorBoardWriter((dir_ / "file" / "sub").string()), std::runtime_error);
}

}  // namespace
}  // namespace rlt
