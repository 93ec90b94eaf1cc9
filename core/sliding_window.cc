#include "core/sliding_window.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <utility>

#include "ceres/problem.h"
#include "ceres/solver.h"
#include "ceres/types.h"
#include "core/marginals.h"
#include "core/openmp_scope.h"

namespace slam {
namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

SlidingWindow::SlidingWindow(SlidingWindowOptions options)
    : options_(std::move(options)) {}

bool SlidingWindow::AddKeyframe(TimeNs stamp,
                                const std::vector<NodeValue>& nodes,
                                std::vector<Factor> factors,
                                std::string* error) {
  if (!keyframes_.empty() && stamp <= keyframes_.back().stamp) {
    *error = "keyframe stamps must increase";
    return false;
  }
  Keyframe keyframe;
  keyframe.stamp = stamp;
  auto roll_back = [&]() {
    for (const Key& key : keyframe.keys) graph_.RemoveNode(key);
  };
  for (const auto& [key, value] : nodes) {
    Node* node = graph_.AddNode(key, value);
    if (node == nullptr) {
      *error = "keyframe node " + key.ToString() +
               (graph_.HasNode(key) ? " already exists" : " has a bad size");
      roll_back();
      return false;
    }
    node->stamp = stamp;
    node->has_stamp = true;
    keyframe.keys.push_back(key);
  }
  for (Factor& factor : factors) {
    const FactorType type = factor.type;
    if (graph_.AddFactor(std::move(factor)) < 0) {
      *error = std::string("keyframe factor (") + FactorTypeName(type) +
               ") references a node outside the window or has wrong sizes";
      roll_back();  // Removes the factors added so far with the nodes.
      return false;
    }
  }
  keyframes_.push_back(std::move(keyframe));
  return true;
}

bool SlidingWindow::AddFactor(Factor factor, std::string* error) {
  if (graph_.AddFactor(std::move(factor)) < 0) {
    *error = "factor references a node outside the window or has wrong sizes";
    return false;
  }
  return true;
}

bool SlidingWindow::Update(WindowUpdateStats* stats, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  WindowUpdateStats local;
  local.keyframes = NumKeyframes();
  {
    ceres::Problem problem(Graph::ProblemOptions());
    graph_.BuildProblem(&problem);
    ceres::Solver::Options solver;
    if (!ceres::StringToLinearSolverType(
            [&] {
              std::string upper = options_.linear_solver;
              for (char& c : upper) c = static_cast<char>(std::toupper(c));
              return upper;
            }(),
            &solver.linear_solver_type)) {
      *error = "unknown linear solver '" + options_.linear_solver + "'";
      return false;
    }
    solver.max_num_iterations = options_.max_iterations;
    solver.function_tolerance = options_.function_tolerance;
    solver.gradient_tolerance = options_.gradient_tolerance;
    solver.parameter_tolerance = options_.parameter_tolerance;
    solver.num_threads = options_.num_threads;
    solver.initial_trust_region_radius = options_.initial_trust_region_radius;
    solver.logging_type = ceres::SILENT;
    solver.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    {
      const SerialOpenMpScope serial_openmp;
      ceres::Solve(solver, &problem, &summary);
    }
    local.iterations = static_cast<int>(summary.iterations.size());
    local.solve_seconds = SecondsSince(start);
    if (summary.termination_type == ceres::FAILURE) {
      *error = "window solve failed: " + summary.message;
      return false;
    }
  }
  local.final_chi2 = graph_.Chi2();
  if (NumKeyframes() >= std::max(options_.window_size, 2)) {
    if (options_.final_covariances) {
      const auto cov_start = std::chrono::steady_clock::now();
      RecordFinalCovariance(keyframes_.front().keys);
      local.covariance_seconds = SecondsSince(cov_start);
    }
    const auto marg_start = std::chrono::steady_clock::now();
    if (!MarginalizeOldest(error)) return false;
    local.marginalize_seconds = SecondsSince(marg_start);
    local.marginalized = true;
  }
  local.seconds = SecondsSince(start) - local.covariance_seconds;
  update_seconds_.push_back(local.seconds);
  if (stats != nullptr) *stats = local;
  return true;
}

bool SlidingWindow::MarginalizeOldest(std::string* error) {
  const Keyframe& oldest = keyframes_.front();
  std::vector<std::pair<Key, std::vector<double>>> values;
  for (const Key& key : oldest.keys) {
    values.emplace_back(key, graph_.FindNode(key)->value);
  }
  FactorId prior_id = -1;
  if (!MarginalizeNodes(&graph_, oldest.keys, options_.marginalization,
                        options_.prior_builder, &prior_id, error,
                        options_.first_estimate_jacobians
                            ? &linearization_points_
                            : nullptr)) {
    return false;
  }
  for (auto& [key, value] : values) {
    linearization_points_.erase(key);
    final_values_[key] = std::move(value);
  }
  // A node entering a prior for the first time keeps this linearization
  // point (the prior's x0: its current value) from now on.
  if (const Factor* prior = graph_.FindFactor(prior_id)) {
    for (const Key& key : prior->keys) {
      if (linearization_points_.count(key) == 0) {
        linearization_points_[key] = graph_.FindNode(key)->value;
      }
    }
  }
  keyframes_.pop_front();
  return true;
}

bool SlidingWindow::JointCovariance(const std::vector<Key>& keys,
                                    Eigen::MatrixXd* joint,
                                    std::string* error) {
  return ComputeJointMarginal(&graph_, keys, joint, error);
}

std::vector<std::vector<Key>> SlidingWindow::WindowKeys() const {
  std::vector<std::vector<Key>> keys;
  for (const Keyframe& k : keyframes_) keys.push_back(k.keys);
  return keys;
}

void SlidingWindow::RecordFinalCovariance(const std::vector<Key>& keys) {
  Eigen::MatrixXd joint;
  std::string ignored;
  if (!JointCovariance(keys, &joint, &ignored)) joint.resize(0, 0);
  final_covariances_.emplace_back(keys, std::move(joint));
}

void SlidingWindow::Finish() {
  for (const Keyframe& k : keyframes_) {
    if (options_.final_covariances) RecordFinalCovariance(k.keys);
    for (const Key& key : k.keys) {
      final_values_[key] = graph_.FindNode(key)->value;
    }
  }
}

TimingSummary SummarizeTimes(std::vector<double> seconds) {
  TimingSummary s;
  s.count = seconds.size();
  if (seconds.empty()) return s;
  std::sort(seconds.begin(), seconds.end());
  const size_t n = seconds.size();
  s.median =
      n % 2 == 1 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
  const size_t rank = static_cast<size_t>(std::ceil(0.99 * n));
  s.p99 = seconds[std::min(n - 1, rank == 0 ? 0 : rank - 1)];
  s.max = seconds.back();
  for (double t : seconds) s.total += t;
  return s;
}

}  // namespace slam
