// Geometric verification (PnP-RANSAC with its covariance, fundamental
// matrix RANSAC) and the loop detector, on synthetic data with a known
// answer.
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <Eigen/Dense>

#include "core/lie.h"
#include "factors/between_se3.h"
#include "frontends/bow/geometric_verification.h"
#include "frontends/bow/loop_detector.h"
#include "frontends/bow/vocabulary.h"
#include "gtest/gtest.h"

namespace slam::bow {
namespace {

const PinholeCamera kCamera{500.0, 500.0, 320.0, 240.0};

Eigen::Vector2d Project(const Eigen::Vector3d& p) {
  return Eigen::Vector2d(kCamera.fx * p.x() / p.z() + kCamera.cx,
                         kCamera.fy * p.y() / p.z() + kCamera.cy);
}

// T [+] delta (core/conventions.h: right perturbation, translation first).
Pose3 Plus(const Pose3& t, const Eigen::Matrix<double, 6, 1>& delta) {
  return Pose3(t.t + t.q * delta.head<3>(),
               t.q * QuaternionExp<double>(delta.tail<3>()));
}

// The tangent e with truth [+] e = estimate.
Eigen::Matrix<double, 6, 1> Minus(const Pose3& estimate, const Pose3& truth) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = truth.q.conjugate() * (estimate.t - truth.t);
  e.tail<3>() = QuaternionLog<double>(truth.q.conjugate() * estimate.q);
  return e;
}

const Pose3 kTruth(Eigen::Vector3d(0.3, -0.1, 0.5),
                   QuaternionExp<double>(Eigen::Vector3d(0.05, -0.1, 0.2)));

// Points in the candidate frame that the query camera (kTruth) sees.
std::vector<Eigen::Vector3d> VisiblePoints(int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> x(-4, 4), y(-3, 3), z(4, 15);
  std::vector<Eigen::Vector3d> points;
  while (static_cast<int>(points.size()) < n) {
    const Eigen::Vector3d p(x(*rng), y(*rng), z(*rng));
    const Eigen::Vector3d q = kTruth.Inverse() * p;
    if (q.z() < 1.0) continue;
    const Eigen::Vector2d px = Project(q);
    if (px.x() < 0 || px.x() > 640 || px.y() < 0 || px.y() > 480) continue;
    points.push_back(p);
  }
  return points;
}

TEST(GeometricVerificationTest, ReprojectionJacobianMatchesNumericDerivative) {
  std::mt19937 rng(1);
  for (const Eigen::Vector3d& p : VisiblePoints(20, &rng)) {
    const Eigen::Matrix<double, 2, 6> analytic =
        ReprojectionJacobian(kTruth, p, kCamera);
    Eigen::Matrix<double, 2, 6> numeric;
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      d[k] = h;
      numeric.col(k) = (Project(Plus(kTruth, d).Inverse() * p) -
                        Project(Plus(kTruth, -d).Inverse() * p)) /
                       (2 * h);
    }
    EXPECT_LT((analytic - numeric).norm(), 1e-5 * (1.0 + numeric.norm()))
        << analytic << "\n"
        << numeric;
  }
}

TEST(GeometricVerificationTest, PnpRecoversThePoseAndRejectsOutliers) {
  std::mt19937 rng(2);
  std::normal_distribution<double> noise(0.0, 0.7);
  std::uniform_real_distribution<double> u(0.0, 640.0), v(0.0, 480.0);
  std::vector<Eigen::Vector3d> points = VisiblePoints(120, &rng);
  std::vector<Eigen::Vector2d> pixels;
  for (const Eigen::Vector3d& p : points)
    pixels.push_back(Project(kTruth.Inverse() * p) +
                     Eigen::Vector2d(noise(rng), noise(rng)));
  // 40 % outliers: random pixels for extra points.
  for (const Eigen::Vector3d& p : VisiblePoints(80, &rng)) {
    points.push_back(p);
    pixels.emplace_back(u(rng), v(rng));
  }
  const StereoVerification v_result =
      VerifyStereoPnp(points, pixels, kCamera, StereoVerificationOptions());
  ASSERT_TRUE(v_result.success);
  EXPECT_EQ(v_result.matches, 200);
  EXPECT_GE(v_result.inliers, 114);  // 120 true, 3 px threshold.
  EXPECT_LE(v_result.inliers, 125);  // A few outliers may fall near.
  const Eigen::Matrix<double, 6, 1> e =
      Minus(v_result.T_candidate_query, kTruth);
  EXPECT_LT(e.head<3>().norm(), 0.05);
  EXPECT_LT(e.tail<3>().norm(), 0.005);
  // The error is plausible under the reported covariance.
  EXPECT_LT(e.dot(v_result.covariance.inverse() * e), 30.0);

  // Random correspondences only: rejected.
  std::vector<Eigen::Vector2d> random_pixels;
  for (size_t i = 0; i < points.size(); ++i)
    random_pixels.emplace_back(u(rng), v(rng));
  EXPECT_FALSE(VerifyStereoPnp(points, random_pixels, kCamera,
                               StereoVerificationOptions())
                   .success);
}

TEST(GeometricVerificationTest, PnpCovarianceMatchesTheScatter) {
  // Monte Carlo: the normalised squared error e^T C^-1 e averages 6 when the
  // covariance is right (1 px noise, above the 0.5 px floor).
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  const std::vector<Eigen::Vector3d> points = VisiblePoints(80, &rng);
  double nees = 0.0;
  constexpr int kTrials = 200;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::vector<Eigen::Vector2d> pixels;
    for (const Eigen::Vector3d& p : points)
      pixels.push_back(Project(kTruth.Inverse() * p) +
                       Eigen::Vector2d(noise(rng), noise(rng)));
    StereoVerificationOptions options;
    options.reprojection_error_px = 5.0;  // No true point rejected.
    const StereoVerification r =
        VerifyStereoPnp(points, pixels, kCamera, options);
    ASSERT_TRUE(r.success);
    const Eigen::Matrix<double, 6, 1> e = Minus(r.T_candidate_query, kTruth);
    nees += e.dot(r.covariance.inverse() * e);
  }
  nees /= kTrials;
  EXPECT_GT(nees, 6.0 * 0.8);
  EXPECT_LT(nees, 6.0 * 1.25);
}

TEST(GeometricVerificationTest, BetweenInformationMatchesTheFactorsError) {
  // The between factor's error for X_i^-1 X_j = Z [+] delta is J delta to
  // first order; the information must then be (J C J^T)^-1.
  std::mt19937 rng(8);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 6, 6> a;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) a(r, c) = n(rng);
  const Eigen::Matrix<double, 6, 6> covariance =
      a * a.transpose() + Eigen::Matrix<double, 6, 6>::Identity();
  const Eigen::Matrix<double, 6, 6> information =
      BetweenSE3Information(covariance);
  BetweenSE3Factor factor(kTruth.t, kTruth.q,
                          Eigen::Matrix<double, 6, 6>::Identity());
  const double xi[7] = {0, 0, 0, 0, 0, 0, 1};
  for (int trial = 0; trial < 10; ++trial) {
    Eigen::Matrix<double, 6, 1> delta;
    for (int k = 0; k < 6; ++k) delta[k] = 1e-4 * n(rng);
    const Pose3 xj = Plus(kTruth, delta);
    const double xj_values[7] = {xj.t.x(), xj.t.y(), xj.t.z(), xj.q.x(),
                                 xj.q.y(), xj.q.z(), xj.q.w()};
    Eigen::Matrix<double, 6, 1> e;
    ASSERT_TRUE(factor(xi, xj_values, e.data()));
    // e^T Omega e = delta^T C^-1 delta (the same error in both units).
    const double chi2_factor = e.dot(information * e);
    const double chi2_tangent = delta.dot(covariance.inverse() * delta);
    EXPECT_NEAR(chi2_factor, chi2_tangent, 1e-4 * chi2_tangent);
  }
}

TEST(GeometricVerificationTest, FundamentalMatrixFindsTheEpipolarInliers) {
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::uniform_real_distribution<double> u(0.0, 640.0), v(0.0, 480.0);
  std::vector<cv::Point2f> query, candidate;
  const std::vector<Eigen::Vector3d> points = VisiblePoints(100, &rng);
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector2d c = Project(p);
    const Eigen::Vector2d q = Project(kTruth.Inverse() * p);
    candidate.emplace_back(c.x() + noise(rng), c.y() + noise(rng));
    query.emplace_back(q.x() + noise(rng), q.y() + noise(rng));
  }
  for (int i = 0; i < 50; ++i) {
    candidate.emplace_back(u(rng), v(rng));
    query.emplace_back(u(rng), v(rng));
  }
  const FundamentalVerification r =
      VerifyFundamental(query, candidate, FundamentalVerificationOptions());
  ASSERT_TRUE(r.success);
  EXPECT_GE(r.inliers, 95);
  EXPECT_LE(r.inliers, 110);
  // The true correspondences lie on their epipolar lines (within the RANSAC
  // threshold, 2 px; the model is fitted to noisy points).
  cv::Matx33d f(r.fundamental);
  int on_line = 0;
  for (int i = 0; i < 100; ++i) {
    const cv::Vec3d xc(candidate[i].x, candidate[i].y, 1.0);
    const cv::Vec3d xq(query[i].x, query[i].y, 1.0);
    const cv::Vec3d line = f * xc;
    const double distance =
        std::abs(xq.dot(line)) / std::hypot(line[0], line[1]);
    if (distance < 2.0) ++on_line;
  }
  EXPECT_GE(on_line, 95);
  // Random pairs only: rejected.
  std::vector<cv::Point2f> random_query, random_candidate;
  for (int i = 0; i < 150; ++i) {
    random_query.emplace_back(u(rng), v(rng));
    random_candidate.emplace_back(u(rng), v(rng));
  }
  EXPECT_FALSE(VerifyFundamental(random_query, random_candidate,
                                 FundamentalVerificationOptions())
                   .success);
}

TEST(GeometricVerificationTest, MatchingPairsNoisyCopies) {
  std::mt19937 rng(5);
  cv::Mat a(100, kDescriptorBytes, CV_8U), b(100, kDescriptorBytes, CV_8U);
  cv::randu(a, 0, 256);
  // b row i = a row perm[i] with 5 bits flipped.
  std::vector<int> perm(100);
  for (int i = 0; i < 100; ++i) perm[i] = i;
  std::shuffle(perm.begin(), perm.end(), rng);
  for (int i = 0; i < 100; ++i) {
    a.row(perm[i]).copyTo(b.row(i));
    for (int k = 0; k < 5; ++k)
      b.at<uint8_t>(i, rng() % 32) ^= 1 << (rng() % 8);
  }
  const std::vector<cv::DMatch> matches =
      MatchDescriptors(a, b, nullptr, nullptr, MatchingOptions());
  ASSERT_EQ(matches.size(), 100u);
  for (const cv::DMatch& m : matches) EXPECT_EQ(m.queryIdx, perm[m.trainIdx]);
}

// A synthetic stereo world: 30 places along x, each with 200 landmarks
// (descriptor + world point) in front of it. Keyframes 0-29 visit the places,
// keyframes 30-59 revisit them with a small pose offset; every keyframe sees
// 85 % of its place's landmarks and 30 % of the neighbouring places' ones.
struct World {
  std::vector<Descriptor> descriptors;
  std::vector<Eigen::Vector3d> points;
  std::vector<int> place_of;
  std::vector<Pose3> keyframe_poses;  // World <- camera.
  std::vector<LoopKeyframe> keyframes;
};

World MakeWorld(std::mt19937* rng) {
  World w;
  constexpr int kPlaces = 30;
  std::uniform_real_distribution<double> x(-4, 4), y(-3, 3), z(5, 15);
  for (int p = 0; p < kPlaces; ++p) {
    for (int l = 0; l < 200; ++l) {
      Descriptor d;
      for (auto& byte : d) byte = static_cast<uint8_t>((*rng)() & 0xff);
      w.descriptors.push_back(d);
      w.points.emplace_back(p * 5.0 + x(*rng), y(*rng), z(*rng));
      w.place_of.push_back(p);
    }
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> pixel_noise(0.0, 0.5);
  for (int k = 0; k < 2 * kPlaces; ++k) {
    const int place = k % kPlaces;
    Pose3 pose(Eigen::Vector3d(place * 5.0, 0, 0),
               Eigen::Quaterniond::Identity());
    if (k >= kPlaces) {
      pose =
          pose * Pose3(Eigen::Vector3d(0.3, 0.1, -0.2),
                       QuaternionExp<double>(Eigen::Vector3d(0, 0.05, 0.02)));
    }
    w.keyframe_poses.push_back(pose);
    LoopKeyframe kf;
    kf.id = 1000 + k;
    kf.stamp = k * 100000000LL;
    std::vector<Descriptor> rows;
    for (size_t l = 0; l < w.points.size(); ++l) {
      const int dp = std::abs(w.place_of[l] - place);
      const double p_see = dp == 0 ? 0.85 : dp == 1 ? 0.3 : 0.0;
      if (unit(*rng) >= p_see) continue;
      const Eigen::Vector3d pc = pose.Inverse() * w.points[l];
      if (pc.z() < 1.0) continue;
      Descriptor d = w.descriptors[l];
      for (int f = 0; f < 4; ++f) d[(*rng)() % 32] ^= 1 << ((*rng)() % 8);
      rows.push_back(d);
      const Eigen::Vector2d px = Project(pc);
      kf.keypoints.emplace_back(static_cast<float>(px.x() + pixel_noise(*rng)),
                                static_cast<float>(px.y() + pixel_noise(*rng)),
                                31.0f);
      kf.points.push_back(pc);
    }
    kf.descriptors =
        cv::Mat(static_cast<int>(rows.size()), kDescriptorBytes, CV_8U);
    for (size_t r = 0; r < rows.size(); ++r)
      std::memcpy(kf.descriptors.ptr<uint8_t>(static_cast<int>(r)),
                  rows[r].data(), kDescriptorBytes);
    w.keyframes.push_back(kf);
  }
  return w;
}

TEST(LoopDetectorTest, FindsTheRevisitsOfASyntheticStereoWorldWithTheirPoses) {
  std::mt19937 rng(6);
  const World world = MakeWorld(&rng);
  // Vocabulary trained on the first traversal.
  std::vector<cv::Mat> training;
  for (int k = 0; k < 30; ++k)
    training.push_back(world.keyframes[k].descriptors);
  Vocabulary voc;
  std::string error;
  VocabularyTrainingOptions options;
  options.k = 10;
  options.levels = 3;
  ASSERT_TRUE(voc.Train(training, options, &error)) << error;

  LoopDetectorConfig config;
  config.verification = Verification::kStereoPnp;
  config.camera = kCamera;
  LoopDetector detector(&voc, config);
  int accepted = 0;
  for (int k = 0; k < 60; ++k) {
    const LoopResult r = detector.Process(world.keyframes[k]);
    EXPECT_EQ(r.query_id, 1000 + k);
    if (k < 30) {
      EXPECT_NE(r.status, LoopStatus::kAccepted) << "keyframe " << k;
      continue;
    }
    if (r.status != LoopStatus::kAccepted) continue;
    ++accepted;
    // The candidate shows the same place or a neighbouring one.
    const int candidate = static_cast<int>(r.candidate_id - 1000);
    ASSERT_GE(candidate, 0);
    ASSERT_LT(candidate, 30);
    EXPECT_LE(std::abs(candidate - (k - 30)), 1) << "keyframe " << k;
    ASSERT_TRUE(r.has_pose);
    const Pose3 truth =
        world.keyframe_poses[candidate].Inverse() * world.keyframe_poses[k];
    const Eigen::Matrix<double, 6, 1> e = Minus(r.T_candidate_query, truth);
    EXPECT_LT(e.head<3>().norm(), 0.1) << "keyframe " << k;
    EXPECT_LT(e.tail<3>().norm(), 0.01) << "keyframe " << k;
    EXPECT_GE(r.inliers, config.stereo.min_inliers);
    EXPECT_TRUE(r.covariance.allFinite());
    EXPECT_GT(r.covariance.determinant(), 0.0);
  }
  // All but the first two revisits (temporal consistency needs three).
  EXPECT_GE(accepted, 26);
  EXPECT_EQ(detector.size(), 60u);
}

TEST(LoopDetectorTest, TemporalConsistencyAndExclusionHoldBackEarlyMatches) {
  std::mt19937 rng(7);
  const World world = MakeWorld(&rng);
  std::vector<cv::Mat> training;
  for (int k = 0; k < 30; ++k)
    training.push_back(world.keyframes[k].descriptors);
  Vocabulary voc;
  std::string error;
  ASSERT_TRUE(voc.Train(training, VocabularyTrainingOptions(), &error))
      << error;
  LoopDetectorConfig config;
  config.verification = Verification::kNone;
  config.min_consistent_queries = 4;
  LoopDetector detector(&voc, config);
  // Every query before MinKeyframesForALoop - 1 is too early (VisualSlam
  // skips the vocabulary and the detection below that many keyframes), and
  // the one at it is not.
  ASSERT_EQ(MinKeyframesForALoop(config), 22);
  for (int k = 0; k < 60; ++k) {
    const LoopResult r = detector.Process(world.keyframes[k]);
    if (k < MinKeyframesForALoop(config) - 1) {
      EXPECT_EQ(r.status, LoopStatus::kTooEarly) << k;
    } else {
      EXPECT_NE(r.status, LoopStatus::kTooEarly) << k;
    }
    if (k >= 30 && k < 33) {
      EXPECT_EQ(r.status, LoopStatus::kNotConsistent) << k;
      EXPECT_EQ(r.consistent_queries, k - 29);
    }
    if (k >= 33) {
      EXPECT_EQ(r.status, LoopStatus::kAccepted) << k;
    }
  }
}

}  // namespace
}  // namespace slam::bow

namespace slam::bow {
namespace {

TEST(LoopDetectorTest, OneBlankKeyframeDoesNotBlindTheNextQuery) {
  std::mt19937 rng(9);
  World world = MakeWorld(&rng);
  // Keyframe 40 (a revisit) sees nothing: no features at all.
  world.keyframes[40].descriptors = cv::Mat();
  world.keyframes[40].keypoints.clear();
  world.keyframes[40].points.clear();
  std::vector<cv::Mat> training;
  for (int k = 0; k < 30; ++k)
    training.push_back(world.keyframes[k].descriptors);
  Vocabulary voc;
  std::string error;
  ASSERT_TRUE(voc.Train(training, VocabularyTrainingOptions(), &error))
      << error;
  for (int prior_keyframes : {1, 2}) {
    LoopDetectorConfig config;
    config.verification = Verification::kNone;
    config.prior_keyframes = prior_keyframes;
    LoopDetector detector(&voc, config);
    for (int k = 0; k < 42; ++k) {
      const LoopResult r = detector.Process(world.keyframes[k]);
      if (k == 40) {
        EXPECT_EQ(r.status, LoopStatus::kLowPriorScore);
      }
      if (k == 41) {
        // With the previous keyframe only, the blank one is the reference.
        EXPECT_EQ(r.status, prior_keyframes == 1 ? LoopStatus::kLowPriorScore
                                                 : LoopStatus::kAccepted);
      }
    }
  }
}

}  // namespace
}  // namespace slam::bow
