// The sliding window (core/sliding_window.h):
//   * generic: on a linear problem the newest state after every update
//     equals the full batch over all factors so far (marginalization is exact
//     for linear factors), and the window never holds more than its size;
//   * timing summary (median, p99) of a known list.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ceres/cost_function.h"
#include "core/graph.h"
#include "core/optimizer.h"
#include "core/sliding_window.h"
#include "factors/marginalization_prior.h"
#include "tests/test_random.h"
#include "gtest/gtest.h"

namespace slam {
namespace {

using testing::TestRng;

// r = sum_k A_k x_k - z over Euclidean blocks.
class LinearCost : public ceres::CostFunction {
public:
  LinearCost(std::vector<Eigen::MatrixXd> a, Eigen::VectorXd z)
      : a_(std::move(a)), z_(std::move(z)) {
    set_num_residuals(static_cast<int>(z_.size()));
    for (const auto &m : a_) {
      mutable_parameter_block_sizes()->push_back(static_cast<int>(m.cols()));
    }
  }
  bool Evaluate(double const *const *x, double *residuals,
                double **jacobians) const override {
    Eigen::Map<Eigen::VectorXd> r(residuals, z_.size());
    r = -z_;
    for (size_t k = 0; k < a_.size(); ++k) {
      r += a_[k] * Eigen::Map<const Eigen::VectorXd>(x[k], a_[k].cols());
      if (jacobians != nullptr && jacobians[k] != nullptr) {
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                 Eigen::RowMajor>>(jacobians[k], a_[k].rows(),
                                                   a_[k].cols()) = a_[k];
      }
    }
    return true;
  }

private:
  std::vector<Eigen::MatrixXd> a_;
  Eigen::VectorXd z_;
};

Factor Linear(const std::vector<Key> &keys, TestRng *rng) {
  std::vector<Eigen::MatrixXd> a;
  for (size_t k = 0; k < keys.size(); ++k) {
    Eigen::MatrixXd m(3, 3);
    for (int i = 0; i < 9; ++i)
      m(i / 3, i % 3) = rng->Normal();
    a.push_back(m + 2.0 * Eigen::MatrixXd::Identity(3, 3));
  }
  Factor f;
  f.keys = keys;
  f.cost = std::make_shared<LinearCost>(
      a, Eigen::Vector3d(rng->Normal(), rng->Normal(), rng->Normal()));
  return f;
}

TEST(SlidingWindowTest, LinearNewestStateEqualsFullBatch) {
  TestRng rng(5);
  SlidingWindowOptions options;
  options.window_size = 4;
  options.prior_builder = MakeMarginalizationPrior;
  options.function_tolerance = options.gradient_tolerance =
      options.parameter_tolerance = 1e-14;
  SlidingWindow window(options);
  Graph full;
  OptimizerOptions batch;
  batch.verbose = false;
  batch.function_tolerance = batch.gradient_tolerance =
      batch.parameter_tolerance = 1e-14;
  std::string error;
  for (int k = 0; k < 20; ++k) {
    std::vector<Factor> factors;
    factors.push_back(Linear({Point3Key(k)}, &rng)); // "position fix"
    if (k > 0)
      factors.push_back(Linear({Point3Key(k - 1), Point3Key(k)}, &rng));
    if (k > 1)
      factors.push_back(Linear({Point3Key(k - 2), Point3Key(k)}, &rng));
    full.AddNode(Point3Key(k), {0.0, 0.0, 0.0});
    for (const Factor &f : factors)
      ASSERT_GE(full.AddFactor(f), 0);
    ASSERT_TRUE(window.AddKeyframe(1000 * (k + 1), {{Point3Key(k), {1, 2, 3}}},
                                   factors, &error))
        << error;
    WindowUpdateStats stats;
    ASSERT_TRUE(window.Update(&stats, &error)) << error;
    EXPECT_LE(stats.keyframes, options.window_size);
    EXPECT_EQ(stats.marginalized, k + 1 >= options.window_size);
    Optimize(&full, batch, nullptr);
    const std::vector<double> &a = full.FindNode(Point3Key(k))->value;
    const std::vector<double> &b = window.graph().FindNode(Point3Key(k))->value;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(a[c], b[c], 1e-8) << "k=" << k;
  }
  EXPECT_EQ(window.NumKeyframes(), options.window_size - 1);
  EXPECT_EQ(window.update_seconds().size(), 20u);
  // Marginalised states keep their value at marginalization; Finish() adds
  // the rest.
  window.Finish();
  EXPECT_EQ(window.final_values().size(), 20u);
  // A keyframe must not reference marginalised states; nothing is added.
  const size_t nodes = window.graph().NumNodes();
  EXPECT_FALSE(window.AddKeyframe(
      1000000, {{Point3Key(100), {0, 0, 0}}},
      {Linear({Point3Key(0), Point3Key(100)}, &rng)}, &error));
  EXPECT_EQ(window.graph().NumNodes(), nodes);
}

TEST(SlidingWindowTest, TimingSummary) {
  std::vector<double> t;
  for (int i = 1; i <= 200; ++i)
    t.push_back(i * 1e-3);
  const TimingSummary s = SummarizeTimes(t);
  EXPECT_NEAR(s.median, 100.5e-3, 1e-12);
  EXPECT_NEAR(s.p99, 198e-3, 1e-12);
  EXPECT_NEAR(s.max, 200e-3, 1e-12);
  EXPECT_EQ(s.count, 200u);
}

} // namespace
} // namespace slam
