// A linear cost function for the marginalization and sliding-window tests:
// r = sum_k A_k x_k - z over Euclidean parameter blocks, so that problems
// built from it are exactly linear least squares.
#ifndef SLAM_TESTS_TEST_LINEAR_COST_H_
#define SLAM_TESTS_TEST_LINEAR_COST_H_

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "ceres/cost_function.h"

namespace slam::testing {

class LinearCost : public ceres::CostFunction {
 public:
  LinearCost(std::vector<Eigen::MatrixXd> a, Eigen::VectorXd z)
      : a_(std::move(a)), z_(std::move(z)) {
    set_num_residuals(static_cast<int>(z_.size()));
    for (const auto& m : a_) {
      mutable_parameter_block_sizes()->push_back(static_cast<int>(m.cols()));
    }
  }
  bool Evaluate(double const* const* x, double* residuals,
                double** jacobians) const override {
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

}  // namespace slam::testing

#endif  // SLAM_TESTS_TEST_LINEAR_COST_H_
