// The random source of the simulators (datasets/simulator.h,
// datasets/inertial_simulator.h): one std::mt19937_64 whose raw output is
// turned into uniform and normal draws here, so that a seed gives the same
// dataset with every standard library.
#ifndef SLAM_DATASETS_SIMULATION_RANDOM_H_
#define SLAM_DATASETS_SIMULATION_RANDOM_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

namespace slam {

// Uniform and normal draws computed from the raw engine output, so that the
// sequence is the same with every standard library.
class SimulationRandom {
 public:
  explicit SimulationRandom(uint64_t seed) : engine_(seed) {}

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

}  // namespace slam

#endif  // SLAM_DATASETS_SIMULATION_RANDOM_H_
