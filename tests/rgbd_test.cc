// RGB-D visual SLAM (issue 23): the TUM RGB-D folder reader (association as
// TUM's associate.py, its edge cases and errors), the RGB-D measurement
// (undistortion, virtual right coordinate), the visual SLAM pipeline on a
// synthetic RGB-D world with depth noise growing with the square of the
// depth, `slam run` with run.pipeline: rgbd on handmade folders (bad input:
// message, exit 1, no output) and on the shared fr1/rpy excerpt (bounds).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/visual/rgbd_run_config.h"
#include "core/graph.h"
#include "core/keys.h"
#include "core/optimizer.h"
#include "datasets/tum_rgbd_io.h"
#include "factors/pose_factors.h"
#include "frontends/bow/loop_detector.h"
#include "frontends/rgbd/rgbd_camera.h"
#include "frontends/rgbd/rgbd_features.h"
#include "frontends/stereo/stereo_loop_closing.h"
#include "frontends/stereo/stereo_simulator.h"
#include "frontends/visual/capture_clock.h"
#include "frontends/visual/visual_slam.h"
#include "gtest/gtest.h"
#include "test_util.h"

namespace slam {
namespace {

using testing::Contains;
using testing::DatasetPath;
using testing::Exists;
using testing::ReadText;
using testing::RunSlam;
using testing::TempDir;
using testing::WriteText;
namespace fs = std::filesystem;

TEST(TumRgbdAssociationTest, NearestFirstEachStampOnce) {
  // 0.010 is nearer to 0.006 than 0.0 is: it takes the depth image, and
  // 0.0 stays unmatched although it is within the limit too.
  auto m = AssociateStamps({0.0, 0.010, 0.033}, {0.006, 0.034}, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], std::make_pair(size_t{1}, size_t{0}));
  EXPECT_EQ(m[1], std::make_pair(size_t{2}, size_t{1}));
  // Nothing within the limit (strictly closer than it, as associate.py).
  EXPECT_TRUE(AssociateStamps({0.0, 1.0}, {0.02, 0.5}, 0.02).empty());
  // Duplicate depth stamps: one is taken, the other left.
  m = AssociateStamps({5.0}, {5.001, 5.001}, 0.02);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].first, 0u);
}

// A TUM folder: colour images (textured) and 16-bit depth images at the
// stamps given; list lines written as given.
void WriteTumFolder(const std::string& dir, const std::vector<double>& rgb,
                    const std::vector<double>& depth, int width = 64,
                    int height = 48) {
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  std::string rgb_txt = "# color images\n# timestamp filename\n";
  std::string depth_txt = "# depth maps\n# timestamp filename\n";
  cv::Mat colour(height, width, CV_8UC3);
  cv::randu(colour, 0, 255);
  const cv::Mat d(height, width, CV_16U, cv::Scalar(5000));
  char stamp[32];
  for (double s : rgb) {
    std::snprintf(stamp, sizeof(stamp), "%.6f", s);
    const std::string name = "rgb/" + std::string(stamp) + ".png";
    cv::imwrite(dir + "/" + name, colour);
    rgb_txt += std::string(stamp) + " " + name + "\n";
  }
  for (double s : depth) {
    std::snprintf(stamp, sizeof(stamp), "%.6f", s);
    const std::string name = "depth/" + std::string(stamp) + ".png";
    cv::imwrite(dir + "/" + name, d);
    depth_txt += std::string(stamp) + " " + name + "\n";
  }
  WriteText(dir + "/rgb.txt", rgb_txt);
  WriteText(dir + "/depth.txt", depth_txt);
}

TEST(TumRgbdReaderTest, ReportsUnmatchedFramesAndChecksTheLists) {
  const std::string dir = TempDir() + "/rgbd_dataset_freiburg2_test";
  // A depth image is missing for the third colour image; the last depth
  // image has no colour image.
  WriteTumFolder(dir, {10.0, 10.033, 10.066, 10.1},
                 {10.001, 10.034, 10.101, 10.2});
  TumRgbdSequence seq;
  std::string error;
  ASSERT_TRUE(ReadTumRgbdSequence(dir, {}, &seq, &error)) << error;
  ASSERT_EQ(seq.frames.size(), 3u);
  EXPECT_EQ(seq.frames[2].rgb.stamp, SecondsToNs(10.1));
  EXPECT_EQ(seq.frames[2].depth.stamp, SecondsToNs(10.101));
  ASSERT_EQ(seq.unmatched_rgb.size(), 1u);
  EXPECT_EQ(seq.unmatched_rgb[0].line, 5);  // Two comment lines first.
  ASSERT_EQ(seq.unmatched_depth.size(), 1u);
  EXPECT_EQ(seq.unmatched_depth[0].stamp, SecondsToNs(10.2));
  EXPECT_EQ(GuessTumCameraPreset(dir), "freiburg2");
  EXPECT_EQ(GuessTumCameraPreset("/x/rgbd_tum_fr1_rpy_0-109/"), "freiburg1");
  EXPECT_EQ(GuessTumCameraPreset("/x/frame_data"), "");
  EXPECT_EQ(GuessTumCameraPreset("/x/freiburg1_vs_freiburg3"), "");

  // Stamps going backwards, duplicate colour stamps, nothing associated,
  // a listed image that is missing: errors naming file and line.
  WriteText(dir + "/rgb.txt", "# c\n10.0 rgb/10.000000.png\n9.9 rgb/x.png\n");
  EXPECT_FALSE(ReadTumRgbdSequence(dir, {}, &seq, &error));
  EXPECT_TRUE(Contains(error, "rgb.txt:3: stamp 9.9 goes backwards")) << error;
  WriteText(dir + "/rgb.txt",
            "10.0 rgb/10.000000.png\n10.0 rgb/10.033000.png\n");
  EXPECT_FALSE(ReadTumRgbdSequence(dir, {}, &seq, &error));
  EXPECT_TRUE(Contains(error, "rgb.txt:2: stamp 10.0 repeats")) << error;
  WriteText(dir + "/rgb.txt", "20.0 rgb/10.000000.png\n");
  EXPECT_FALSE(ReadTumRgbdSequence(dir, {}, &seq, &error));
  EXPECT_TRUE(Contains(error, "no colour image has a depth image")) << error;
  WriteText(dir + "/rgb.txt", "# c\n10.0 rgb/gone.png\n");
  EXPECT_FALSE(ReadTumRgbdSequence(dir, {}, &seq, &error));
  EXPECT_TRUE(Contains(error, "rgb.txt:2: ")) << error;
  EXPECT_TRUE(Contains(error, "gone.png: no such image file")) << error;
  WriteText(dir + "/rgb.txt", "# c\n10.0\n");
  EXPECT_FALSE(ReadTumRgbdSequence(dir, {}, &seq, &error));
  EXPECT_TRUE(Contains(error, "rgb.txt:2: expected 'timestamp path'")) << error;
}

TEST(RgbdFeaturesTest, UndistortsKeypointsAndUsesTheMeasuredPixelsDepth) {
  RgbdCamera camera;
  ASSERT_TRUE(TumCameraPreset("freiburg1", &camera));
  RgbdConfig config;
  RgbdFeatureExtractor extractor(StereoFeatureConfig(), camera, config);
  const StereoCalibration& c = extractor.calibration();
  EXPECT_EQ(c.baseline, config.virtual_baseline);
  // Pinhole points, distorted with OpenCV's model as the camera images
  // them: undistortion must give the pinhole positions back.
  const cv::Mat k = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0,
                     camera.fy, camera.cy, 0, 0, 1);
  const cv::Mat dist = (cv::Mat_<double>(1, 5) << camera.k1, camera.k2,
                        camera.p1, camera.p2, camera.k3);
  std::vector<cv::Point3d> rays;
  for (double x = -0.5; x <= 0.5; x += 0.25)
    for (double y = -0.4; y <= 0.4; y += 0.2) rays.emplace_back(x, y, 1.0);
  std::vector<cv::Point2d> distorted;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, dist,
                    distorted);
  std::vector<cv::KeyPoint> keypoints;
  for (const cv::Point2d& p : distorted)
    keypoints.emplace_back(cv::Point2f(p.x, p.y), 31.0f);
  cv::Mat depth(480, 640, CV_32F, cv::Scalar(0.0f));
  // Depth 2 m around the measured pixel of keypoint 0 (a smooth surface),
  // nothing elsewhere; keypoint 1 sits on a depth step.
  depth(cv::Rect(std::lround(distorted[0].x) - 3,
                 std::lround(distorted[0].y) - 3, 7, 7))
      .setTo(2.0f);
  const int col1 = std::lround(distorted[1].x),
            row1 = std::lround(distorted[1].y);
  depth(cv::Rect(col1 - 3, row1 - 3, 7, 7)).setTo(2.0f);
  depth(cv::Rect(col1 + 1, row1 - 3, 3, 7)).setTo(2.5f);
  const cv::Mat descriptors(static_cast<int>(keypoints.size()), 32, CV_8U,
                            cv::Scalar(1));
  const StereoFeatureFrame frame =
      extractor.Measure(keypoints, descriptors, depth);
  ASSERT_EQ(frame.size(), rays.size());
  double max_error = 0.0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const double u = camera.fx * rays[i].x + camera.cx;
    const double v = camera.fy * rays[i].y + camera.cy;
    max_error = std::max(max_error, std::hypot(frame.keypoints[i].pt.x - u,
                                               frame.keypoints[i].pt.y - v));
  }
  EXPECT_LT(max_error, 0.05);
  // Distortion moves these points by pixels: without it the test fails.
  EXPECT_GT(std::hypot(distorted[0].x - (camera.fx * -0.5 + camera.cx),
                       distorted[0].y - (camera.fy * -0.4 + camera.cy)),
            5.0);
  EXPECT_NEAR(frame.u_right[0],
              frame.keypoints[0].pt.x - c.fx * c.baseline / 2.0, 1e-4);
  for (size_t i = 1; i < frame.size(); ++i) EXPECT_FALSE(frame.HasStereo(i));
  // Depth outside [min_depth, max_depth] is no measurement.
  EXPECT_TRUE(
      std::isnan(VirtualRightU(320.0, config.max_depth + 0.1, c, config)));
  EXPECT_TRUE(std::isnan(VirtualRightU(320.0, 0.0, c, config)));
}

// A near point at the left edge of the image has a virtual right coordinate
// left of the image (u - fx b / z < 0): its depth is still a measurement
// (the stereo frame used to read u_R < 0 as "no depth", which silently made
// the left quarter of the image monocular at 1.5 m with b = 0.34 m).
TEST(RgbdFeaturesTest, NearPointAtTheLeftEdgeKeepsItsDepth) {
  const RgbdConfig config;
  RgbdCamera camera;
  camera.fx = camera.fy = 517.3;
  camera.cx = 318.6;
  camera.cy = 255.3;
  const StereoCalibration c = VirtualStereoCalibration(camera, config);
  const double u = 10.0, z = 0.5;
  const double ur = VirtualRightU(u, z, c, config);
  ASSERT_LT(ur, 0.0);
  StereoFeatureFrame frame;
  frame.keypoints.emplace_back(static_cast<float>(u), 200.0f, 31.0f);
  frame.u_right.push_back(ur);
  EXPECT_TRUE(frame.HasStereo(0));
  // The depth it carries back is the measured one.
  EXPECT_NEAR(c.fx * c.baseline / (u - ur), z, 1e-12);
}

// The synthetic world's frames, given to the pipeline as a source.
class FrameListSource : public VisualFrameSource {
 public:
  FrameListSource(std::vector<StereoFeatureFrame> frames,
                  const StereoCalibration& calibration, int width, int height)
      : frames_(std::move(frames)),
        calibration_(calibration),
        width_(width),
        height_(height) {}
  size_t NumFrames() const override { return frames_.size(); }
  const StereoCalibration& calibration() const override { return calibration_; }
  int width() const override { return width_; }
  int height() const override { return height_; }
  bool Load(size_t k, VisualImages* images, std::string*) const override {
    images->index = static_cast<int64_t>(k);
    images->stamp = frames_[k].stamp;
    return true;
  }
  StereoFeatureFrame Extract(const VisualImages& images,
                             StereoFeatureTimings*) const override {
    return frames_[images.index];
  }
  bool FixedRateCapture() const override { return fixed_rate_capture_; }
  void set_fixed_rate_capture(bool on) { fixed_rate_capture_ = on; }

 private:
  std::vector<StereoFeatureFrame> frames_;
  StereoCalibration calibration_;
  int width_, height_;
  bool fixed_rate_capture_ = false;
};

// A room-sized world seen by a Freiburg 1 camera: keypoints rendered with
// the camera's distortion, depth read at the measured pixel with noise
// sigma_z = depth_noise * z^2 (a structured-light sensor).
// With `loops`, loop closure is on and the run's log lines and trajectory
// are returned there.
struct LoopsRun {
  std::vector<std::string> log;
  std::vector<StampedPose> trajectory;
  int keyframes = 0;
};
double RunSyntheticRgbd(double depth_noise, bool use_depth,
                        LoopsRun* loops = nullptr) {
  RgbdCamera camera;
  TumCameraPreset("freiburg1", &camera);
  RgbdConfig rgbd;
  StereoSimulationConfig sc;
  sc.calibration = {camera.fx, camera.fy, camera.cx, camera.cy, 0.1};
  sc.frames = 40;
  sc.step = 0.02;  // 0.8 m along a weaving path.
  sc.weave_amplitude = 0.1;
  sc.points_per_metre = 1200;
  sc.min_lateral = 0.3, sc.max_lateral = 2.5;
  sc.min_height = -1.2, sc.max_height = 1.2;
  sc.min_depth = 0.4, sc.max_depth = 5.0;
  sc.pixel_sigma = 0.5;
  const StereoSimulation sim = SimulateStereo(sc);
  RgbdFeatureExtractor extractor(StereoFeatureConfig(), camera, rgbd);
  const cv::Mat k = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0,
                     camera.fy, camera.cy, 0, 0, 1);
  const cv::Mat dist = (cv::Mat_<double>(1, 5) << camera.k1, camera.k2,
                        camera.p1, camera.p2, camera.k3);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<StereoFeatureFrame> frames;
  for (size_t f = 0; f < sim.frames.size(); ++f) {
    const StereoFeatureFrame& s = sim.frames[f];
    const Pose3& pose = sim.poses[f].pose;
    std::vector<cv::Point3d> rays;
    for (const cv::KeyPoint& kp : s.keypoints) {
      rays.emplace_back((kp.pt.x - camera.cx) / camera.fx,
                        (kp.pt.y - camera.cy) / camera.fy, 1.0);
    }
    std::vector<cv::Point2d> measured;
    if (!rays.empty()) {
      cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, dist,
                        measured);
    }
    cv::Mat depth(480, 640, CV_32F, cv::Scalar(0.0f));
    std::vector<cv::KeyPoint> keypoints;
    std::vector<int> rows;
    for (size_t i = 0; i < measured.size(); ++i) {
      const int col = static_cast<int>(std::lround(measured[i].x));
      const int row = static_cast<int>(std::lround(measured[i].y));
      if (col < 0 || row < 0 || col >= 640 || row >= 480) continue;
      const Eigen::Vector3d pc =
          pose.q.conjugate() * (sim.points[sim.true_point[f][i]] - pose.t);
      const double z = pc.z() + depth_noise * pc.z() * pc.z() * noise(rng);
      // A smooth surface around the keypoint (5 x 5 pixels).
      if (use_depth) {
        depth(cv::Rect(col - 2, row - 2, 5, 5) & cv::Rect(0, 0, 640, 480))
            .setTo(static_cast<float>(z));
      }
      keypoints.emplace_back(cv::Point2f(measured[i].x, measured[i].y), 31.0f);
      keypoints.back().octave = 0;
      rows.push_back(static_cast<int>(i));
    }
    cv::Mat descriptors(static_cast<int>(rows.size()), 32, CV_8U);
    for (size_t r = 0; r < rows.size(); ++r)
      s.descriptors.row(rows[r]).copyTo(descriptors.row(static_cast<int>(r)));
    StereoFeatureFrame frame = extractor.Measure(keypoints, descriptors, depth);
    frame.index = s.index;
    frame.stamp = s.stamp;
    frames.push_back(std::move(frame));
  }
  FrameListSource source(std::move(frames), extractor.calibration(), 640, 480);
  VisualSlamConfig config;
  config.loop_closure.enabled = loops != nullptr;
  VisualSlam slam(config, &source);
  VisualSlamResult result;
  std::string error;
  VisualSlamCallbacks callbacks;
  if (loops != nullptr) {
    callbacks.log = [loops](const std::string& line) {
      loops->log.push_back(line);
    };
  }
  const bool ran = slam.Run(callbacks, &result, &error);
  if (loops != nullptr) {
    loops->trajectory = result.trajectory;
    loops->keyframes = result.stats.keyframes;
  }
  if (!use_depth) {
    // Without depth no keypoint is stereo-like: the map never starts, and
    // the run says so early instead of returning an untracked path.
    EXPECT_FALSE(ran);
    EXPECT_NE(error.find("nothing can be tracked"), std::string::npos) << error;
    return INFINITY;
  }
  EXPECT_TRUE(ran) << error;
  if (result.trajectory.size() != sim.poses.size()) return INFINITY;
  double sse = 0.0;
  for (size_t f = 0; f < sim.poses.size(); ++f) {
    sse += (result.trajectory[f].pose.t - sim.poses[f].pose.t).squaredNorm();
  }
  return std::sqrt(sse / sim.poses.size());
}

TEST(RgbdSlamTest, SyntheticRgbdWorldRecoversThePath) {
  // Kinect-like depth noise: 1.5 mm at 1 m, 6 mm at 2 m, 24 mm at 4 m.
  const double rmse = RunSyntheticRgbd(0.0015, true);
  std::printf("synthetic RGB-D: position rmse %.4f m over 0.8 m\n", rmse);
  EXPECT_LT(rmse, 0.01);
  // Without depth the map never starts (no stereo-like keypoints): the
  // same world cannot be tracked (the run fails early), so the test above
  // measures the depth.
  const double no_depth = RunSyntheticRgbd(0.0015, false);
  EXPECT_GT(no_depth, 0.1);
}

// A run with fewer keyframes than a loop needs (bow::MinKeyframesForALoop:
// every query's candidates lie more than exclude_recent keyframes back)
// trains no vocabulary and runs no detection, and ends as the run without
// loop closure does, pose for pose.
TEST(RgbdSlamTest, AShortRunSkipsTheLoopClosingItCannotUse) {
  LoopsRun with_loops;
  RunSyntheticRgbd(0.0015, true, &with_loops);
  const int needed = bow::MinKeyframesForALoop(bow::LoopDetectorConfig());
  ASSERT_GT(with_loops.keyframes, 1);
  ASSERT_LT(with_loops.keyframes, needed);
  bool skipped = false;
  for (const std::string& line : with_loops.log) {
    EXPECT_EQ(line.find("vocabulary"), std::string::npos) << line;
    skipped = skipped || line.find("loop closure: none possible among " +
                                   std::to_string(with_loops.keyframes) +
                                   " keyframes") != std::string::npos;
  }
  EXPECT_TRUE(skipped);
  // The same world without loop closure (RunSyntheticRgbd's default): the
  // same error to the bit.
  LoopsRun again;
  EXPECT_EQ(RunSyntheticRgbd(0.0015, true),
            RunSyntheticRgbd(0.0015, true, &again));
}

// A run is reproducible to the bit, also within one process whose heap
// differs between the runs: the bundle adjustments solve on copies of the
// values in one buffer, in the order the blocks enter, because Ceres orders
// an elimination group's blocks by address (on the graph's own arrays the
// results moved in the 16th digit from run to run, with the heap layout the
// image prefetch thread left).
TEST(RgbdSlamTest, RunsAreReproducibleToTheBit) {
  const double first = RunSyntheticRgbd(0.0015, true);
  std::vector<std::vector<char>> clutter;  // Another heap layout.
  for (int i = 1; i < 200; ++i) clutter.emplace_back(37 * i);
  EXPECT_EQ(first, RunSyntheticRgbd(0.0015, true));
  EXPECT_EQ(first, RunSyntheticRgbd(0.0015, true));
}

TEST(CaptureClockTest, RecoversTheClockUnderJitterAndADroppedFrame) {
  // A 30 Hz clock stamped on arrival: latencies 0 / 6 / 1.4 ms in turn (the
  // pattern of TUM fr1's colour stamps) plus 1 ms to 3 ms more, and frame
  // 7 dropped.
  const double period = 1.0 / 30.0;
  std::vector<TimeNs> capture, stamps;
  const double latency[3] = {0.0, 6.0e-3, 1.4e-3};
  for (int k = 0; k < 40; ++k) {
    if (k == 7) continue;
    const double t = 100.0 + k * period;
    capture.push_back(SecondsToNs(t));
    stamps.push_back(SecondsToNs(t + 1e-3 + latency[k % 3] + 2e-3 * (k % 2)));
  }
  const CaptureClock clock = FitCaptureClock(stamps);
  ASSERT_TRUE(clock.fixed_rate);
  EXPECT_NEAR(clock.period, period, 2e-5);
  ASSERT_EQ(clock.capture.size(), stamps.size());
  // The captures up to the constant latency (1 ms, the smallest one), which
  // the stamps cannot tell, within 0.5 ms (the least-squares line takes a
  // little of the latency pattern into its slope: 2e-5 s per period here,
  // against jumps of 6 ms); none after its stamp.
  for (size_t i = 0; i < stamps.size(); ++i) {
    EXPECT_NEAR(NsToSeconds(clock.capture[i] - capture[i]), 1e-3, 5e-4) << i;
    EXPECT_LE(clock.capture[i], stamps[i]);
  }
  // Stamps of no fixed rate, too few stamps, or stamps going backwards: the
  // stamps are taken as they are.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> step(0.01, 0.06);
  std::vector<TimeNs> irregular = {0};
  for (int k = 0; k < 30; ++k) {
    irregular.push_back(irregular.back() + SecondsToNs(step(rng)));
  }
  const CaptureClock none = FitCaptureClock(irregular);
  EXPECT_FALSE(none.fixed_rate);
  EXPECT_EQ(none.capture, irregular);
  EXPECT_FALSE(FitCaptureClock({0, 33333333}).fixed_rate);
  EXPECT_FALSE(FitCaptureClock({0, 66666666, 33333333, 99999999}).fixed_rate);
}

TEST(CaptureClockTest, PosesAtStampsFollowTheMotionBetweenCaptures) {
  // A camera turning at 2 rad/s about y and moving at 0.3 m/s along x,
  // estimated exactly at its captures, stamped 5 ms later (the last one
  // past the last capture: extrapolated).
  auto truth = [](double t) {
    return Pose3(Eigen::Vector3d(0.3 * t, 0, 0),
                 Eigen::Quaterniond(
                     Eigen::AngleAxisd(2.0 * t, Eigen::Vector3d::UnitY())));
  };
  Trajectory at_capture;
  std::vector<TimeNs> capture;
  for (int k = 0; k < 10; ++k) {
    const double t = k / 30.0;
    capture.push_back(SecondsToNs(t));
    at_capture.push_back({SecondsToNs(t + 0.005), truth(t)});
  }
  const Trajectory at_stamps = PosesAtStamps(at_capture, capture);
  ASSERT_EQ(at_stamps.size(), at_capture.size());
  for (size_t k = 0; k < at_stamps.size(); ++k) {
    const Pose3 expected = truth(NsToSeconds(at_stamps[k].stamp));
    EXPECT_EQ(at_stamps[k].stamp, at_capture[k].stamp);
    EXPECT_LT((at_stamps[k].pose.t - expected.t).norm(), 1e-9) << k;
    EXPECT_LT(at_stamps[k].pose.q.angularDistance(expected.q), 1e-9) << k;
  }
}

// The keypoints of `points` (a random descriptor each, a row of
// `descriptors`) seen by an undistorted camera at `pose`: pixel noise
// 0.3 px, depth noise 1.5 mm x z^2 (a structured-light sensor), the virtual
// right coordinate by the RGB-D settings (depth range).
void RenderRgbdKeypoints(const std::vector<Eigen::Vector3d>& points,
                         const cv::Mat& descriptors, const Pose3& pose,
                         const RgbdCamera& camera,
                         const StereoCalibration& calibration,
                         const RgbdConfig& rgbd, std::mt19937* rng,
                         StereoFeatureFrame* frame) {
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<int> rows;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d pc = pose.Inverse() * points[i];
    if (pc.z() < 0.3) continue;
    const double u =
        camera.fx * pc.x() / pc.z() + camera.cx + 0.3 * noise(*rng);
    const double v =
        camera.fy * pc.y() / pc.z() + camera.cy + 0.3 * noise(*rng);
    if (u < 0 || v < 0 || u > 639 || v > 479) continue;
    const double z = pc.z() + 0.0015 * pc.z() * pc.z() * noise(*rng);
    frame->keypoints.emplace_back(static_cast<float>(u), static_cast<float>(v),
                                  31.0f);
    frame->keypoints.back().octave = 0;
    frame->u_right.push_back(VirtualRightU(u, z, calibration, rgbd));
    rows.push_back(static_cast<int>(i));
  }
  frame->descriptors.create(static_cast<int>(rows.size()), 32, CV_8U);
  for (size_t r = 0; r < rows.size(); ++r) {
    descriptors.row(rows[r]).copyTo(
        frame->descriptors.row(static_cast<int>(r)));
  }
}

// A camera turning in place at a varying rate (yaw up to 97 deg/s, some
// pitch; as TUM fr1/rpy) in a room whose walls carry the points, captured
// at 30 Hz and stamped on arrival with a latency of 0 / 6 / 1.4 ms in turn
// (TUM fr1's colour stamps): the per-frame rotation error (deg, rmse) of
// the trajectory written at the stamps against the true poses at the
// stamps, with and without the fixed-rate capture clock.
double TurningCameraStepErrorDeg(bool fixed_rate_capture) {
  RgbdCamera camera;
  TumCameraPreset("freiburg3", &camera);  // No distortion.
  RgbdConfig rgbd;
  const StereoCalibration calibration = VirtualStereoCalibration(camera, rgbd);
  auto truth = [](double t) {
    const double yaw = 0.45 * std::sin(2.0 * M_PI * t / 1.6);
    const double pitch = 0.12 * std::sin(2.0 * M_PI * t / 0.9);
    return Pose3(
        Eigen::Vector3d(0.02 * std::sin(3.0 * t), 0, 0),
        Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX())));
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Points on a cylinder wall 2-3 m away, 1.5 m up and down; a random
  // descriptor each.
  std::vector<Eigen::Vector3d> points;
  cv::Mat descriptors(3000, 32, CV_8U);
  for (int i = 0; i < descriptors.rows; ++i) {
    const double a = 2.0 * M_PI * unit(rng), r = 2.0 + unit(rng);
    points.emplace_back(r * std::sin(a), 3.0 * unit(rng) - 1.5,
                        r * std::cos(a));
    for (int b = 0; b < 32; ++b) {
      descriptors.at<uint8_t>(i, b) = static_cast<uint8_t>(rng() & 0xff);
    }
  }
  const double latency[3] = {0.0, 6.0e-3, 1.4e-3};
  std::vector<StereoFeatureFrame> frames;
  std::vector<double> stamps;
  for (int k = 0; k < 48; ++k) {
    const double capture = k / 30.0;
    const Pose3 pose = truth(capture);
    StereoFeatureFrame frame;
    frame.index = k;
    stamps.push_back(capture + latency[k % 3]);
    frame.stamp = SecondsToNs(stamps.back());
    RenderRgbdKeypoints(points, descriptors, pose, camera, calibration, rgbd,
                        &rng, &frame);
    frames.push_back(std::move(frame));
  }
  FrameListSource source(std::move(frames), calibration, 640, 480);
  source.set_fixed_rate_capture(fixed_rate_capture);
  VisualSlamConfig config;
  config.loop_closure.enabled = false;
  VisualSlam slam(config, &source);
  VisualSlamResult result;
  std::string error;
  EXPECT_TRUE(slam.Run({}, &result, &error)) << error;
  if (result.trajectory.size() != stamps.size()) return INFINITY;
  double sse = 0.0;
  for (size_t k = 1; k < stamps.size(); ++k) {
    EXPECT_EQ(result.trajectory[k].stamp, SecondsToNs(stamps[k]));
    // Both relative to the first frame's true pose (the estimate's origin
    // is the first frame, its pose written at its stamp).
    const Pose3 a = truth(stamps[k - 1]), b = truth(stamps[k]);
    const Pose3 ea = result.trajectory[k - 1].pose;
    const Pose3 eb = result.trajectory[k].pose;
    const Eigen::Quaterniond error_q =
        (a.Inverse() * b).q.conjugate() * (ea.Inverse() * eb).q;
    const double deg = Eigen::AngleAxisd(error_q).angle() * 180.0 / M_PI;
    sse += deg * deg;
  }
  return std::sqrt(sse / (stamps.size() - 1));
}

TEST(RgbdSlamTest, FixedRateCaptureUnderArrivalStampsKeepsTheRotation) {
  // The poses are the captures'; labelled with the jittered stamps they
  // are off by the rate times the jitter (0.5 deg at 97 deg/s and 6 ms).
  const double at_stamps = TurningCameraStepErrorDeg(false);
  const double from_capture = TurningCameraStepErrorDeg(true);
  std::printf(
      "turning camera, per-frame rotation error: %.3f deg as the stamps', "
      "%.3f deg from the capture clock\n",
      at_stamps, from_capture);
  EXPECT_GT(at_stamps, 0.15);
  EXPECT_LT(from_capture, 0.06);
}

// A camera turning in place (yaw from -26 to +49 deg and most of the way
// back, up to 3.2 deg per frame, as TUM fr1/rpy) from a near wall
// (1.5-2.5 m) to a far one (3.5-4.2 m; TUM fr1/rpy frames 43-52 look at
// the far end of the room, 3.6-3.9 m, and lose depth at half of their
// keypoints with a 3.2 m limit) before which only a few near points stand.
// Returns the fewest inliers of a frame facing the far wall and the rotation
// error (deg, rmse) of the frames' poses relative to the first.
struct FarWallResult {
  int fewest_inliers = 0;
  double rotation_rmse_deg = INFINITY;
};
FarWallResult TurnToAFarWall(double max_depth) {
  RgbdCamera camera;
  TumCameraPreset("freiburg3", &camera);  // No distortion.
  RgbdConfig rgbd;
  rgbd.max_depth = max_depth;
  const StereoCalibration calibration = VirtualStereoCalibration(camera, rgbd);
  auto yaw_at = [](double t) {
    return 0.2 - 0.65 * std::cos(2.0 * M_PI * t / 2.4);
  };
  auto truth = [&](double t) {
    return Pose3(Eigen::Vector3d(0.02 * std::sin(3.0 * t), 0, 0),
                 Eigen::Quaterniond(
                     Eigen::AngleAxisd(yaw_at(t), Eigen::Vector3d::UnitY())));
  };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Azimuth a (from +z towards +x) and range r: the near wall left of
  // a = 0.1, the far wall right of it with 40 near points before it.
  std::vector<Eigen::Vector3d> points;
  auto add = [&](int n, double a0, double a1, double r0, double r1) {
    for (int i = 0; i < n; ++i) {
      const double a = a0 + (a1 - a0) * unit(rng);
      const double r = r0 + (r1 - r0) * unit(rng);
      points.emplace_back(r * std::sin(a), 3.0 * unit(rng) - 1.5,
                          r * std::cos(a));
    }
  };
  add(1500, -1.2, 0.1, 1.5, 2.5);
  add(1500, 0.1, 1.5, 3.5, 4.2);
  add(40, 0.1, 1.5, 1.5, 2.5);
  cv::Mat descriptors(static_cast<int>(points.size()), 32, CV_8U);
  for (int i = 0; i < descriptors.rows; ++i) {
    for (int b = 0; b < 32; ++b) {
      descriptors.at<uint8_t>(i, b) = static_cast<uint8_t>(rng() & 0xff);
    }
  }
  constexpr int kFrames = 60;
  std::vector<StereoFeatureFrame> frames;
  for (int k = 0; k < kFrames; ++k) {
    StereoFeatureFrame frame;
    frame.index = k;
    frame.stamp = SecondsToNs(k / 30.0);
    RenderRgbdKeypoints(points, descriptors, truth(k / 30.0), camera,
                        calibration, rgbd, &rng, &frame);
    frames.push_back(std::move(frame));
  }
  FrameListSource source(std::move(frames), calibration, 640, 480);
  VisualSlamConfig config;
  config.loop_closure.enabled = false;
  VisualSlam slam(config, &source);
  VisualSlamResult result;
  std::string error;
  FarWallResult out;
  EXPECT_TRUE(slam.Run({}, &result, &error)) << error;
  if (result.trajectory.size() != kFrames) return out;
  out.fewest_inliers = 1 << 30;
  double sse = 0.0;
  const Pose3 first = truth(0.0);
  for (int k = 1; k < kFrames; ++k) {
    // Facing the far wall: the view's left edge (yaw - 0.54 rad) beyond
    // the near wall.
    if (yaw_at(k / 30.0) > 0.7) {
      out.fewest_inliers =
          std::min(out.fewest_inliers, result.timings[k].inliers);
    }
    const Eigen::Quaterniond error_q =
        (first.Inverse() * truth(k / 30.0)).q.conjugate() *
        result.trajectory[k].pose.q;
    const double deg = Eigen::AngleAxisd(error_q).angle() * 180.0 / M_PI;
    sse += deg * deg;
  }
  out.rotation_rmse_deg = std::sqrt(sse / (kFrames - 1));
  return out;
}

TEST(RgbdSlamTest, AFarWallWithinTheSensorsRangeKeepsItsDepth) {
  // The default depth range (the Kinect's specified 4 m) against the
  // former 3.2 m (ORB-SLAM2's close-point threshold, 40 baselines of its
  // virtual stereo): beyond the limit a keypoint is monocular and makes no
  // map point, so facing the far wall the map holds its 40 near points and
  // the far points seen off-axis (depth z = range x cos of the angle, below
  // 3.2 m at the image edges) only. Fewest inliers 124 with 3.2 m, 1047
  // with 4 m.
  const FarWallResult within = TurnToAFarWall(RgbdConfig().max_depth);
  const FarWallResult cut = TurnToAFarWall(3.2);
  std::printf(
      "turning to a far wall: fewest inliers %d, rotation rmse %.3f deg "
      "(max_depth %.1f m); %d, %.3f deg (3.2 m)\n",
      within.fewest_inliers, within.rotation_rmse_deg, RgbdConfig().max_depth,
      cut.fewest_inliers, cut.rotation_rmse_deg);
  EXPECT_GT(within.fewest_inliers, 500);
  EXPECT_LT(within.rotation_rmse_deg, 0.05);
  // The mechanism: the same world with the 3.2 m limit.
  EXPECT_LT(cut.fewest_inliers, 200);
}

TEST(RgbdRunConfigTest, RoundTripsThroughItsYamlDumpAndRejectsUnknownKeys) {
  RgbdRunConfig config;
  std::string error;
  ASSERT_TRUE(
      LoadRgbdRunConfig(testing::ConfigPath("tum_rgbd.yaml"), &config, &error))
      << error;
  EXPECT_EQ(config.features.max_features, 1000);
  EXPECT_EQ(config.camera, "auto");
  EXPECT_FALSE(config.features.grid_fast);
  config.features.grid_fast = true;  // Off by default: its keys round-trip.
  config.features.min_fast_threshold = 7;
  const std::string dir = TempDir();
  const std::string dump = RgbdRunConfigToYaml(config);
  WriteText(dir + "/dump.yaml", dump);
  RgbdRunConfig again;
  ASSERT_TRUE(LoadRgbdRunConfig(dir + "/dump.yaml", &again, &error)) << error;
  EXPECT_EQ(RgbdRunConfigToYaml(again), dump);
  EXPECT_TRUE(again.features.grid_fast);
  EXPECT_EQ(again.features.min_fast_threshold, 7);
  WriteText(dir + "/bad.yaml",
            "run:\n  pipeline: rgbd\n  depth:\n    baseline: 0.1\n");
  EXPECT_FALSE(LoadRgbdRunConfig(dir + "/bad.yaml", &again, &error));
  EXPECT_TRUE(Contains(error, "bad.yaml:4")) << error;
  EXPECT_TRUE(Contains(error, "baseline")) << error;
  WriteText(dir + "/bad.yaml", "run:\n  pipeline: rgbd\n  camera: kinect\n");
  EXPECT_FALSE(LoadRgbdRunConfig(dir + "/bad.yaml", &again, &error));
  EXPECT_TRUE(Contains(error, "camera must be freiburg1")) << error;
}

// slam run on a TUM folder written here (640 x 480: the Freiburg cameras'
// principal points must fit), with the given extra run: lines.
int RunRgbd(const std::string& dir, const std::string& sequence,
            const std::string& extra = "",
            const std::string& camera = "freiburg1") {
  WriteText(dir + "/run.yaml", "run:\n  pipeline: rgbd\n  sequence: " +
                                   sequence + "\n  output_dir: " + dir +
                                   "/out\n  camera: " + camera + "\n" + extra);
  return RunSlam(
      "run --config " + dir + "/run.yaml --report " + dir + "/out/report.json",
      dir + "/log.txt");
}

const std::vector<double> kStamps = {1.0, 1.033, 1.066, 1.1, 1.133, 1.166};

TEST(RgbdRunTest, RunsOnAHandmadeFolder) {
  const std::string dir = TempDir();
  WriteTumFolder(dir + "/seq", kStamps, kStamps, 640, 480);
  ASSERT_EQ(RunRgbd(dir, dir + "/seq"), 0) << ReadText(dir + "/log.txt");
  const std::string log = ReadText(dir + "/log.txt");
  EXPECT_TRUE(Contains(log, "camera freiburg1 (preset named by run.camera)"))
      << log;
  for (const char* f :
       {"trajectory_kitti.txt", "trajectory.tum", "graph.g2o", "map_points.ply",
        "timings.csv", "map.png", "report.json"}) {
    EXPECT_TRUE(Exists(dir + "/out/" + f)) << f;
  }
  // The colour stamps, one pose each; the same view every frame: the camera
  // stays where it is.
  const std::string tum = ReadText(dir + "/out/trajectory.tum");
  EXPECT_EQ(std::count(tum.begin(), tum.end(), '\n'), 7) << tum;  // Header.
  EXPECT_TRUE(Contains(tum, "1.166")) << tum;
  std::istringstream lines(tum);
  std::string line;
  while (std::getline(lines, line)) {
    if (line[0] == '#') continue;
    std::istringstream fields(line);
    double t, x, y, z;
    fields >> t >> x >> y >> z;
    EXPECT_LT(std::sqrt(x * x + y * y + z * z), 0.01) << line;
  }
}

TEST(RgbdRunTest, BadInputFailsWithAMessageAndNoOutputs) {
  struct Case {
    const char* what;
    std::function<void(const std::string&)> damage;
    const char* extra;
    const char* expected;
  };
  const Case cases[] = {
      {"unreadable colour image",
       [](const std::string& s) {
         WriteText(s + "/rgb/1.066000.png", "not a png");
       },
       "", "rgb.txt:5: "},
      {"8-bit depth image",
       [](const std::string& s) {
         cv::imwrite(s + "/depth/1.100000.png",
                     cv::Mat(480, 640, CV_8U, cv::Scalar(50)));
       },
       "", "the depth image is 8-bit"},
      {"depth image of another size",
       [](const std::string& s) {
         cv::imwrite(s + "/depth/1.133000.png",
                     cv::Mat(240, 320, CV_16U, cv::Scalar(5000)));
       },
       "", "the depth image is 320x240 but its colour image"},
      {"depth factor 0", [](const std::string&) {},
       "  depth:\n    depth_factor: 0\n", "depth_factor must be > 0"},
      {"depth factor negative", [](const std::string&) {},
       "  depth:\n    depth_factor: -5000\n", "depth_factor must be > 0"},
      {"negative acceleration sigma of the smoothing",
       [](const std::string&) {},
       "  keyframes:\n    between_acceleration_sigma: -1\n",
       "between_acceleration_sigma >= 0"},
      {"stamps going backwards",
       [](const std::string& s) {
         WriteText(s + "/depth.txt",
                   "1.0 depth/1.000000.png\n0.5 depth/1.033000.png\n");
       },
       "", "depth.txt:2: stamp 0.5 goes backwards"},
      {"nothing associated",
       [](const std::string& s) {
         WriteText(s + "/depth.txt", "7.0 depth/1.000000.png\n");
       },
       "", "no colour image has a depth image"},
      {"camera for another image size", [](const std::string&) {},
       "  intrinsics: {fx: 500, fy: 500, cx: 600, cy: 400}\n",
       "is not in its middle half"},
  };
  for (const Case& c : cases) {
    const std::string dir = TempDir();
    WriteTumFolder(dir + "/seq", kStamps, kStamps, 640, 480);
    c.damage(dir + "/seq");
    const std::string extra = c.extra;
    const bool custom = extra.find("intrinsics") != std::string::npos;
    EXPECT_EQ(
        RunRgbd(dir, dir + "/seq", extra, custom ? "custom" : "freiburg1"), 1)
        << c.what;
    const std::string log = ReadText(dir + "/log.txt");
    EXPECT_TRUE(Contains(log, c.expected)) << c.what << ": " << log;
    EXPECT_TRUE(!Exists(dir + "/out") || fs::is_empty(dir + "/out")) << c.what;
  }
}

// The loop closing's pose graph (frontends/stereo/stereo_loop_closing.h,
// step 2) for a hand-held camera turning in place, as in TUM fr1/rpy: 25
// keyframes turn out to 1.6 rad and back while moving 5 cm; the odometry
// errs by 3 % of every turn (5.5 deg after 3.2 rad turned), and a
// correct loop joins the last keyframe to the first. With a drift model by
// distance travelled alone, the 25 keyframes are allowed 0.3 deg of
// rotation drift, the loop's chi2 exceeds the rejection threshold and the
// loop is lost; with a drift per radian turned it is accepted and corrects
// the last keyframe.
struct TurningLoopResult {
  double loop_chi2 = 0.0;
  double last_rotation_error = 0.0;  // rad, after the optimization.
};

TurningLoopResult OptimizeTurningLoop(const StereoLoopClosingConfig& config) {
  const int n = 25;
  std::vector<Pose3> truth(n);
  for (int k = 0; k < n; ++k) {
    const double s = std::sin(M_PI * k / (n - 1));
    truth[k] = Pose3(Eigen::Vector3d(0.05 * s, 0.01 * s, 0.0),
                     Eigen::Quaterniond(
                         Eigen::AngleAxisd(1.6 * s, Eigen::Vector3d::UnitY())));
  }
  Graph graph;
  Pose3 chained = truth[0];
  for (int k = 0; k < n; ++k) {
    if (k > 0) {
      const Pose3 z = truth[k - 1].Inverse() * truth[k];
      const Eigen::AngleAxisd turn(z.q);
      // An error of 3 % of each turn about another axis (the camera's x):
      // turning out and back does not cancel it.
      const Pose3 measured(
          z.t + Eigen::Vector3d(0.0, 0.0, 0.01 * turn.angle()),
          z.q * Eigen::Quaterniond(Eigen::AngleAxisd(
                    0.03 * turn.angle(), Eigen::Vector3d::UnitX())));
      chained = chained * measured;
      Factor f;
      std::string error;
      EXPECT_TRUE(MakeBetweenSE3(Pose3Key(k - 1), Pose3Key(k), measured,
                                 LoopDriftInformation(config, measured), &f,
                                 &error))
          << error;
      graph.AddNode(Pose3Key(k), Pose3Value(chained));
      graph.AddFactor(std::move(f));
    } else {
      graph.AddNode(Pose3Key(0), Pose3Value(truth[0]));
      graph.SetFixed(Pose3Key(0), true);
    }
  }
  // The verified loop: the true relative pose, as tight as a PnP on a
  // hundred points (1 mm, 0.05 deg).
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  covariance.diagonal() << 1e-6, 1e-6, 1e-6, 1e-6, 1e-6, 1e-6;
  Factor loop;
  std::string error;
  EXPECT_TRUE(MakeBetweenSE3(Pose3Key(0), Pose3Key(n - 1),
                             truth[0].Inverse() * truth[n - 1],
                             covariance.inverse(), &loop, &error))
      << error;
  const FactorId loop_id = graph.AddFactor(std::move(loop));
  OptimizerOptions options;
  options.max_iterations = 100;
  options.verbose = false;
  Optimize(&graph, options, nullptr);
  TurningLoopResult result;
  EXPECT_TRUE(graph.FactorChi2(*graph.FindFactor(loop_id), &result.loop_chi2));
  const Pose3 last = NodePose3(*graph.FindNode(Pose3Key(n - 1)));
  result.last_rotation_error =
      Eigen::AngleAxisd(truth[n - 1].q.conjugate() * last.q).angle();
  return result;
}

TEST(RgbdLoopDriftTest, ALoopAfterTurningInPlaceFitsTheDriftPerRadian) {
  StereoLoopClosingConfig by_distance;  // The stereo defaults.
  const TurningLoopResult rejected = OptimizeTurningLoop(by_distance);
  EXPECT_GT(rejected.loop_chi2, by_distance.reject_chi2);
  StereoLoopClosingConfig per_radian = by_distance;
  per_radian.drift_rotation_per_rad = 0.1;
  per_radian.drift_translation_per_rad = 0.1;
  const TurningLoopResult accepted = OptimizeTurningLoop(per_radian);
  std::printf(
      "loop chi2 %.1f by distance, %.2f per radian (last keyframe %.2f deg "
      "off)\n",
      rejected.loop_chi2, accepted.loop_chi2,
      accepted.last_rotation_error * 180.0 / M_PI);
  EXPECT_LT(accepted.loop_chi2, per_radian.reject_chi2);
  // The chained odometry ends 5.5 deg off; the loop brings it back.
  EXPECT_LT(accepted.last_rotation_error, 0.2 * M_PI / 180.0);
  std::string error;
  EXPECT_TRUE(ValidateStereoLoopClosingConfig(per_radian, &error)) << error;
  per_radian.drift_rotation_per_rad = -0.1;
  EXPECT_FALSE(ValidateStereoLoopClosingConfig(per_radian, &error));
}

// The report's numbers ("key": value).
double ReportNumber(const std::string& report, const std::string& key,
                    const std::string& after = "") {
  const size_t from = after.empty() ? 0 : report.find("\"" + after + "\"");
  const size_t at = report.find("\"" + key + "\"", from);
  if (at == std::string::npos) return NAN;
  return std::stod(report.substr(report.find(':', at) + 1));
}

TEST(RgbdRunTest, TumFr1RpyExcerptEndToEnd) {
  SLAM_REQUIRE_DATASET(DatasetPath("rgbd_tum_fr1_rpy_0-109/rgb.txt"));
  const std::string dir = TempDir();
  // The shipped config, loop closing included: the recording turns back to
  // its first view, and the loop found there corrects the drift of the
  // turns (ATE 0.043 m without it, worse than a camera that never moves).
  const std::string config = ReadText(testing::ConfigPath("tum_rgbd.yaml"));
  WriteText(dir + "/run.yaml", config);
  ASSERT_EQ(RunSlam("run --config " + dir + "/run.yaml --datasets " +
                        testing::DatasetsDir() + " --output_dir " + dir +
                        "/out --report " + dir + "/report.json",
                    dir + "/log.txt"),
            0)
      << ReadText(dir + "/log.txt");
  const std::string log = ReadText(dir + "/log.txt");
  EXPECT_TRUE(Contains(log, "camera freiburg1 (guessed from the folder name)"))
      << log;
  const std::string report = ReadText(dir + "/report.json");
  EXPECT_EQ(ReportNumber(report, "frames"), 110);
  const double ate = ReportNumber(report, "rmse", "ape_translation");
  const double rpe_r = ReportNumber(report, "rmse", "rpe_rotation");
  std::printf("TUM fr1/rpy excerpt: ATE %.4f m, RPE rotation %.3f deg\n", ate,
              rpe_r);
  // Regression bounds with a margin over what the pipeline reaches (ATE
  // 0.0144 m, RPE 0.373 deg; README): the ATE target (0.020 m),
  // and 0.42 deg (target 0.40) for the RPE. With the former 3.2 m depth limit
  // (rgbd_features.h) the ATE was 0.0203 m. Before the poses were taken as the
  // capture instants' and written at the jittered colour stamps
  // (capture_clock.h) the RPE was 0.50 deg, and before the has-depth flag (u_R
  // < 0 read as no depth), the Kinect's depth noise (b 0.08 -> 0.34 m) and the
  // tracking of the frames between keyframes it was ATE 0.0345 m (0.0426
  // without the loop), RPE 0.64 deg. A camera that never moves scores
  // ATE 0.040 m and RPE 2.26 deg here: the rotation is what is measured.
  EXPECT_GE(ReportNumber(report, "accepted", "loop_closure"), 1) << report;
  EXPECT_LT(ate, 0.020) << report;
  EXPECT_LT(rpe_r, 0.42) << report;
  EXPECT_FALSE(std::isnan(ReportNumber(report, "rmse", "rpe_per_second")))
      << report;
  for (const char* f : {"trajectory.tum", "graph.g2o", "map_points.ply",
                        "timings.csv", "map.png", "plots/trajectories.png"}) {
    EXPECT_TRUE(Exists(dir + "/out/" + f)) << f;
  }
  ASSERT_EQ(RunSlam("optimize -i " + dir + "/out/graph.g2o -o " + dir +
                        "/ba.g2o --report " + dir + "/ba.json",
                    dir + "/optimize.txt"),
            0)
      << ReadText(dir + "/optimize.txt");
}

}  // namespace
}  // namespace slam
