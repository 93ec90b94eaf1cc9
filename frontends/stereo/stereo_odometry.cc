#include "frontends/stereo/stereo_odometry.h"
#include "frontends/stereo/stereo_common.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/core/hal/hal.hpp>
#include <opencv2/features2d.hpp>

#include "ceres/ceres.h"
#include "core/lie.h"
#include "core/openmp_scope.h"
#include "factors/landmark_factors.h"
#include "factors/pose_factors.h"

namespace slam {
namespace {

using stereo::Hamming;

double RotationAngle(const Pose3& p) { return Eigen::AngleAxisd(p.q).angle(); }

// V(phi) of SE(3)'s exponential: t = V(phi) rho.
Eigen::Matrix3d SE3V(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d k = Skew<double>(phi);
  if (theta < 1e-6) return Eigen::Matrix3d::Identity() + 0.5 * k;
  return Eigen::Matrix3d::Identity() +
         (1.0 - std::cos(theta)) / (theta * theta) * k +
         (theta - std::sin(theta)) / (theta * theta * theta) * k * k;
}

}  // namespace

Pose3 ScrewInterpolation(const Pose3& p, double s) {
  // Exp(s Log(p)) on SE(3): the motion of constant velocity in the moving
  // frame (a circular arc for a constant turn rate).
  const Eigen::Vector3d phi = QuaternionLog(p.q);
  const Eigen::Vector3d rho = SE3V(phi).inverse() * p.t;
  return Pose3(SE3V(s * phi) * (s * rho), QuaternionExp<double>(s * phi));
}

namespace {

ceres::Solver::Options SolverOptions(int iterations,
                                     ceres::LinearSolverType solver) {
  ceres::Solver::Options o;
  o.max_num_iterations = iterations;
  o.linear_solver_type = solver;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  o.num_threads = 1;
  return o;
}

}  // namespace

Eigen::Matrix3d StereoInformation(double pixel_sigma, double disparity_sigma) {
  // (u_L, u_R, v) = (u_L, u_L - d, v) with u_L, v, d independent.
  const double p2 = pixel_sigma * pixel_sigma;
  Eigen::Matrix3d covariance;
  covariance << p2, p2, 0, p2, p2 + disparity_sigma * disparity_sigma, 0, 0, 0,
      p2;
  return covariance.inverse();
}

bool ValidateStereoOdometryConfig(const StereoOdometryConfig& c,
                                  std::string* error) {
  auto fail = [&](const char* message) {
    *error = message;
    return false;
  };
  if (!(c.pixel_sigma > 0) || !(c.disparity_sigma > 0) ||
      !(c.scale_factor >= 1) || !(c.chi2_stereo > 0) || !(c.chi2_mono > 0))
    return fail(
        "pixel_sigma, disparity_sigma, chi2 thresholds must be > 0, "
        "scale_factor >= 1");
  if (!(c.close_depth_baselines > 0) || c.far_point_min_keyframes < 2 ||
      !(c.min_parallax >= 0))
    return fail(
        "close_depth_baselines > 0, far_point_min_keyframes >= 2, "
        "min_parallax >= 0");
  if (c.local_map_keyframes < 1 || !(c.search_radius > 0) ||
      c.max_descriptor_distance < 0 || c.max_descriptor_distance > 256 ||
      !(c.match_ratio > 0 && c.match_ratio <= 1))
    return fail(
        "tracking: local_map_keyframes >= 1, search_radius > 0, "
        "max_descriptor_distance in [0, 256], match_ratio in (0, 1]");
  if (c.pose_rounds < 1 || c.pose_iterations < 1 || c.min_inliers < 6)
    return fail("pose_rounds, pose_iterations >= 1, min_inliers >= 6");
  if (!(c.pnp_reprojection_error > 0) || c.pnp_iterations < 1 ||
      !(c.pnp_ratio > 0 && c.pnp_ratio <= 1))
    return fail(
        "pnp: reprojection_error > 0, iterations >= 1, ratio in (0, 1]");
  if (!(c.keyframe_tracked_ratio >= 0 && c.keyframe_tracked_ratio <= 1) ||
      c.keyframe_close_tracked < 0 || c.keyframe_new_close < 0 ||
      !(c.keyframe_rotation > 0) || c.keyframe_min_frames < 1 ||
      c.keyframe_max_frames < c.keyframe_min_frames || c.min_initial_points < 6)
    return fail(
        "keyframes: tracked_ratio in [0, 1], close_tracked and new_close "
        ">= 0, rotation > 0, 1 <= min_frames <= max_frames, "
        "min_initial_points >= 6");
  if (!(c.between_acceleration_sigma >= 0) ||
      !std::isfinite(c.between_acceleration_sigma))
    return fail("keyframes: between_acceleration_sigma >= 0 and finite");
  if (c.min_point_observations < 1 || c.cull_after_keyframes < 0)
    return fail("min_point_observations >= 1, cull_after_keyframes >= 0");
  if (c.window_keyframes < 1 || c.local_ba_iterations < 0 ||
      c.final_ba_iterations < 0)
    return fail("bundle adjustment: window >= 1, iterations >= 0");
  return true;
}

StereoOdometry::StereoOdometry(const StereoOdometryConfig& config,
                               const StereoCalibration& calibration,
                               int image_width, int image_height)
    : config_(config),
      calibration_(calibration),
      width_(image_width),
      height_(image_height) {
  pinhole_.fx = calibration.fx;
  pinhole_.fy = calibration.fy;
  pinhole_.cx = calibration.cx;
  pinhole_.cy = calibration.cy;
}

Pose3 StereoOdometry::KeyframePose(int64_t keyframe) const {
  return NodePose3(*graph_.FindNode(Pose3Key(keyframe)));
}

Eigen::Vector3d StereoOdometry::PointValue(int64_t point) const {
  const std::vector<double>& v = graph_.FindNode(Point3Key(point))->value;
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Eigen::Vector3d StereoOdometry::Position(int64_t point) const {
  return IsLastFramePoint(point)
             ? last_frame_points_[LastFramePointIndex(point)].position
             : PointValue(point);
}

const cv::Mat& StereoOdometry::Descriptor(int64_t point) const {
  return IsLastFramePoint(point)
             ? last_frame_points_[LastFramePointIndex(point)].descriptor
             : points_[point].descriptor;
}

void StereoOdometry::UpdateLastFramePoints(const StereoFeatureFrame& frame,
                                           const Pose3& pose,
                                           const std::vector<Match>& matches,
                                           bool keyframe) {
  last_frame_points_.clear();
  if (keyframe || !config_.track_last_frame) return;
  std::vector<bool> matched(frame.size(), false);
  for (const Match& m : matches) matched[m.keypoint] = true;
  const Eigen::Matrix3d r = pose.q.toRotationMatrix();
  for (size_t i = 0; i < frame.size(); ++i) {
    if (matched[i] || !IsClose(frame, i)) continue;
    last_frame_points_.push_back({r * StereoPoint(frame, i) + pose.t,
                                  frame.descriptors.row(static_cast<int>(i))});
  }
}

Eigen::Vector3d StereoOdometry::StereoPoint(const StereoFeatureFrame& frame,
                                            size_t i) const {
  const double disparity = frame.keypoints[i].pt.x - frame.u_right[i];
  const double z = calibration_.fx * calibration_.baseline / disparity;
  return Eigen::Vector3d(
      (frame.keypoints[i].pt.x - calibration_.cx) * z / calibration_.fx,
      (frame.keypoints[i].pt.y - calibration_.cy) * z / calibration_.fy, z);
}

void StereoOdometry::TrackingInformation(const StereoFeatureFrame& frame,
                                         const std::vector<Match>& matches,
                                         const Pose3& pose,
                                         bool last_frame_only,
                                         Matrix6* information) const {
  information->setZero();
  const std::vector<double> camera = Pose3Value(pose);
  Eigen::Matrix<double, 7, 6, Eigen::RowMajor> plus;
  graph_.ManifoldFor(NodeKind::kPose3)
      ->PlusJacobian(camera.data(), plus.data());
  for (const Match& m : matches) {
    if (last_frame_only && !IsLastFramePoint(m.point)) continue;
    if (config_.far_points_wait && !IsLastFramePoint(m.point) &&
        !points_[m.point].confirmed) {
      continue;  // Not in the refinement (step 4).
    }
    Factor factor;
    if (!MakeObservationFactor(frame, m.keypoint, Pose3Key(0), Point3Key(0),
                               &factor)) {
      continue;
    }
    const Eigen::Vector3d x = Position(m.point);
    const double* parameters[2] = {camera.data(), x.data()};
    const int n = factor.cost->num_residuals();
    Eigen::Matrix<double, 3, 7, Eigen::RowMajor> jacobian;
    double residuals[3];
    double* jacobians[2] = {jacobian.data(), nullptr};
    if (!factor.cost->Evaluate(parameters, residuals, jacobians)) continue;
    const Eigen::MatrixXd j = jacobian.topRows(n) * plus;
    *information += j.transpose() * j;
  }
}

void StereoOdometry::ChainTracking(const StereoFeatureFrame& frame,
                                   const std::vector<Match>& matches,
                                   const Pose3& previous, const Pose3& pose,
                                   bool after_keyframe) {
  if (!config_.keyframe_odometry) return;
  // This frame's pose information, given the points it was tracked
  // against: the map's when the previous frame is the keyframe, else the
  // previous frame's own points (its map matches are in the local map of
  // the keyframe already, or the keyframe observes them).
  Matrix6 information;
  TrackingInformation(frame, matches, pose,
                      !after_keyframe && config_.track_last_frame,
                      &information);
  const Eigen::LDLT<Matrix6> ldlt(information);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0) ||
      !(ldlt.vectorD().minCoeff() > 1e-9 * ldlt.vectorD().maxCoeff())) {
    chain_valid_ = false;  // A step without information breaks the chain.
    return;
  }
  const Matrix6 step_covariance = ldlt.solve(Matrix6::Identity());
  if (after_keyframe) {
    chain_valid_ = true;
    chain_ = previous.Inverse() * pose;
    chain_covariance_ = step_covariance;
    return;
  }
  if (!chain_valid_) return;
  // Z = Z_prev S with right perturbations (t + R rho, R Exp(phi)) of both:
  // delta_Z = A delta_prev + delta_S, A = [R_S^T, -R_S^T [t_S]x; 0, R_S^T].
  const Pose3 step = previous.Inverse() * pose;
  const Eigen::Matrix3d rt = step.q.conjugate().toRotationMatrix();
  Matrix6 a = Matrix6::Zero();
  a.topLeftCorner<3, 3>() = rt;
  a.topRightCorner<3, 3>() = -rt * Skew<double>(step.t);
  a.bottomRightCorner<3, 3>() = rt;
  chain_ = chain_ * step;
  chain_covariance_ = a * chain_covariance_ * a.transpose() + step_covariance;
}

Pose3 StereoOdometry::FramePose(const FrameRecord& record) const {
  if (record.keyframe < 0) return Pose3();
  const Pose3 reference = KeyframePose(record.keyframe);
  const size_t next = static_cast<size_t>(record.keyframe) + 1;
  const bool interpolate =
      config_.interpolate_between_keyframes && next < keyframes_.size();
  if (!interpolate &&
      (next >= keyframes_.size() || !keyframes_[next].has_chain)) {
    return reference * record.keyframe_to_frame;
  }
  const Keyframe& a = keyframes_[record.keyframe];
  const Keyframe& b = keyframes_[next];
  const double s = static_cast<double>(record.index - a.frame_index) /
                   static_cast<double>(b.frame_index - a.frame_index);
  const Pose3 between = reference.Inverse() * KeyframePose(next);
  // What bundle adjustment changed between the two keyframes against their
  // tracking, spread along the frames between them by their share of it.
  Pose3 pose = reference * record.keyframe_to_frame;
  if (b.has_chain) {
    const Pose3 delta = between * b.chain_from_previous.Inverse();
    const Pose3 part(s * delta.t,
                     Eigen::Quaterniond::Identity().slerp(s, delta.q));
    pose = reference * part * record.keyframe_to_frame;
  }
  // The position at the share of the way between the two keyframes
  // (constant velocity), the rotation as tracked: one frame's rotation is
  // held by all its points, the far ones too, its position by the few close
  // ones (interpolating the rotation as well cost TUM fr1/rpy's hand-held
  // turns 0.37 -> 0.51 deg of one-frame RPE).
  if (interpolate) {
    pose.t = (reference * ScrewInterpolation(between, s)).t;
  }
  return pose;
}

std::vector<int64_t> StereoOdometry::LocalMapPoints(int64_t frame_index) {
  std::vector<int64_t> local;
  const int64_t n = static_cast<int64_t>(keyframes_.size());
  for (int64_t k = std::max<int64_t>(0, n - config_.local_map_keyframes); k < n;
       ++k) {
    for (int64_t p : keyframes_[k].point_of_keypoint) {
      if (p < 0 || !point_alive_[p] || points_[p].local_stamp == frame_index)
        continue;
      points_[p].local_stamp = frame_index;
      local.push_back(p);
    }
  }
  return local;
}

std::vector<StereoOdometry::Match> StereoOdometry::SearchByProjection(
    const StereoFeatureFrame& frame, const Pose3& pose,
    const std::vector<int64_t>& points, double radius) const {
  // Keypoints on a grid of cells for the window lookups.
  constexpr int kCell = 16;
  const int cols = width_ / kCell + 1, rows = height_ / kCell + 1;
  std::vector<std::vector<int>> grid(cols * rows);
  for (size_t i = 0; i < frame.size(); ++i) {
    const cv::Point2f& pt = frame.keypoints[i].pt;
    const int cx = std::clamp(static_cast<int>(pt.x) / kCell, 0, cols - 1);
    const int cy = std::clamp(static_cast<int>(pt.y) / kCell, 0, rows - 1);
    grid[cy * cols + cx].push_back(static_cast<int>(i));
  }
  const Eigen::Matrix3d rt = pose.q.conjugate().toRotationMatrix();
  const double max_scale = std::pow(config_.scale_factor, 7);
  std::vector<Match> best(frame.size(), {-1, -1, 1 << 30});
  for (int64_t p : points) {
    const Eigen::Vector3d pc = rt * (Position(p) - pose.t);
    if (!(pc.z() > 0.1 * calibration_.baseline)) continue;
    const double u = calibration_.fx * pc.x() / pc.z() + calibration_.cx;
    const double v = calibration_.fy * pc.y() / pc.z() + calibration_.cy;
    if (u < 0 || v < 0 || u >= width_ || v >= height_) continue;
    const double ur = u - calibration_.fx * calibration_.baseline / pc.z();
    const double r_max = radius * max_scale;
    const int x0 = std::max(0, static_cast<int>((u - r_max) / kCell));
    const int x1 = std::min(cols - 1, static_cast<int>((u + r_max) / kCell));
    const int y0 = std::max(0, static_cast<int>((v - r_max) / kCell));
    const int y1 = std::min(rows - 1, static_cast<int>((v + r_max) / kCell));
    int best_d = 1 << 30, second_d = 1 << 30, best_i = -1;
    for (int gy = y0; gy <= y1; ++gy) {
      for (int gx = x0; gx <= x1; ++gx) {
        for (int i : grid[gy * cols + gx]) {
          const cv::KeyPoint& k = frame.keypoints[i];
          const double r = radius * std::pow(config_.scale_factor, k.octave);
          const double du = k.pt.x - u, dv = k.pt.y - v;
          if (du * du + dv * dv > r * r) continue;
          if (frame.HasStereo(i) && std::abs(frame.u_right[i] - ur) > r)
            continue;
          const int d = Hamming(Descriptor(p), 0, frame.descriptors, i);
          if (d < best_d) {
            second_d = best_d;
            best_d = d;
            best_i = i;
          } else if (d < second_d) {
            second_d = d;
          }
        }
      }
    }
    if (best_i < 0 || best_d > config_.max_descriptor_distance) continue;
    if (second_d < (1 << 30) && best_d >= config_.match_ratio * second_d)
      continue;
    if (best_d < best[best_i].distance) best[best_i] = {best_i, p, best_d};
  }
  // One keypoint per point as well: the closest in descriptor.
  std::vector<Match> matches;
  for (const Match& m : best) {
    if (m.keypoint >= 0) matches.push_back(m);
  }
  std::sort(matches.begin(), matches.end(), [](const Match& a, const Match& b) {
    return a.point != b.point ? a.point < b.point : a.distance < b.distance;
  });
  matches.erase(std::unique(matches.begin(), matches.end(),
                            [](const Match& a, const Match& b) {
                              return a.point == b.point;
                            }),
                matches.end());
  return matches;
}

std::vector<StereoOdometry::Match> StereoOdometry::SearchByDescriptor(
    const StereoFeatureFrame& frame, const std::vector<int64_t>& points) const {
  std::vector<Match> matches;
  if (points.size() < 2 || frame.size() < 2) return matches;
  cv::Mat map_descriptors(static_cast<int>(points.size()), 32, CV_8U);
  for (size_t k = 0; k < points.size(); ++k) {
    points_[points[k]].descriptor.copyTo(
        map_descriptors.row(static_cast<int>(k)));
  }
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(frame.descriptors, map_descriptors, knn, 2);
  std::vector<Match> best(points.size(), {-1, -1, 1 << 30});
  for (const auto& m : knn) {
    if (m.size() < 2) continue;
    if (m[0].distance > config_.max_descriptor_distance ||
        m[0].distance >= config_.pnp_ratio * m[1].distance) {
      continue;
    }
    Match& b = best[m[0].trainIdx];
    if (m[0].distance < b.distance) {
      b = {m[0].queryIdx, points[m[0].trainIdx],
           static_cast<int>(m[0].distance)};
    }
  }
  for (const Match& m : best) {
    if (m.keypoint >= 0) matches.push_back(m);
  }
  return matches;
}

bool StereoOdometry::PnpRansac(const StereoFeatureFrame& frame,
                               const std::vector<Match>& matches,
                               Pose3* pose) const {
  if (matches.size() < 6) return false;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const Match& m : matches) {
    const Eigen::Vector3d p = Position(m.point);
    object.emplace_back(p.x(), p.y(), p.z());
    image.emplace_back(frame.keypoints[m.keypoint].pt);
  }
  const cv::Matx33d k(calibration_.fx, 0, calibration_.cx, 0, calibration_.fy,
                      calibration_.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(object, image, k, cv::noArray(), rvec, tvec, false,
                          config_.pnp_iterations,
                          static_cast<float>(config_.pnp_reprojection_error),
                          0.99, inliers, cv::SOLVEPNP_EPNP) ||
      static_cast<int>(inliers.size()) < config_.min_inliers / 2) {
    return false;
  }
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  Eigen::Matrix3d r_cw;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r_cw(i, j) = r(i, j);
  const Eigen::Vector3d t_cw(tvec.at<double>(0), tvec.at<double>(1),
                             tvec.at<double>(2));
  // T_world_camera = T_camera_world^-1.
  const Eigen::Quaterniond q_cw(r_cw);
  *pose = Pose3(t_cw, q_cw.normalized()).Inverse();
  return true;
}

bool StereoOdometry::MakeObservationFactor(const StereoFeatureFrame& frame,
                                           int keypoint, const Key& camera,
                                           const Key& point,
                                           Factor* factor) const {
  const cv::KeyPoint& k = frame.keypoints[keypoint];
  const double sigma =
      config_.pixel_sigma * std::pow(config_.scale_factor, k.octave);
  const double info = 1.0 / (sigma * sigma);
  std::string error;
  if (IsClose(frame, keypoint)) {
    return MakeStereo(camera, point, calibration_,
                      Eigen::Vector3d(k.pt.x, frame.u_right[keypoint], k.pt.y),
                      StereoInformation(sigma, config_.disparity_sigma), factor,
                      &error);
  }
  return MakeReprojection(camera, point, pinhole_,
                          Eigen::Vector2d(k.pt.x, k.pt.y),
                          info * Eigen::Matrix2d::Identity(), factor, &error);
}

bool StereoOdometry::IsClose(const StereoFeatureFrame& frame,
                             size_t keypoint) const {
  return frame.HasStereo(keypoint) &&
         frame.keypoints[keypoint].pt.x - frame.u_right[keypoint] >=
             calibration_.fx / config_.close_depth_baselines;
}

double StereoOdometry::Chi2Threshold(const Factor& factor) const {
  return factor.type == FactorType::kStereo ? config_.chi2_stereo
                                            : config_.chi2_mono;
}

int StereoOdometry::OptimizePose(const StereoFeatureFrame& frame,
                                 std::vector<Match>* matches,
                                 Pose3* pose) const {
  std::vector<double> camera = Pose3Value(*pose);
  std::vector<Factor> factors(matches->size());
  std::vector<std::array<double, 3>> values(matches->size());
  for (size_t k = 0; k < matches->size(); ++k) {
    const Match& m = (*matches)[k];
    const Eigen::Vector3d p = Position(m.point);
    values[k] = {p.x(), p.y(), p.z()};
    MakeObservationFactor(frame, m.keypoint, Pose3Key(0), Point3Key(0),
                          &factors[k]);
  }
  std::vector<bool> inlier(matches->size(), true);
  // Unconfirmed far points are classified, not used (step 4).
  std::vector<bool> informs(matches->size());
  for (size_t k = 0; k < matches->size(); ++k) {
    const int64_t p = (*matches)[k].point;
    informs[k] =
        !config_.far_points_wait || IsLastFramePoint(p) || points_[p].confirmed;
  }
  const ceres::Manifold* manifold = graph_.ManifoldFor(NodeKind::kPose3);
  // With refine_with_structure, copies of the observing keyframes' poses
  // (held fixed); the map itself is not changed.
  std::map<int64_t, std::vector<double>> keyframe_values;
  std::vector<bool> free_point(matches->size());
  for (size_t k = 0; k < matches->size(); ++k) {
    free_point[k] =
        config_.refine_with_structure && !IsLastFramePoint((*matches)[k].point);
  }
  // Each free point's keyframe observations: the point must still agree
  // with them (a wrong match would pull it away).
  std::vector<std::vector<std::pair<const Factor*, const double*>>> held_by(
      matches->size());
  auto chi2_of = [](const Factor& f, const double* camera, const double* point,
                    double* chi2) {
    const double* params[2] = {camera, point};
    double r[3];
    const bool ok = f.cost->Evaluate(params, r, nullptr);
    const int n = f.type == FactorType::kStereo ? 3 : 2;
    *chi2 = 0;
    for (int i = 0; i < n; ++i) *chi2 += r[i] * r[i];
    return ok;
  };
  int inliers = 0;
  for (int round = 0; round < config_.pose_rounds; ++round) {
    ceres::Problem problem(Graph::ProblemOptions());
    std::vector<std::unique_ptr<ceres::LossFunction>> losses;
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    problem.AddParameterBlock(camera.data(), 7,
                              const_cast<ceres::Manifold*>(manifold));
    ordering->AddElementToGroup(camera.data(), 1);
    int used = 0;
    for (size_t k = 0; k < factors.size(); ++k) {
      if (!inlier[k] || !informs[k] || factors[k].cost == nullptr) continue;
      losses.emplace_back(
          new ceres::HuberLoss(std::sqrt(Chi2Threshold(factors[k]))));
      problem.AddResidualBlock(factors[k].cost.get(), losses.back().get(),
                               camera.data(), values[k].data());
      ordering->AddElementToGroup(values[k].data(), 0);
      ++used;
      if (!free_point[k]) {
        problem.SetParameterBlockConstant(values[k].data());
        continue;
      }
      for (const Observation& o : points_[(*matches)[k].point].observations) {
        const Factor* f = graph_.FindFactor(o.factor);
        if (f == nullptr || f->cost == nullptr) continue;
        auto it = keyframe_values.find(o.keyframe);
        if (it == keyframe_values.end()) {
          it = keyframe_values
                   .emplace(o.keyframe,
                            graph_.FindNode(Pose3Key(o.keyframe))->value)
                   .first;
        }
        problem.AddResidualBlock(f->cost.get(), f->loss.get(),
                                 it->second.data(), values[k].data());
        if (round == 0) held_by[k].emplace_back(f, it->second.data());
        if (!ordering->IsMember(it->second.data())) {
          ordering->AddElementToGroup(it->second.data(), 1);
          problem.SetParameterBlockConstant(it->second.data());
        }
      }
    }
    if (used < 3) return 0;
    ceres::Solver::Options options = SolverOptions(
        config_.pose_iterations,
        config_.refine_with_structure ? ceres::DENSE_SCHUR : ceres::DENSE_QR);
    if (config_.refine_with_structure)
      options.linear_solver_ordering = ordering;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    // Classify every match (outliers of earlier rounds may come back).
    inliers = 0;
    for (size_t k = 0; k < factors.size(); ++k) {
      if (factors[k].cost == nullptr) {
        inlier[k] = false;
        continue;
      }
      double chi2 = 0;
      inlier[k] = chi2_of(factors[k], camera.data(), values[k].data(), &chi2) &&
                  chi2 <= Chi2Threshold(factors[k]);
      for (const auto& [f, keyframe] : held_by[k]) {
        inlier[k] = inlier[k] &&
                    chi2_of(*f, keyframe, values[k].data(), &chi2) &&
                    chi2 <= Chi2Threshold(*f);
      }
      inliers += inlier[k] && informs[k];
    }
  }
  std::vector<Match> kept;
  for (size_t k = 0; k < matches->size(); ++k) {
    if (inlier[k]) kept.push_back((*matches)[k]);
  }
  *matches = std::move(kept);
  Pose3 result;
  result.t = Eigen::Vector3d(camera[0], camera[1], camera[2]);
  result.q = Eigen::Quaterniond(camera[6], camera[3], camera[4], camera[5])
                 .normalized();
  *pose = result;
  return inliers;
}

int64_t StereoOdometry::AddKeyframe(const StereoFeatureFrame& frame,
                                    const Pose3& pose,
                                    const std::vector<Match>& matches,
                                    int* new_points) {
  const int64_t id = static_cast<int64_t>(keyframes_.size());
  Node* node = graph_.AddNode(Pose3Key(id), Pose3Value(pose));
  node->stamp = frame.stamp;
  node->has_stamp = true;
  Keyframe kf;
  kf.frame_index = frame.index;
  kf.stamp = frame.stamp;
  kf.features = frame;
  kf.point_of_keypoint.assign(frame.size(), -1);
  auto observe = [&](int keypoint, int64_t point) {
    Factor factor;
    if (!MakeObservationFactor(frame, keypoint, Pose3Key(id), Point3Key(point),
                               &factor)) {
      return false;
    }
    const FactorId fid = graph_.AddFactor(std::move(factor));
    if (fid < 0) return false;
    graph_.SetLoss(fid, std::make_shared<ceres::HuberLoss>(
                            std::sqrt(Chi2Threshold(*graph_.FindFactor(fid)))));
    points_[point].observations.push_back({id, keypoint, fid});
    MapPoint& mp = points_[point];
    if (graph_.FindFactor(fid)->type == FactorType::kStereo) {
      mp.confirmed = true;
    } else if (!mp.confirmed && static_cast<int>(mp.observations.size()) >=
                                    config_.far_point_min_keyframes) {
      // Triangulable: the rays from the first observing keyframe and this
      // one differ by at least min_parallax.
      const Eigen::Vector3d x = PointValue(point);
      const Eigen::Vector3d a =
          (x - (mp.observations[0].keyframe == id
                    ? pose.t
                    : KeyframePose(mp.observations[0].keyframe).t))
              .normalized();
      const Eigen::Vector3d b = (x - pose.t).normalized();
      mp.confirmed =
          std::acos(std::clamp(a.dot(b), -1.0, 1.0)) >= config_.min_parallax;
    }
    frame.descriptors.row(keypoint).copyTo(points_[point].descriptor);
    kf.point_of_keypoint[keypoint] = point;
    return true;
  };
  for (const Match& m : matches) {
    if (!IsLastFramePoint(m.point)) observe(m.keypoint, m.point);
  }
  // New points from the stereo keypoints without a map point.
  *new_points = 0;
  const Eigen::Matrix3d r = pose.q.toRotationMatrix();
  for (size_t i = 0; i < frame.size(); ++i) {
    if (!frame.HasStereo(i)) continue;
    if (kf.point_of_keypoint[i] >= 0) continue;
    const Eigen::Vector3d pw = r * StereoPoint(frame, i) + pose.t;
    const int64_t pid = static_cast<int64_t>(points_.size());
    points_.emplace_back();
    points_.back().anchor_keyframe = id;
    point_alive_.push_back(true);
    graph_.AddNode(Point3Key(pid), {pw.x(), pw.y(), pw.z()});
    if (!observe(static_cast<int>(i), pid)) {
      dead_points_.push_back(Point3Key(pid));
      point_alive_[pid] = false;
      continue;
    }
    kf.created_points.push_back(pid);
    ++*new_points;
  }
  stats_.points_created += *new_points;
  keyframes_.push_back(std::move(kf));
  ++stats_.keyframes;
  return id;
}

void StereoOdometry::RemoveObservation(int64_t point, size_t observation) {
  MapPoint& mp = points_[point];
  const Observation o = mp.observations[observation];
  graph_.RemoveFactor(o.factor);
  keyframes_[o.keyframe].point_of_keypoint[o.keypoint] = -1;
  mp.observations.erase(mp.observations.begin() + observation);
  ++stats_.observations_removed;
  if (mp.observations.empty()) {
    dead_points_.push_back(Point3Key(point));
    point_alive_[point] = false;
  }
}

bool StereoOdometry::CullPoint(int64_t point) {
  if (!point_alive_[point] ||
      static_cast<int>(points_[point].observations.size()) >=
          config_.min_point_observations) {
    return false;
  }
  while (point_alive_[point]) {
    RemoveObservation(point, points_[point].observations.size() - 1);
    --stats_.observations_removed;  // Culled, not outliers.
  }
  ++stats_.points_culled;
  return true;
}

void StereoOdometry::RemoveOutlierObservations(
    const std::vector<int64_t>& points) {
  for (int64_t p : points) {
    if (!point_alive_[p]) continue;
    for (size_t k = points_[p].observations.size(); k-- > 0;) {
      const Factor* f = graph_.FindFactor(points_[p].observations[k].factor);
      double chi2 = 0;
      if (!graph_.FactorChi2(*f, &chi2) || !(chi2 <= Chi2Threshold(*f))) {
        RemoveObservation(p, k);
        if (!point_alive_[p]) break;
      }
    }
  }
}

namespace {

// Copies of graph values in one buffer, in the order they were added, for
// a bundle adjustment to work on and write back. Ceres orders the blocks
// of an elimination group by their addresses, so on the graph's own arrays
// the elimination order (and the rounding of the solve) followed where the
// heap had put them, which the image prefetch thread changes from run to
// run; in one buffer, address order is the order of Add.
class ValueCopies {
 public:
  // First pass: each graph value once (repeats are ignored).
  void Add(double* graph_value, size_t size) {
    if (!offset_.emplace(graph_value, total_).second) return;
    blocks_.push_back({graph_value, total_, size});
    total_ += size;
  }
  // Then: the buffer, filled from the graph.
  void CopyIn() {
    values_.resize(total_);
    for (const Block& b : blocks_) {
      std::copy(b.graph_value, b.graph_value + b.size,
                values_.data() + b.offset);
    }
  }
  bool Has(const double* graph_value) const {
    return offset_.count(graph_value) > 0;
  }
  double* At(const double* graph_value) {
    return values_.data() + offset_.at(graph_value);
  }
  void WriteBack() const {
    for (const Block& b : blocks_) {
      std::copy(values_.begin() + b.offset, values_.begin() + b.offset + b.size,
                b.graph_value);
    }
  }

 private:
  struct Block {
    double* graph_value;
    size_t offset;
    size_t size;
  };
  std::vector<Block> blocks_;
  std::map<const double*, size_t> offset_;
  std::vector<double> values_;
  size_t total_ = 0;
};

}  // namespace

// Step 8's problem and what to do after it. The problem works on `values`
// (ValueCopies), written back at the merge, inline or on its thread alike.
struct StereoOdometry::LocalBaJob {
  int64_t newest = 0;
  std::vector<int64_t> points;  // For the outlier test after the solve.
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Options options;
  ValueCopies values;
  void Solve() {
    if (problem == nullptr) return;
    ceres::Solver::Summary summary;
    ceres::Solve(options, problem.get(), &summary);
  }
};

StereoOdometry::StereoOdometry(StereoOdometry&&) noexcept = default;

StereoOdometry::~StereoOdometry() {
  if (local_ba_done_.valid()) local_ba_done_.wait();
}

void StereoOdometry::WaitForLocalMapping() {
  if (!local_ba_done_.valid()) return;
  local_ba_done_.get();
  MergeLocalBundleAdjustment(*local_ba_job_);
  local_ba_job_.reset();
}

void StereoOdometry::MergeLocalBundleAdjustment(const LocalBaJob& job) {
  job.values.WriteBack();
  CompleteLocalBundleAdjustment(job);
}

void StereoOdometry::LocalBundleAdjustment(int64_t newest) {
  auto job = std::make_unique<LocalBaJob>();
  job->newest = newest;
  const int64_t first =
      std::max<int64_t>(0, newest + 1 - config_.window_keyframes);
  std::vector<int64_t>& points = job->points;
  for (int64_t k = first; k <= newest; ++k) {
    for (int64_t p : keyframes_[k].point_of_keypoint) {
      if (p >= 0 && point_alive_[p]) points.push_back(p);
    }
  }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  const bool thread = config_.local_mapping_thread;
  if (config_.local_ba_iterations > 0 && newest > 0) {
    // The residual blocks first, then (on the thread) the copies of their
    // values, in one array in the order the blocks enter the problem.
    std::vector<const Factor*> factors;
    std::vector<std::vector<double*>> factor_blocks;
    std::vector<bool> factor_pose;  // Both blocks poses (step 7's factor).
    std::vector<int64_t> fixed;
    auto add = [&](const Factor* f, bool all_poses) {
      factors.push_back(f);
      factor_blocks.push_back(graph_.ParameterBlocks(*f));
      factor_pose.push_back(all_poses);
    };
    for (int64_t p : points) {
      if (!points_[p].confirmed && points_[p].observations.size() < 2)
        continue;  // Nothing fixes its depth yet.
      for (const Observation& o : points_[p].observations) {
        const Factor* f = graph_.FindFactor(o.factor);
        add(f, false);
        if (o.keyframe < first) fixed.push_back(o.keyframe);
      }
    }
    // The tracking between consecutive keyframes of the window (step 7).
    for (int64_t k = std::max<int64_t>(first, 1); k <= newest; ++k) {
      if (odometry_factor_[k] < 0) continue;
      add(graph_.FindFactor(odometry_factor_[k]), true);
      if (k - 1 < first) fixed.push_back(k - 1);
    }
    // The values the problem works on: copies in one buffer (ValueCopies).
    for (size_t i = 0; i < factors.size(); ++i) {
      for (size_t b = 0; b < factor_blocks[i].size(); ++b) {
        job->values.Add(factor_blocks[i][b],
                        graph_.FindNode(factors[i]->keys[b])->value.size());
      }
    }
    job->values.CopyIn();
    auto block = [&](double* v) { return job->values.At(v); };
    job->problem = std::make_unique<ceres::Problem>(Graph::ProblemOptions());
    ceres::Problem& problem = *job->problem;
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    const ceres::Manifold* manifold = graph_.ManifoldFor(NodeKind::kPose3);
    for (size_t i = 0; i < factors.size(); ++i) {
      std::vector<double*> blocks;
      for (double* v : factor_blocks[i]) blocks.push_back(block(v));
      problem.AddResidualBlock(factors[i]->cost.get(), factors[i]->loss.get(),
                               blocks);
      for (size_t b = 0; b < blocks.size(); ++b) {
        if (ordering->IsMember(blocks[b])) continue;
        const bool pose = factor_pose[i] || b == 0;
        if (pose) {
          problem.SetManifold(blocks[b],
                              const_cast<ceres::Manifold*>(manifold));
        }
        ordering->AddElementToGroup(blocks[b], pose ? 1 : 0);
      }
    }
    std::sort(fixed.begin(), fixed.end());
    fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
    for (int64_t k : fixed) {
      problem.SetParameterBlockConstant(
          block(graph_.FindNode(Pose3Key(k))->value.data()));
    }
    // The gauge: held by the fixed keyframes, else by the oldest in the
    // window (and always by keyframe 0).
    if (fixed.empty() || first == 0) {
      double* oldest = graph_.FindNode(Pose3Key(first))->value.data();
      oldest = job->values.Has(oldest) ? job->values.At(oldest) : nullptr;
      if (oldest != nullptr && problem.HasParameterBlock(oldest))
        problem.SetParameterBlockConstant(oldest);
    }
    job->options =
        SolverOptions(config_.local_ba_iterations, ceres::DENSE_SCHUR);
    job->options.linear_solver_ordering = ordering;
    ++stats_.local_bundle_adjustments;
  }
  if (thread) {
    local_ba_job_ = std::move(job);
    LocalBaJob* j = local_ba_job_.get();
    local_ba_done_ = std::async(std::launch::async, [j] { j->Solve(); });
    return;
  }
  job->Solve();
  MergeLocalBundleAdjustment(*job);
}

void StereoOdometry::CompleteLocalBundleAdjustment(const LocalBaJob& job) {
  RemoveOutlierObservations(job.points);
  const int64_t check = job.newest - config_.cull_after_keyframes;
  if (check >= 0) {
    for (int64_t p : keyframes_[check].created_points) CullPoint(p);
  }
  RemoveDeadPoints();
}

void StereoOdometry::AddKeyframeOdometry(int64_t id) {
  odometry_factor_.resize(id + 1, -1);
  const bool valid = chain_valid_ && id > 0;
  chain_valid_ = false;
  if (!valid) return;
  // e = (t, vec q) of the between factor is (rho, phi / 2) near the
  // measurement: its information is D Cov^-1 D, D = diag(I, 2 I).
  Matrix6 d = Matrix6::Identity();
  d.bottomRightCorner<3, 3>() *= 2.0;
  const Matrix6 information =
      d * chain_covariance_.ldlt().solve(Matrix6::Identity()) * d;
  Factor factor;
  std::string error;
  if (!MakeBetweenSE3(Pose3Key(id - 1), Pose3Key(id), chain_,
                      0.5 * (information + information.transpose()), &factor,
                      &error)) {
    return;
  }
  odometry_factor_[id] = graph_.AddFactor(std::move(factor));
  keyframes_[id].has_chain = true;
  keyframes_[id].chain_from_previous = chain_;
}

void StereoOdometry::RemoveDeadPoints() {
  graph_.RemoveNodes(dead_points_);
  dead_points_.clear();
}

StereoFrameResult StereoOdometry::AddFrame(const StereoFeatureFrame& frame) {
  StereoFrameResult result;
  if (local_ba_done_.valid()) {
    // The last keyframe's local BA (on its thread while this frame's
    // features were extracted) in the map first: the waiting counts as
    // local BA time.
    const auto wait_start = std::chrono::steady_clock::now();
    WaitForLocalMapping();
    result.local_ba_ms = stereo::MillisecondsSince(wait_start);
  }
  const auto start = std::chrono::steady_clock::now();
  result.index = frame.index;
  ++stats_.frames;
  FrameRecord record;
  record.index = frame.index;
  record.stamp = frame.stamp;
  if (keyframes_.empty()) {
    // Start the map at the first frame with enough stereo points; frames
    // before it stay at the origin.
    int stereo = 0;
    for (size_t i = 0; i < frame.size(); ++i) stereo += frame.HasStereo(i);
    if (stereo >= config_.min_initial_points) {
      const Pose3 origin =
          frames_.empty() ? Pose3() : FramePose(frames_.back());
      AddKeyframe(frame, origin, {}, &result.new_points);
      record.keyframe = 0;
      result.keyframe = true;
      result.initialized = true;
      frames_since_keyframe_ = 0;
    } else {
      // No pose from the images (blank, uniform or noise images, or a
      // calibration that does not fit them): lost, not silently at rest.
      result.lost = true;
      ++stats_.lost_frames;
    }
    frames_.push_back(record);
    result.tracking_ms = stereo::MillisecondsSince(start);
    return result;
  }
  result.initialized = true;
  const Pose3 previous = FramePose(frames_.back());
  const Pose3 predicted = previous * last_motion_;
  const std::vector<int64_t> local = LocalMapPoints(frame.index);
  // The last frame's own stereo points join the map's (step 3).
  std::vector<int64_t> candidates = local;
  for (size_t i = 0; i < last_frame_points_.size(); ++i) {
    candidates.push_back(LastFramePointId(i));
  }
  std::vector<Match> matches =
      SearchByProjection(frame, predicted, candidates, config_.search_radius);
  result.matches = static_cast<int>(matches.size());
  Pose3 pose = predicted;
  int inliers = static_cast<int>(matches.size()) >= 6
                    ? OptimizePose(frame, &matches, &pose)
                    : 0;
  if (inliers >= config_.min_inliers) {
    // A second projection search from the refined pose finds the points the
    // prediction missed.
    std::vector<Match> more =
        SearchByProjection(frame, pose, candidates, config_.search_radius / 2);
    if (more.size() > matches.size()) {
      Pose3 refined = pose;
      const int n = OptimizePose(frame, &more, &refined);
      if (n >= inliers) {
        inliers = n;
        matches = std::move(more);
        pose = refined;
      }
    }
  }
  if (inliers < config_.min_inliers) {
    result.used_pnp = true;
    ++stats_.pnp_fallbacks;
    std::vector<Match> by_descriptor = SearchByDescriptor(frame, local);
    Pose3 pnp_pose;
    inliers = 0;
    if (PnpRansac(frame, by_descriptor, &pnp_pose)) {
      std::vector<Match> again = SearchByProjection(frame, pnp_pose, candidates,
                                                    config_.search_radius / 2);
      const int n = static_cast<int>(again.size()) >= 6
                        ? OptimizePose(frame, &again, &pnp_pose)
                        : 0;
      if (n >= config_.min_inliers) {
        inliers = n;
        matches = std::move(again);
        pose = pnp_pose;
      }
    }
  }
  if (inliers < config_.min_inliers) {
    result.lost = true;
    ++stats_.lost_frames;
    pose = predicted;
    matches.clear();
    inliers = 0;
  }
  result.inliers = inliers;
  last_motion_ = previous.Inverse() * pose;
  ++frames_since_keyframe_;
  // Matches to the last frame's points serve its pose only (step 3).
  const std::vector<Match> frame_matches = matches;
  matches.erase(
      std::remove_if(matches.begin(), matches.end(),
                     [](const Match& m) { return IsLastFramePoint(m.point); }),
      matches.end());
  const int map_inliers = static_cast<int>(matches.size());
  if (result.lost) {
    chain_valid_ = false;
  } else {
    const FrameRecord& before = frames_.back();
    ChainTracking(frame, frame_matches, previous, pose,
                  keyframes_[before.keyframe].frame_index == before.index);
  }

  // Step 6: keyframe decision.
  const Keyframe& last = keyframes_.back();
  const int64_t last_id = static_cast<int64_t>(keyframes_.size()) - 1;
  int last_points = 0;
  // The reference: the last keyframe's points that were tracked, i.e. that
  // at least two keyframes observe (ORB-SLAM's nRefMatches), not the ones it
  // has just created.
  for (int64_t p : last.point_of_keypoint) {
    last_points += p >= 0 && point_alive_[p] && points_[p].confirmed &&
                   points_[p].observations.size() >= 2;
  }
  std::vector<bool> tracked(frame.size(), false);
  for (const Match& m : matches) {
    tracked[m.keypoint] = true;
    result.close_tracked += IsClose(frame, m.keypoint);
  }
  int close_untracked = 0;
  for (size_t i = 0; i < frame.size(); ++i) {
    close_untracked += !tracked[i] && IsClose(frame, i);
  }
  const Pose3 from_last = KeyframePose(last_id).Inverse() * pose;
  const bool need =
      map_inliers < config_.keyframe_tracked_ratio * last_points ||
      (result.close_tracked < config_.keyframe_close_tracked &&
       close_untracked > config_.keyframe_new_close);
  const bool make_keyframe =
      result.lost || frames_since_keyframe_ >= config_.keyframe_max_frames ||
      RotationAngle(from_last) > config_.keyframe_rotation ||
      (frames_since_keyframe_ >= config_.keyframe_min_frames && need);
  result.tracking_ms = stereo::MillisecondsSince(start);
  if (make_keyframe) {
    const auto ba_start = std::chrono::steady_clock::now();
    const int64_t id = AddKeyframe(frame, pose, matches, &result.new_points);
    AddKeyframeOdometry(id);
    LocalBundleAdjustment(id);
    record.keyframe = id;
    record.keyframe_to_frame = Pose3();
    result.keyframe = true;
    frames_since_keyframe_ = 0;
    result.local_ba_ms += stereo::MillisecondsSince(ba_start);
  } else {
    record.keyframe = last_id;
    record.keyframe_to_frame = from_last;
    if (!result.lost && config_.between_acceleration_sigma > 0 &&
        !config_.interpolate_between_keyframes) {
      // The tracked position's covariance for the smoothing of step 10:
      // the pose-only refinement's information over all its matches, the
      // points held exact. They are not: each was made from a keyframe's
      // stereo measurement with the same noise model as the frame's own, so
      // the frame's pose relative to its keyframe is the difference of two
      // such measurements, twice the variance (points refined over several
      // keyframes have less; in simulation the actual error is larger
      // still, see the README).
      Matrix6 information;
      TrackingInformation(frame, frame_matches, pose, false, &information);
      const Eigen::LDLT<Matrix6> ldlt(information);
      if (ldlt.info() == Eigen::Success && ldlt.vectorD().minCoeff() > 0 &&
          ldlt.vectorD().minCoeff() > 1e-9 * ldlt.vectorD().maxCoeff()) {
        record.position_covariance =
            2.0 * ldlt.solve(Matrix6::Identity()).topLeftCorner<3, 3>();
      }
    }
  }
  UpdateLastFramePoints(frame, pose, frame_matches, result.keyframe);
  frames_.push_back(record);
  return result;
}

void StereoOdometry::Finish() {
  WaitForLocalMapping();
  for (size_t p = 0; p < points_.size(); ++p) {
    // Far points seen by too few keyframes to be triangulated first.
    if (point_alive_[p] && !points_[p].confirmed) {
      while (point_alive_[p]) {
        RemoveObservation(static_cast<int64_t>(p),
                          points_[p].observations.size() - 1);
        --stats_.observations_removed;
      }
      ++stats_.points_culled;
    }
    CullPoint(static_cast<int64_t>(p));
  }
  RemoveDeadPoints();
  if (config_.final_ba_iterations <= 0 || keyframes_.size() < 2) return;
  const auto start = std::chrono::steady_clock::now();
  ceres::Problem problem(Graph::ProblemOptions());
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  const ceres::Manifold* manifold = graph_.ManifoldFor(NodeKind::kPose3);
  // On copies in one buffer, in the order the blocks enter (ValueCopies).
  ValueCopies values;
  for (const auto& [id, factor] : graph_.factors()) {
    const std::vector<double*> blocks = graph_.ParameterBlocks(factor);
    for (size_t b = 0; b < blocks.size(); ++b) {
      values.Add(blocks[b], graph_.FindNode(factor.keys[b])->value.size());
    }
  }
  values.CopyIn();
  for (const auto& [id, factor] : graph_.factors()) {
    std::vector<double*> blocks = graph_.ParameterBlocks(factor);
    for (double*& v : blocks) v = values.At(v);
    problem.AddResidualBlock(factor.cost.get(), factor.loss.get(), blocks);
    // Points first in the elimination; poses (also both ends of a loop
    // constraint) on their manifold.
    for (size_t b = 0; b < blocks.size(); ++b) {
      if (ordering->IsMember(blocks[b])) continue;
      const bool pose = factor.keys[b].kind == NodeKind::kPose3;
      if (pose) {
        problem.SetManifold(blocks[b], const_cast<ceres::Manifold*>(manifold));
      }
      ordering->AddElementToGroup(blocks[b], pose ? 1 : 0);
    }
  }
  double* first = graph_.FindNode(Pose3Key(0))->value.data();
  if (values.Has(first)) problem.SetParameterBlockConstant(values.At(first));
  ceres::Solver::Options options =
      SolverOptions(config_.final_ba_iterations, ceres::SPARSE_SCHUR);
  options.linear_solver_ordering = ordering;
  ceres::Solver::Summary summary;
  {
    // CHOLMOD (the sparse Schur complement) on one OpenMP thread: see
    // core/openmp_scope.h.
    const SerialOpenMpScope serial_openmp;
    ceres::Solve(options, &problem, &summary);
  }
  values.WriteBack();
  stats_.global_ba_initial_chi2 = CeresCostToChi2(summary.initial_cost);
  stats_.global_ba_final_chi2 = CeresCostToChi2(summary.final_cost);
  std::vector<int64_t> all;
  for (size_t p = 0; p < points_.size(); ++p) {
    if (point_alive_[p]) all.push_back(static_cast<int64_t>(p));
  }
  RemoveOutlierObservations(all);
  RemoveDeadPoints();
  stats_.final_ba_ms = stereo::MillisecondsSince(start);
}

Trajectory StereoOdometry::FrameTrajectory() const {
  std::vector<Pose3> poses;
  poses.reserve(frames_.size());
  for (const FrameRecord& r : frames_) poses.push_back(FramePose(r));
  if (config_.between_acceleration_sigma > 0 &&
      !config_.interpolate_between_keyframes) {
    // Step 10: each run of frames between two keyframes.
    size_t first = 0;
    while (first < frames_.size()) {
      size_t last = first + 1;
      while (last < frames_.size() &&
             frames_[last].keyframe == frames_[first].keyframe) {
        ++last;
      }
      SmoothBetweenKeyframes(first, last, &poses);
      first = last;
    }
  }
  Trajectory trajectory;
  for (size_t i = 0; i < frames_.size(); ++i) {
    trajectory.push_back({frames_[i].stamp, poses[i]});
  }
  return trajectory;
}

void StereoOdometry::SmoothBetweenKeyframes(size_t first, size_t last,
                                            std::vector<Pose3>* poses) const {
  // frames_[first, last) share the reference keyframe a; the first of them
  // is a itself unless the map started later. Only the frames strictly
  // between a and the next keyframe b are smoothed.
  const int64_t a = frames_[first].keyframe;
  if (a < 0 || static_cast<size_t>(a) + 1 >= keyframes_.size()) return;
  const Keyframe& ka = keyframes_[a];
  const Keyframe& kb = keyframes_[a + 1];
  if (frames_[first].index != ka.frame_index || last >= frames_.size() ||
      frames_[last].index != kb.frame_index) {
    return;
  }
  const int m = static_cast<int>(last - first);  // b is frame m of the run.
  if (m < 2) return;
  // Times from the stamps (the acceleration is per second); a run whose
  // stamps do not increase is left as tracked.
  std::vector<double> time(m + 1);
  for (int i = 0; i <= m; ++i) {
    time[i] = 1e-9 * static_cast<double>(frames_[first + i].stamp -
                                         frames_[first].stamp);
  }
  for (int i = 1; i <= m; ++i) {
    if (!(time[i] > time[i - 1])) return;
  }
  // The deviations d_i (world frame) of the positions from the screw path
  // between the two keyframes' final poses, i = 1..m-1 (d_0 = d_m = 0).
  const Pose3 pa = KeyframePose(a);
  const Pose3 between = pa.Inverse() * KeyframePose(a + 1);
  const int n = 3 * (m - 1);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::Vector3d> path(m + 1);
  for (int i = 1; i < m; ++i) {
    path[i] = (pa * ScrewInterpolation(between, time[i] / time[m])).t;
    const FrameRecord& r = frames_[first + i];
    if (r.position_covariance.isZero()) continue;  // No measurement.
    const Eigen::Matrix3d rot = (*poses)[first + i].q.toRotationMatrix();
    const Eigen::Matrix3d covariance =
        rot * r.position_covariance * rot.transpose();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(covariance);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) {
      continue;
    }
    const Eigen::Matrix3d w = ldlt.solve(Eigen::Matrix3d::Identity());
    h.block<3, 3>(3 * (i - 1), 3 * (i - 1)) += w;
    g.segment<3>(3 * (i - 1)) += w * ((*poses)[first + i].t - path[i]);
  }
  // Acceleration at frame i: (d_{i+1} - d_i) / dt_{i+1} - (d_i - d_{i-1}) /
  // dt_i over the mean of the two steps; coefficients c_{i-1}, c_i, c_{i+1}.
  const double inv_sigma2 = 1.0 / (config_.between_acceleration_sigma *
                                   config_.between_acceleration_sigma);
  for (int i = 1; i < m; ++i) {
    const double dt0 = time[i] - time[i - 1], dt1 = time[i + 1] - time[i];
    const double mean = 0.5 * (dt0 + dt1);
    const double c[3] = {1.0 / (dt0 * mean), -(1.0 / dt0 + 1.0 / dt1) / mean,
                         1.0 / (dt1 * mean)};
    for (int u = 0; u < 3; ++u) {
      const int ju = i - 1 + u;  // Frame index of the u-th term.
      if (ju < 1 || ju > m - 1) continue;
      for (int v = 0; v < 3; ++v) {
        const int jv = i - 1 + v;
        if (jv < 1 || jv > m - 1) continue;
        h.block<3, 3>(3 * (ju - 1), 3 * (jv - 1)).diagonal().array() +=
            c[u] * c[v] * inv_sigma2;
      }
    }
  }
  const Eigen::LDLT<Eigen::MatrixXd> solver(h);
  const Eigen::VectorXd d = solver.solve(g);
  if (solver.info() != Eigen::Success || !d.allFinite()) return;
  for (int i = 1; i < m; ++i) {
    (*poses)[first + i].t = path[i] + d.segment<3>(3 * (i - 1));
  }
}

std::vector<Eigen::Vector3d> StereoOdometry::MapPoints() const {
  std::vector<Eigen::Vector3d> out;
  for (size_t p = 0; p < points_.size(); ++p) {
    if (point_alive_[p]) out.push_back(PointValue(static_cast<int64_t>(p)));
  }
  return out;
}

}  // namespace slam

namespace slam {

std::vector<StereoOdometry::PointTrack> StereoOdometry::PointTracks() const {
  std::vector<PointTrack> tracks;
  for (size_t p = 0; p < points_.size(); ++p) {
    if (!point_alive_[p]) continue;
    PointTrack t;
    t.point = static_cast<int64_t>(p);
    for (const Observation& o : points_[p].observations) {
      t.observations.push_back(
          {keyframes_[o.keyframe].frame_index, o.keypoint,
           graph_.FindFactor(o.factor)->type == FactorType::kStereo});
    }
    tracks.push_back(std::move(t));
  }
  return tracks;
}

}  // namespace slam

namespace slam {

void StereoOdometry::MoveKeyframes(const std::vector<Pose3>& poses) {
  WaitForLocalMapping();
  std::vector<Pose3> corrections(keyframes_.size());
  for (size_t k = 0; k < keyframes_.size() && k < poses.size(); ++k) {
    Node* node = graph_.FindNode(Pose3Key(static_cast<int64_t>(k)));
    corrections[k] = poses[k] * NodePose3(*node).Inverse();
    const std::vector<double> value = Pose3Value(poses[k]);
    std::copy(value.begin(), value.end(), node->value.begin());
  }
  for (size_t p = 0; p < points_.size(); ++p) {
    if (!point_alive_[p]) continue;
    Node* node = graph_.FindNode(Point3Key(static_cast<int64_t>(p)));
    const Pose3& c = corrections[points_[p].anchor_keyframe];
    const Eigen::Vector3d moved =
        c.q * Eigen::Vector3d(node->value[0], node->value[1], node->value[2]) +
        c.t;
    for (int i = 0; i < 3; ++i) node->value[i] = moved[i];
  }
}

FactorId StereoOdometry::AddKeyframeConstraint(
    int64_t candidate, int64_t query, const Pose3& measurement,
    const Eigen::Matrix<double, 6, 6>& information,
    std::shared_ptr<ceres::LossFunction> loss) {
  WaitForLocalMapping();
  Factor factor;
  std::string error;
  if (!MakeBetweenSE3(Pose3Key(candidate), Pose3Key(query), measurement,
                      information, &factor, &error)) {
    return -1;
  }
  factor.loss = std::move(loss);
  return graph_.AddFactor(std::move(factor));
}

}  // namespace slam
