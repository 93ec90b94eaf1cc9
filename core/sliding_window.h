// Fixed-lag smoother over keyframes: a window of the newest keyframes is
// optimized with Ceres; when the window is full, the oldest keyframe's states
// are marginalised (core/marginalization.h) into a dense linear prior on the
// states they were connected to. Generic over factors and node kinds: a
// keyframe is a set of nodes (e.g. pose, velocity, bias) added together, and
// the factors added with it (e.g. an IMU factor to the previous keyframe).
//
//   SlidingWindowOptions options;
//   options.prior_builder = MakeMarginalizationPrior;  // factors/
//   SlidingWindow window(options);
//   window.AddKeyframe(stamp, {{PoseKey, value}, ...}, {factors...}, &error);
//   window.Update(&stats, &error);  // optimize, then marginalise if full
//
// Update() optimizes the window as it is (at most window_size keyframes),
// then, when it holds window_size keyframes, marginalises the oldest one at
// the optimized values, so that the next keyframe brings it back to
// window_size. The gauge is not anchored by the window: the first keyframe
// needs priors (or fixed nodes), and later ones inherit the marginalization
// prior.
#ifndef SLAM_CORE_SLIDING_WINDOW_H_
#define SLAM_CORE_SLIDING_WINDOW_H_

#include <Eigen/Core>
#include <deque>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/graph.h"
#include "core/marginalization.h"

namespace slam {

struct SlidingWindowOptions {
  int window_size = 10;  // Keyframes optimized together (>= 2).
  // Ceres settings per update: a few LM iterations warm-started from the
  // previous estimate. Sparse normal Cholesky: measured on the inertial
  // window (10 keyframes of 15 dof, 60 s simulated, 601 updates) median
  // 0.19 ms / p99 3.3 ms, against 0.43 / 8.4 ms for dense normal Cholesky
  // (whose dense Jacobian products dominate) and 0.22 / 4.5 ms for
  // dense_schur.
  int max_iterations = 10;
  std::string linear_solver = "sparse_normal_cholesky";
  double function_tolerance = 1e-8;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  // LM starts near Gauss-Newton (as core/optimizer.h): the window is warm
  // started, so the first step is usually accepted.
  double initial_trust_region_radius = 1e12;
  int num_threads = 1;
  MarginalizationOptions marginalization;
  PriorFactorBuilder prior_builder;  // Required once the window fills.
  // First-estimate Jacobians across priors (core/marginalization.h): a node
  // keeps the linearization point of the first prior that touches it in
  // every later marginalization. false: each marginalization linearises at
  // the current values (priors then disagree on unobserved directions).
  bool first_estimate_jacobians = true;
  // Also record every keyframe's joint covariance (its nodes in the order
  // they were added, core/marginals.h) at the values final_values() keeps:
  // right before it is marginalised, and at Finish() for those left. A
  // diagnostic (consistency of the fixed-lag estimate): its time is not part
  // of update_seconds().
  bool final_covariances = false;
};

struct WindowUpdateStats {
  double seconds = 0.0;              // Whole Update() wall time.
  double solve_seconds = 0.0;        // Ceres part.
  double marginalize_seconds = 0.0;  // Marginalization part.
  double covariance_seconds = 0.0;   // final_covariances (not in seconds).
  int iterations = 0;
  double final_chi2 = 0.0;  // g2o-convention chi2 of the window after.
  int keyframes = 0;        // Keyframes optimized.
  bool marginalized = false;
};

class SlidingWindow {
 public:
  using NodeValue = std::pair<Key, std::vector<double>>;

  explicit SlidingWindow(SlidingWindowOptions options);

  // Adds the keyframe's nodes (stamped with `stamp`) and factors. The
  // factors may reference the new nodes and any node still in the window.
  // On failure nothing is added.
  bool AddKeyframe(TimeNs stamp, const std::vector<NodeValue>& nodes,
                   std::vector<Factor> factors, std::string* error);
  // Adds a factor between nodes in the window (e.g. a late measurement).
  bool AddFactor(Factor factor, std::string* error);
  // Optimizes the window; marginalises the oldest keyframe when full.
  bool Update(WindowUpdateStats* stats, std::string* error);

  // Joint covariance of `keys` in the current window (core/marginals.h).
  bool JointCovariance(const std::vector<Key>& keys, Eigen::MatrixXd* joint,
                       std::string* error);

  const Graph& graph() const { return graph_; }
  Graph* mutable_graph() { return &graph_; }
  int NumKeyframes() const { return static_cast<int>(keyframes_.size()); }
  // Keys of the keyframes in the window, oldest first.
  std::vector<std::vector<Key>> WindowKeys() const;
  // The value every state had when it was marginalised (its fixed-lag
  // smoothed estimate), plus, after Finish(), those still in the window.
  const std::map<Key, std::vector<double>>& final_values() const {
    return final_values_;
  }
  // Copies the states still in the window into final_values() (and, with
  // final_covariances, their covariances into final_covariances()).
  void Finish();
  // With options.final_covariances: (keyframe keys, joint covariance) per
  // keyframe, in the order the keyframes left the window (then Finish()'s);
  // an empty matrix where the covariance could not be computed.
  const std::vector<std::pair<std::vector<Key>, Eigen::MatrixXd>>&
  final_covariances() const {
    return final_covariances_;
  }
  // Wall time of every Update() call, seconds.
  const std::vector<double>& update_seconds() const { return update_seconds_; }
  const SlidingWindowOptions& options() const { return options_; }

 private:
  bool MarginalizeOldest(std::string* error);
  void RecordFinalCovariance(const std::vector<Key>& keys);

  struct Keyframe {
    TimeNs stamp = 0;
    std::vector<Key> keys;
  };
  SlidingWindowOptions options_;
  Graph graph_;
  std::deque<Keyframe> keyframes_;
  std::map<Key, std::vector<double>> final_values_;
  std::vector<std::pair<std::vector<Key>, Eigen::MatrixXd>> final_covariances_;
  LinearizationPoints linearization_points_;  // FEJ points of prior nodes.
  std::vector<double> update_seconds_;
};

// Median and 99th percentile (nearest rank) of a list of durations.
struct TimingSummary {
  double median = 0.0;
  double p99 = 0.0;
  double max = 0.0;
  double total = 0.0;
  size_t count = 0;
};
TimingSummary SummarizeTimes(std::vector<double> seconds);

}  // namespace slam

#endif  // SLAM_CORE_SLIDING_WINDOW_H_
