#include "frontends/stereo/stereo_simulator.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace slam {
namespace {

// Camera pose at arc length s: position and heading on the path, camera z
// along the direction of travel, y down (the world is the first camera's
// frame: x right, y down, z forward).
Pose3 RawPathPose(const StereoSimulationConfig& c, double s) {
  Eigen::Vector3d position;
  double heading;  // Rotation about -y (towards +x), radians.
  if (c.loop) {
    const double a = s / c.loop_radius;
    // Circle through the origin, starting along +z, turning right (+x).
    position = Eigen::Vector3d(c.loop_radius * (1.0 - std::cos(a)), 0.0,
                               c.loop_radius * std::sin(a));
    heading = a;
  } else {
    const double w = 2.0 * M_PI / 40.0;
    position = Eigen::Vector3d(c.weave_amplitude * std::sin(w * s), 0.0, s);
    heading = std::atan(c.weave_amplitude * w * std::cos(w * s));
  }
  // Rotation about the camera's y axis (down): +heading turns z towards +x.
  const Eigen::Quaterniond q(
      Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitY()));
  return Pose3(position, q);
}

// The same with the first camera at the origin (the world frame).
Pose3 PathPose(const StereoSimulationConfig& c, double s) {
  return RawPathPose(c, 0.0).Inverse() * RawPathPose(c, s);
}

}  // namespace

StereoSimulation SimulateStereo(const StereoSimulationConfig& c) {
  std::mt19937 rng(c.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  StereoSimulation sim;
  const double length = c.loop
                            ? 2.0 * M_PI * c.loop_radius * std::min(1.0, c.laps)
                            : c.step * (c.frames - 1 +
                                        std::abs(c.speed_variation) *
                                            c.speed_period / (2.0 * M_PI));
  // Points along the path (one lap of a loop), beyond its ends too.
  const double margin = c.loop ? 0.0 : c.max_depth;
  const int count = static_cast<int>((length + margin) * c.points_per_metre);
  std::vector<cv::Mat> descriptors;
  for (int k = 0; k < count; ++k) {
    const double s = unit(rng) * (length + margin);
    const Pose3 at = PathPose(c, s);
    const double side = unit(rng) < 0.5 ? -1.0 : 1.0;
    const double lateral =
        side * (c.min_lateral + unit(rng) * (c.max_lateral - c.min_lateral));
    const double height =
        c.min_height + unit(rng) * (c.max_height - c.min_height);
    sim.points.push_back(at.t + at.q * Eigen::Vector3d(lateral, height, 0.0));
    cv::Mat d(1, 32, CV_8U);
    for (int b = 0; b < 32; ++b)
      d.at<uchar>(0, b) = static_cast<uchar>(rng() & 0xff);
    descriptors.push_back(d);
  }
  const StereoCalibration& cal = c.calibration;
  for (int f = 0; f < c.frames; ++f) {
    const double w = 2.0 * M_PI / c.speed_period;
    const double arc = c.step * (f + c.speed_variation / w * std::sin(w * f));
    const Pose3 pose = PathPose(c, arc);
    sim.poses.push_back({SecondsToNs(0.1 * f), pose});
    StereoFeatureFrame frame;
    frame.index = f;
    frame.stamp = SecondsToNs(0.1 * f);
    std::vector<int> truth;
    std::vector<bool> outlier;
    std::vector<cv::Mat> rows;
    const Eigen::Matrix3d rt = pose.q.conjugate().toRotationMatrix();
    auto add = [&](double u, double v, double ur, const cv::Mat& d, int point,
                   bool is_outlier) {
      frame.keypoints.emplace_back(static_cast<float>(u), static_cast<float>(v),
                                   31.0f);
      frame.keypoints.back().octave = 0;
      frame.u_right.push_back(ur);
      rows.push_back(d);
      truth.push_back(point);
      outlier.push_back(is_outlier);
    };
    for (size_t p = 0; p < sim.points.size(); ++p) {
      const Eigen::Vector3d pc = rt * (sim.points[p] - pose.t);
      if (pc.z() < c.min_depth || pc.z() > c.max_depth) continue;
      double u = cal.fx * pc.x() / pc.z() + cal.cx;
      double v = cal.fy * pc.y() / pc.z() + cal.cy;
      double ur = cal.fx * (pc.x() - cal.baseline) / pc.z() + cal.cx;
      if (u < 0 || v < 0 || u > c.width - 1 || v > c.height - 1) continue;
      const double true_disparity = u - ur;
      u += c.pixel_sigma * noise(rng);
      v += c.pixel_sigma * noise(rng);
      if (c.disparity_sigma >= 0) {
        ur = u - (true_disparity + c.disparity_sigma * noise(rng));
      } else {
        ur += c.pixel_sigma * noise(rng);
      }
      double disparity = u - ur + c.disparity_bias;
      if (c.disparity_quantum > 0) {
        disparity =
            c.disparity_quantum * std::round(disparity / c.disparity_quantum);
      }
      ur = u - disparity;
      bool is_outlier = false;
      cv::Mat d = descriptors[p].clone();
      for (int b = 0; b < c.descriptor_flips; ++b) {
        const int bit = static_cast<int>(rng() % 256);
        d.at<uchar>(0, bit / 8) ^= static_cast<uchar>(1u << (bit % 8));
      }
      if (unit(rng) < c.stereo_outlier_fraction && u - ur >= 1.0) {
        // Off either way, as long as it stays a stereo match.
        const double shift =
            (unit(rng) < 0.5 ? -1.0 : 1.0) * c.stereo_outlier_pixels;
        ur += u - (ur + shift) >= 1.0 ? shift : -std::abs(shift);
        is_outlier = true;
      }
      // As a real right camera: a match needs the point inside its image.
      add(u, v,
          u - ur >= 1.0 && ur >= 0.0 ? ur
                                     : StereoFeatureFrame::kNoRightCoordinate,
          d, static_cast<int>(p), is_outlier);
      // A spurious keypoint with this point's appearance somewhere else.
      if (unit(rng) < c.outlier_fraction) {
        const double su = unit(rng) * (c.width - 1);
        const double sd = 1.0 + unit(rng) * 40.0;
        add(su, unit(rng) * (c.height - 1),
            su - sd >= 0 ? su - sd : StereoFeatureFrame::kNoRightCoordinate, d,
            -1, true);
      }
    }
    if (!rows.empty()) cv::vconcat(rows, frame.descriptors);
    sim.frames.push_back(std::move(frame));
    sim.true_point.push_back(std::move(truth));
    sim.outlier.push_back(std::move(outlier));
  }
  return sim;
}

}  // namespace slam
