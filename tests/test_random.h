// The seeded random source of the core and factor tests: poses, rotations
// and positive-definite information matrices. Every draw is a fixed sequence
// for a given seed (std::mt19937), so the tests are deterministic.
#ifndef SLAM_TESTS_TEST_RANDOM_H_
#define SLAM_TESTS_TEST_RANDOM_H_

#include <cmath>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/lie.h"

namespace slam::testing {

class TestRng {
 public:
  explicit TestRng(unsigned seed) : gen_(seed) {}

  double Uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(gen_);
  }
  double Normal() { return std::normal_distribution<double>(0.0, 1.0)(gen_); }
  Eigen::Vector3d Normal3() {
    return Eigen::Vector3d(Normal(), Normal(), Normal());
  }
  Eigen::Vector3d UnitVector() {
    return Eigen::Vector3d(Normal(), Normal(), Normal()).normalized();
  }
  // Uniform on SO(3): a normalized 4D Gaussian.
  Eigen::Quaterniond Quaternion() {
    Eigen::Vector4d v(Normal(), Normal(), Normal(), Normal());
    v.normalize();
    return Eigen::Quaterniond(v[3], v[0], v[1], v[2]);
  }
  Pose2 RandomPose2(double extent = 20.0) {
    return Pose2(Uniform(-extent, extent), Uniform(-extent, extent),
                 Uniform(-M_PI, M_PI));
  }
  Pose3 RandomPose3(double extent = 20.0) {
    return Pose3(
        Eigen::Vector3d(Uniform(-extent, extent), Uniform(-extent, extent),
                        Uniform(-extent, extent)),
        Quaternion());
  }
  // scale * (A A^T + I) with A standard normal: symmetric positive definite
  // with off-diagonal terms.
  Eigen::MatrixXd SpdMatrix(int n, double scale = 1.0) {
    Eigen::MatrixXd a(n, n);
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) a(r, c) = Normal();
    }
    return scale * (a * a.transpose() + Eigen::MatrixXd::Identity(n, n));
  }
  // Like real information matrices: off-diagonal terms and per-axis scales
  // spread over three decades.
  Eigen::MatrixXd ScaledInformation(int n) {
    Eigen::MatrixXd a(n, n);
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) a(r, c) = Normal();
    }
    Eigen::MatrixXd info =
        a * a.transpose() + 0.5 * Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd scale(n);
    for (int i = 0; i < n; ++i) scale[i] = std::pow(10.0, Uniform(-1.0, 2.0));
    return scale.asDiagonal() * info * scale.asDiagonal();
  }

 private:
  std::mt19937 gen_;
};

}  // namespace slam::testing

#endif  // SLAM_TESTS_TEST_RANDOM_H_
