#include "frontends/stereo/stereo_loop_closing.h"

#include <cmath>
#include <limits>
#include <map>

#include "core/graph.h"
#include "core/optimizer.h"
#include "factors/pose_factors.h"

namespace slam {

Eigen::Matrix<double, 6, 6> LoopDriftInformation(
    const StereoLoopClosingConfig& c, const Pose3& relative) {
  const double distance = relative.t.norm();
  const double angle = Eigen::AngleAxisd(relative.q).angle();
  const double st = c.drift_translation * distance +
                    c.drift_translation_per_rad * angle +
                    c.min_sigma_translation;
  const double sr = c.drift_rotation * distance +
                    c.drift_rotation_per_rad * angle + c.min_sigma_rotation;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  covariance.diagonal() << st * st, st * st, st * st, sr * sr, sr * sr, sr * sr;
  return bow::BetweenSE3Information(covariance);
}

namespace {

struct VerifiedLoop {
  size_t index;  // Into result->loops.
  int64_t candidate, query;
  Pose3 measurement;
  Eigen::Matrix<double, 6, 6> information;
};

}  // namespace

bool ValidateStereoLoopClosingConfig(const StereoLoopClosingConfig& c,
                                     std::string* error) {
  if (!(c.drift_translation >= 0) || !(c.min_sigma_translation > 0) ||
      !(c.drift_rotation >= 0) || !(c.min_sigma_rotation > 0) ||
      !(c.drift_translation_per_rad >= 0) || !(c.drift_rotation_per_rad >= 0) ||
      !(c.reject_chi2 > 0) || c.max_iterations < 1) {
    *error =
        "loop_closure: drifts >= 0, minimum sigmas and reject_chi2 > 0, "
        "max_iterations >= 1";
    return false;
  }
  return true;
}

bow::LoopKeyframe LoopKeyframeOf(const StereoFeatureFrame& frame,
                                 const StereoCalibration& c, int64_t id) {
  bow::LoopKeyframe kf;
  kf.id = id;
  kf.stamp = frame.stamp;
  kf.descriptors = frame.descriptors;
  kf.keypoints = frame.keypoints;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 0; i < frame.size(); ++i) {
    if (!frame.HasStereo(i)) {
      kf.points.emplace_back(nan, nan, nan);
      continue;
    }
    const cv::Point2f& pt = frame.keypoints[i].pt;
    const double z = c.fx * c.baseline / (pt.x - frame.u_right[i]);
    kf.points.emplace_back((pt.x - c.cx) * z / c.fx, (pt.y - c.cy) * z / c.fy,
                           z);
  }
  return kf;
}

bool CloseStereoLoops(const bow::Vocabulary& vocabulary,
                      const bow::LoopDetectorConfig& detector_config,
                      const StereoLoopClosingConfig& config,
                      const StereoCalibration& calibration,
                      StereoOdometry* odometry, StereoLoopClosingResult* result,
                      std::ostream* log, std::string* error) {
  *result = StereoLoopClosingResult();
  const int64_t n = static_cast<int64_t>(odometry->NumKeyframes());
  if (!config.enabled || n < 2) return true;
  bow::LoopDetectorConfig dc = detector_config;
  dc.verification = bow::Verification::kStereoPnp;
  dc.camera = {calibration.fx, calibration.fy, calibration.cx, calibration.cy};
  bow::LoopDetector detector(&vocabulary, dc);
  std::vector<int64_t> frame_of(n);
  std::vector<VerifiedLoop> verified;
  for (int64_t k = 0; k < n; ++k) {
    const StereoFeatureFrame& features = odometry->KeyframeFeatures(k);
    frame_of[k] = features.index;
    const bow::LoopResult r =
        detector.Process(LoopKeyframeOf(features, calibration, k));
    if (r.status != bow::LoopStatus::kAccepted &&
        r.status != bow::LoopStatus::kVerificationFailed) {
      continue;
    }
    ++result->detected;
    StereoLoop loop;
    loop.query_keyframe = k;
    loop.candidate_keyframe = r.candidate_id;
    loop.query_frame = features.index;
    loop.candidate_frame = frame_of[r.candidate_id];
    loop.score = r.normalized_score;
    loop.inliers = r.inliers;
    loop.relative = r.T_candidate_query;
    if (r.status == bow::LoopStatus::kAccepted && r.has_pose) {
      loop.accepted = true;
      verified.push_back({result->loops.size(), r.candidate_id, k,
                          r.T_candidate_query,
                          bow::BetweenSE3Information(r.covariance)});
    } else {
      loop.reason = "geometric verification: " + std::to_string(r.inliers) +
                    " inliers, " + std::to_string(r.matches) + " matches";
    }
    result->loops.push_back(loop);
  }

  // Step 2: the pose graph.
  Graph graph;
  std::vector<Pose3> before(n);
  for (int64_t k = 0; k < n; ++k) {
    before[k] = odometry->KeyframePose(k);
    graph.AddNode(Pose3Key(k), Pose3Value(before[k]));
  }
  for (int64_t k = 0; k + 1 < n; ++k) {
    const Pose3 z = before[k].Inverse() * before[k + 1];
    Factor f;
    if (!MakeBetweenSE3(Pose3Key(k), Pose3Key(k + 1), z,
                        LoopDriftInformation(config, z), &f, error) ||
        graph.AddFactor(std::move(f)) < 0) {
      return false;
    }
  }
  std::map<FactorId, size_t> loop_factor;  // -> index into verified.
  for (size_t v = 0; v < verified.size(); ++v) {
    Factor f;
    std::string problem;
    if (!MakeBetweenSE3(Pose3Key(verified[v].candidate),
                        Pose3Key(verified[v].query), verified[v].measurement,
                        verified[v].information, &f, &problem)) {
      StereoLoop& loop = result->loops[verified[v].index];
      loop.accepted = false;
      loop.reason = "bad verification covariance: " + problem;
      continue;
    }
    f.loss = MakeLoss(config.kernel);
    loop_factor[graph.AddFactor(std::move(f))] = v;
  }
  if (!loop_factor.empty()) {
    OptimizerOptions options;
    options.max_iterations = config.max_iterations;
    options.verbose = false;
    while (true) {
      Optimize(&graph, options, nullptr);
      // The worst loop beyond the threshold goes, then optimize again.
      FactorId worst = -1;
      double worst_chi2 = config.reject_chi2;
      for (const auto& [id, v] : loop_factor) {
        double chi2 = 0.0;
        if (graph.FactorChi2(*graph.FindFactor(id), &chi2) &&
            chi2 > worst_chi2) {
          worst = id;
          worst_chi2 = chi2;
        }
      }
      if (worst < 0) break;
      StereoLoop& loop = result->loops[verified[loop_factor[worst]].index];
      loop.accepted = false;
      char text[96];
      std::snprintf(text, sizeof(text),
                    "rejected by the pose graph: chi2 %.1f > %.2f", worst_chi2,
                    config.reject_chi2);
      loop.reason = text;
      graph.RemoveFactor(worst);
      loop_factor.erase(worst);
      if (loop_factor.empty()) {
        // Back to the odometry alone.
        for (int64_t k = 0; k < n; ++k) {
          const std::vector<double> value = Pose3Value(before[k]);
          std::copy(value.begin(), value.end(),
                    graph.FindNode(Pose3Key(k))->value.begin());
        }
        break;
      }
    }
  }

  // Step 3: move the map, keep the accepted loops.
  std::vector<Pose3> after(n);
  for (int64_t k = 0; k < n; ++k) {
    after[k] = NodePose3(*graph.FindNode(Pose3Key(k)));
    result->largest_correction =
        std::max(result->largest_correction, (after[k].t - before[k].t).norm());
  }
  if (!loop_factor.empty()) odometry->MoveKeyframes(after);
  for (const auto& [id, v] : loop_factor) {
    odometry->AddKeyframeConstraint(
        verified[v].candidate, verified[v].query, verified[v].measurement,
        verified[v].information, MakeLoss(config.kernel));
  }
  for (const StereoLoop& loop : result->loops) {
    (loop.accepted ? result->accepted : result->rejected) += 1;
    if (log != nullptr) {
      char text[256];
      std::snprintf(
          text, sizeof(text),
          "loop: frame %lld -> frame %lld (keyframes %lld -> %lld), "
          "score %.3f, %d inliers: %s",
          static_cast<long long>(loop.query_frame),
          static_cast<long long>(loop.candidate_frame),
          static_cast<long long>(loop.query_keyframe),
          static_cast<long long>(loop.candidate_keyframe), loop.score,
          loop.inliers,
          loop.accepted ? "accepted" : ("rejected, " + loop.reason).c_str());
      *log << text << "\n";
    }
  }
  return true;
}

}  // namespace slam
