// RunningNormalizer: updates in chunks of any size give the mean and population variance of all the
// data at once (double-precision reference), normalize clamps at +-5, serialization is exact, and a
// column's statistics begin when it first varies.
#include "rl/core/running_normalizer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace rlt {
namespace {

constexpr int kSize = 3;

// rows of [kSize] floats with different scales and offsets per column
std::vector<float> random_rows(int rows, std::mt19937_64& rng) {
  std::normal_distribution<float> dist(0.f, 1.f);
  const float scale[kSize] = {1.f, 100.f, 0.01f}, offset[kSize] = {0.f, -40.f, 3.f};
  std::vector<float> out(rows * kSize);
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < kSize; ++i) out[r * kSize + i] = offset[i] + scale[i] * dist(rng);
  return out;
}

void reference_stats(const std::vector<float>& data, std::vector<double>& mean,
                     std::vector<double>& var) {
  const int rows = static_cast<int>(data.size()) / kSize;
  mean.assign(kSize, 0.0);
  var.assign(kSize, 0.0);
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < kSize; ++i) mean[i] += data[r * kSize + i];
  for (int i = 0; i < kSize; ++i) mean[i] /= rows;
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < kSize; ++i) {
      const double d = data[r * kSize + i] - mean[i];
      var[i] += d * d;
    }
  for (int i = 0; i < kSize; ++i) var[i] /= rows;
}

TEST(RunningNormalizerTest, ChunkedUpdatesEqualAllAtOnce) {
  std::mt19937_64 rng(2024);
  const std::vector<int> chunks = {1, 5, 2, 64, 1, 13, 300, 7};
  std::vector<float> all;
  RunningNormalizer norm(kSize);
  for (int rows : chunks) {
    auto chunk = random_rows(rows, rng);
    norm.update(chunk.data(), rows);
    all.insert(all.end(), chunk.begin(), chunk.end());
  }
  std::vector<double> mean, var;
  reference_stats(all, mean, var);
  EXPECT_EQ(norm.count(), double(all.size() / kSize));
  for (int i = 0; i < kSize; ++i) {
    EXPECT_NEAR(norm.mean()[i], mean[i], 1e-10 * (1 + std::abs(mean[i]))) << "column " << i;
    EXPECT_NEAR(norm.variance()[i], var[i], 1e-10 * var[i]) << "column " << i;
  }
  // the same data in one update
  RunningNormalizer once(kSize);
  once.update(all.data(), int64_t(all.size() / kSize));
  for (int i = 0; i < kSize; ++i) {
    EXPECT_NEAR(once.mean()[i], norm.mean()[i], 1e-10 * (1 + std::abs(mean[i])));
    EXPECT_NEAR(once.variance()[i], norm.variance()[i], 1e-10 * var[i]);
  }
}

TEST(RunningNormalizerTest, EmptyUpdateChangesNothing) {
  RunningNormalizer norm(kSize);
  float dummy[kSize] = {1.f, 2.f, 3.f};
  norm.update(dummy, 0);
  EXPECT_EQ(norm.count(), 0.0);
  EXPECT_EQ(norm.mean(), std::vector<double>(kSize, 0.0));
  EXPECT_EQ(norm.variance(), std::vector<double>(kSize, 1.0));
}

TEST(RunningNormalizerTest, NormalizeStandardizesAndClampsAtFive) {
  RunningNormalizer norm(2);
  // column 0: mean 1, variance 4; column 1: mean 0, variance 1
  const float data[] = {-1.f, -1.f, 3.f, 1.f};
  norm.update(data, 2);
  ASSERT_DOUBLE_EQ(norm.variance()[0], 4.0);
  float x[] = {2.f, 0.5f, 100.f, -100.f, 1.f + 2.f * 4.9f, -5.1f};
  norm.normalize(x, 3);
  const double s0 = std::sqrt(4.0 + 1e-8), s1 = std::sqrt(1.0 + 1e-8);
  EXPECT_NEAR(x[0], 1.0 / s0, 1e-6);
  EXPECT_NEAR(x[1], 0.5 / s1, 1e-6);
  EXPECT_EQ(x[2], 5.f);
  EXPECT_EQ(x[3], -5.f);
  EXPECT_NEAR(x[4], 4.9 * 2.0 / s0, 1e-5);
  EXPECT_EQ(x[5], -5.f);
}

// passthrough columns keep mean 0 and variance 1 (normalize leaves them), the others are as
// without; the kept values survive serialization
TEST(RunningNormalizerTest, PassthroughColumnsAreLeftAsTheyAre) {
  std::mt19937_64 rng(5);
  const auto data = random_rows(200, rng);
  RunningNormalizer some(kSize);
  some.set_passthrough({0, 1, 0});
  some.update(data.data(), 100);
  some.merge(100, std::vector<double>(kSize, 7.0), std::vector<double>(kSize, 2.0));
  EXPECT_EQ(some.mean()[1], 0.0);
  EXPECT_EQ(some.variance()[1], 1.0);
  EXPECT_NE(some.mean()[0], 0.0);
  std::vector<float> row{0.25f, -3.5f, 3.0f};
  some.normalize(row.data(), 1);
  EXPECT_NEAR(row[1], -3.5f, 1e-6f);
  const RunningNormalizer copy = RunningNormalizer::deserialize(some.serialize());
  EXPECT_EQ(copy.mean()[1], 0.0);
  EXPECT_EQ(copy.variance()[1], 1.0);
  EXPECT_THROW(some.set_passthrough({1, 0}), std::invalid_argument);
}

TEST(RunningNormalizerTest, SerializeRoundTripIsExact) {
  std::mt19937_64 rng(3);
  RunningNormalizer norm(kSize);
  for (int rows : {3, 17, 101}) {
    auto chunk = random_rows(rows, rng);
    norm.update(chunk.data(), rows);
  }
  const std::string text = norm.serialize();
  RunningNormalizer back = RunningNormalizer::deserialize(text);
  ASSERT_EQ(back.size(), kSize);
  EXPECT_EQ(back.count(), norm.count());
  for (int i = 0; i < kSize; ++i) {
    EXPECT_EQ(back.mean()[i], norm.mean()[i]) << "column " << i;
    EXPECT_EQ(back.variance()[i], norm.variance()[i]) << "column " << i;
    EXPECT_EQ(back.column_count(i), norm.column_count(i)) << "column " << i;
  }
  EXPECT_EQ(back.serialize(), text);
  // a restored normalizer keeps folding data in exactly as the original does
  auto more = random_rows(9, rng);
  norm.update(more.data(), 9);
  back.update(more.data(), 9);
  EXPECT_EQ(back.serialize(), norm.serialize());
}

// A column that held one value for a long time (a feature a curriculum switches on late) takes
// the scale of its values from the batch in which it first varies, not a variance diluted by the
// constant history: alternating +-1 normalizes to +-1, not to the clip at 5.
TEST(RunningNormalizerTest, AColumnThatFirstVariesLateGetsTheScaleOfItsNewValues) {
  std::mt19937_64 rng(11);
  RunningNormalizer norm(kSize);
  auto history = random_rows(10000, rng);
  for (int r = 0; r < 10000; ++r) history[r * kSize + 1] = 0.f;  // column 1: 0 throughout
  norm.update(history.data(), 10000);
  EXPECT_EQ(norm.variance()[1], 0.0);
  std::vector<float> later = random_rows(100, rng);
  for (int r = 0; r < 100; ++r) later[r * kSize + 1] = r % 2 ? 1.f : -1.f;
  norm.update(later.data(), 100);
  EXPECT_EQ(norm.count(), 10100.0);
  EXPECT_EQ(norm.column_count(0), 10100.0);
  EXPECT_EQ(norm.column_count(1), 100.0);
  EXPECT_NEAR(norm.mean()[1], 0.0, 1e-12);
  EXPECT_NEAR(norm.variance()[1], 1.0, 1e-12);
  std::vector<float> row{0.f, 1.f, 3.f};
  norm.normalize(row.data(), 1);
  EXPECT_NEAR(row[1], 1.f, 1e-6f);
  // from there on it folds in as any column does
  std::vector<float> more = random_rows(100, rng);
  for (int r = 0; r < 100; ++r) more[r * kSize + 1] = 0.f;
  norm.update(more.data(), 100);
  EXPECT_EQ(norm.column_count(1), 200.0);
  EXPECT_NEAR(norm.variance()[1], 0.5, 1e-12);
}

// A column that moves from one constant to another (a flag that is 0 at one level and 1 at the
// next) normalizes the new constant to 0, as it did the old one.
TEST(RunningNormalizerTest, AColumnThatMovesToAnotherConstantNormalizesItToZero) {
  RunningNormalizer norm(1);
  const std::vector<float> zeros(500, 0.f), ones(50, 1.f);
  norm.update(zeros.data(), 500);
  norm.update(ones.data(), 50);
  EXPECT_EQ(norm.mean()[0], 1.0);
  EXPECT_EQ(norm.variance()[0], 0.0);
  float x = 1.f;
  norm.normalize(&x, 1);
  EXPECT_EQ(x, 0.f);
}

// A state written before the columns had counts of their own loads with every column holding
// all the observations.
TEST(RunningNormalizerTest, AStateWithoutColumnCountsLoads) {
  const RunningNormalizer old = RunningNormalizer::deserialize("2 0x1.4p+3 0x1p+0 0x1p+1 0x0p+0 0x0p+0");
  EXPECT_EQ(old.count(), 10.0);
  EXPECT_EQ(old.column_count(0), 10.0);
  EXPECT_EQ(old.column_count(1), 10.0);
  EXPECT_EQ(old.mean()[0], 1.0);
  EXPECT_EQ(old.variance()[0], 2.0);
}

TEST(RunningNormalizerTest, DeserializeRejectsCorruptText) {
  EXPECT_THROW(RunningNormalizer::deserialize(""), std::runtime_error);
  EXPECT_THROW(RunningNormalizer::deserialize("2 0x1p+3 0x0p+0"), std::runtime_error);
  EXPECT_THROW(RunningNormalizer::deserialize("-1"), std::runtime_error);
  // the column counts are all there or not at all
  EXPECT_THROW(RunningNormalizer::deserialize("2 0x1p+3 0x0p+0 0x1p+0 0x0p+0 0x1p+0 0x1p+3"),
               std::runtime_error);
}

}  // namespace
}  // namespace rlt
