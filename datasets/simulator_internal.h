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
#include "datasets/simulation_random.h"
#include "datasets/simulator.h"

namespace slam {
namespace simulator_internal {

using Random = SimulationRandom;  // datasets/simulation_random.h

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
