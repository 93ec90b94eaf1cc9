// Pieces of the simulator shared by datasets/simulator.cc (pose-graph worlds)
// and datasets/landmark_simulator.cc (landmark and camera worlds). Internal
// to the datasets library: not part of its interface.
#ifndef SLAM_DATASETS_SIMULATOR_INTERNAL_H_
#define SLAM_DATASETS_SIMULATOR_INTERNAL_H_

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/lie.h"
#include "datasets/simulator.h"

namespace slam {
namespace simulator_internal {

// Uniform and normal draws computed from the raw engine output, so that the
// sequence is the same with every standard library.
class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1), 53 random bits.
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [0, n), n > 0, without modulo bias.
  int64_t UniformInt(int64_t n) {
    const uint64_t un = static_cast<uint64_t>(n);
    const uint64_t limit = std::numeric_limits<uint64_t>::max() -
                           std::numeric_limits<uint64_t>::max() % un;
    uint64_t r;
    do {
      r = engine_();
    } while (r >= limit);
    return static_cast<int64_t>(r % un);
  }
  bool Bernoulli(double p) { return Uniform() < p; }
  // Standard normal (Box-Muller, one draw per call).
  double Normal() {
    const double u1 = 1.0 - Uniform();  // (0, 1].
    const double u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  Eigen::Quaterniond UniformRotation() {
    Eigen::Vector4d v;
    do {
      v << Normal(), Normal(), Normal(), Normal();
    } while (v.norm() < 1e-6);
    v.normalize();
    return Eigen::Quaterniond(v[3], v[0], v[1], v[2]);
  }

 private:
  std::mt19937_64 engine_;
};

// The true trajectory: SE(2) poses (grid2d) or SE(3) poses.
struct TruePoses {
  bool is_3d = false;
  std::vector<Pose2> poses2;
  std::vector<Pose3> poses3;
  std::vector<Eigen::Vector3d> positions;  // For the loop-closure search.

  int size() const {
    return static_cast<int>(is_3d ? poses3.size() : poses2.size());
  }
};

// The trajectories of the grid worlds (see datasets/simulator.h).
void GridWorld2d(const SimulationConfig::World& world, Random* random,
                 TruePoses* truth);
void GridWorld3d(const SimulationConfig::World& world, Random* random,
                 TruePoses* truth);

// v2t(e)^-1 with e drawn from the between factor's error distribution, and
// the matching information matrices (see datasets/simulator.h, Noise).
Pose2 SampleNoise2(const SimulationConfig::Noise& noise, Random* random);
Pose3 SampleNoise3(const SimulationConfig::Noise& noise, Random* random);
Eigen::Matrix3d Information2(const SimulationConfig::Noise& noise);
Eigen::Matrix<double, 6, 6> Information3(const SimulationConfig::Noise& noise);

// Range checks; false with "NAME must be ..." in *error.
bool CheckPositive(double value, const char* name, std::string* error);
bool CheckProbability(double value, const char* name, std::string* error);

// Landmark and camera worlds (datasets/landmark_simulator.cc).
bool IsLandmarkWorld(const std::string& type);
bool ValidateLandmarkConfig(const SimulationConfig& config, std::string* error);
// Fills *result (already reset) for a landmark world; config validated.
bool SimulateLandmarkWorld(const SimulationConfig& config, Random* random,
                           SimulationResult* result, std::string* error);

}  // namespace simulator_internal
}  // namespace slam

#endif  // SLAM_DATASETS_SIMULATOR_INTERNAL_H_
