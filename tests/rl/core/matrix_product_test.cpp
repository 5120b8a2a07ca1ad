// multiply() gives the plain product on both of its paths (Eigen and the BLAS), for every
// transposition, overwriting or accumulating, and into a block of a larger matrix; a shape mismatch
// is an error that names both shapes.
#include "rl/core/matrix_product.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>

namespace rlt {
namespace {

RowMatrix random_matrix(int64_t rows, int64_t cols, std::mt19937& rng) {
  std::normal_distribution<float> normal;
  RowMatrix m(rows, cols);
  for (int64_t i = 0; i < m.size(); ++i) m.data()[i] = normal(rng);
  return m;
}

// the product by definition, in double
RowMatrix reference(const RowMatrix& a, const RowMatrix& b) {
  RowMatrix out(a.rows(), b.cols());
  for (int64_t i = 0; i < a.rows(); ++i)
    for (int64_t j = 0; j < b.cols(); ++j) {
      double sum = 0;
      for (int64_t k = 0; k < a.cols(); ++k) sum += double(a(i, k)) * b(k, j);
      out(i, j) = float(sum);
    }
  return out;
}

struct ProductCase {
  Transpose ta, tb;
  bool accumulate, force_blas;
};

class MatrixProductTest : public ::testing::TestWithParam<ProductCase> {};

TEST_P(MatrixProductTest, EqualsTheDefinition) {
  const auto c = GetParam();
  std::mt19937 rng(3);
  const int64_t m = 23, k = 41, n = 17;
  // stored transposed where the product transposes them
  const RowMatrix a = c.ta == Transpose::kYes ? random_matrix(k, m, rng) : random_matrix(m, k, rng);
  const RowMatrix b = c.tb == Transpose::kYes ? random_matrix(n, k, rng) : random_matrix(k, n, rng);
  const RowMatrix op_a = c.ta == Transpose::kYes ? RowMatrix(a.transpose()) : a;
  const RowMatrix op_b = c.tb == Transpose::kYes ? RowMatrix(b.transpose()) : b;
  const RowMatrix start = random_matrix(m, n, rng);
  RowMatrix expected = reference(op_a, op_b);
  if (c.accumulate) expected += start;

  RowMatrix out = start;
  multiply(a, c.ta, b, c.tb, out, c.accumulate, c.force_blas);
  EXPECT_LT((out - expected).cwiseAbs().maxCoeff(), 1e-4f);

  // into a block of a wider matrix (row stride larger than the block's width): the rest untouched
  RowMatrix wide = RowMatrix::Constant(m, n + 5, 7.f);
  wide.leftCols(n) = start;
  Eigen::Ref<RowMatrix> block = wide.leftCols(n);
  multiply(a, c.ta, b, c.tb, block, c.accumulate, c.force_blas);
  EXPECT_LT((wide.leftCols(n) - expected).cwiseAbs().maxCoeff(), 1e-4f);
  EXPECT_TRUE((wide.rightCols(5).array() == 7.f).all());
}

INSTANTIATE_TEST_SUITE_P(
    Transpositions, MatrixProductTest,
    ::testing::Values(ProductCase{Transpose::kNo, Transpose::kNo, false, false},
                      ProductCase{Transpose::kNo, Transpose::kYes, false, false},
                      ProductCase{Transpose::kYes, Transpose::kNo, false, false},
                      ProductCase{Transpose::kYes, Transpose::kYes, true, false},
                      ProductCase{Transpose::kNo, Transpose::kNo, false, true},
                      ProductCase{Transpose::kNo, Transpose::kYes, true, true},
                      ProductCase{Transpose::kYes, Transpose::kNo, false, true},
                      ProductCase{Transpose::kYes, Transpose::kNo, true, true},
                      ProductCase{Transpose::kYes, Transpose::kYes, false, true}));

TEST(MatrixProduct, LargeProductsTakeTheBlasPathAndAgreeWithEigen) {
  std::mt19937 rng(5);
  // hide-and-seek's first layer at a small batch: above the threshold
  const RowMatrix x = random_matrix(64, 919, rng), w = random_matrix(919, 256, rng);
  ASSERT_GE(x.rows() * x.cols() * w.cols(), kBlasProductMinMultiplies);
  RowMatrix out(64, 256);
  multiply(x, Transpose::kNo, w, Transpose::kNo, out);
  const RowMatrix eigen = x * w;
  EXPECT_LT((out - eigen).cwiseAbs().maxCoeff(), 1e-3f);
}

TEST(MatrixProduct, ShapeMismatchNamesBothShapes) {
  RowMatrix a(3, 4), b(5, 2), out(3, 2);
  try {
    multiply(a, Transpose::kNo, b, Transpose::kNo, out);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("[3, 4] by [5, 2]"), std::string::npos) << e.what();
  }
  RowMatrix wrong_out(2, 2), b2(4, 2);
  EXPECT_THROW(multiply(a, Transpose::kNo, b2, Transpose::kNo, wrong_out), std::invalid_argument);
}

}  // namespace
}  // namespace rlt
