// Tests of `slam eval` run as a process: table, JSON report, plots, config,
// and its errors; figures compared with the library computed in-process.
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <zlib.h>

#include <opencv2/imgproc.hpp>

#include "apps/plot/plot.h"
#include "core/metrics/evaluation.h"
#include "datasets/trajectory_io.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::ReadText;

// A minimal PNG reader for what plot::EncodePng writes (8-bit RGB, filter
// none): checks signature and CRCs, inflates, returns a BGR image (empty on
// any problem).
cv::Mat DecodePng(const std::string& png) {
  auto u32 = [&](size_t at) {
    return (static_cast<uint32_t>(static_cast<unsigned char>(png[at])) << 24) |
           (static_cast<uint32_t>(static_cast<unsigned char>(png[at + 1]))
            << 16) |
           (static_cast<uint32_t>(static_cast<unsigned char>(png[at + 2]))
            << 8) |
           static_cast<uint32_t>(static_cast<unsigned char>(png[at + 3]));
  };
  if (png.size() < 8 || png.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return {};
  size_t pos = 8;
  int width = 0, height = 0;
  std::string idat;
  while (pos + 12 <= png.size()) {
    const uint32_t len = u32(pos);
    if (pos + 12 + len > png.size()) return {};
    const std::string type = png.substr(pos + 4, 4);
    const uint32_t crc = static_cast<uint32_t>(crc32(
        0L, reinterpret_cast<const Bytef*>(png.data() + pos + 4), len + 4));
    if (crc != u32(pos + 8 + len)) return {};
    if (type == "IHDR") {
      width = static_cast<int>(u32(pos + 8));
      height = static_cast<int>(u32(pos + 12));
      if (png[pos + 16] != 8 || png[pos + 17] != 2) return {};
    } else if (type == "IDAT") {
      idat += png.substr(pos + 8, len);
    } else if (type == "IEND") {
      break;
    }
    pos += 12 + len;
  }
  if (width <= 0 || height <= 0) return {};
  std::string raw(static_cast<size_t>(height) * (3 * width + 1), '\0');
  uLongf size = raw.size();
  if (uncompress(reinterpret_cast<Bytef*>(&raw[0]), &size,
                 reinterpret_cast<const Bytef*>(idat.data()),
                 idat.size()) != Z_OK ||
      size != raw.size()) {
    return {};
  }
  cv::Mat img(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    const char* row = raw.data() + static_cast<size_t>(y) * (3 * width + 1);
    if (row[0] != 0) return {};
    for (int x = 0; x < width; ++x) {
      img.at<cv::Vec3b>(y, x) =
          cv::Vec3b(row[1 + 3 * x + 2], row[1 + 3 * x + 1], row[1 + 3 * x]);
    }
  }
  return img;
}

TEST(PngTest, EncodeDecodeRoundTrip) {
  cv::Mat img(37, 53, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::line(img, {0, 0}, {52, 36}, cv::Scalar(10, 20, 200), 3);
  img.at<cv::Vec3b>(5, 7) = cv::Vec3b(1, 2, 3);
  std::string png;
  ASSERT_TRUE(plot::EncodePng(img, &png));
  const cv::Mat back = DecodePng(png);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(cv::norm(img, back, cv::NORM_INF), 0.0);
  EXPECT_EQ(back.at<cv::Vec3b>(5, 7), cv::Vec3b(1, 2, 3));  // BGR kept.
  png[40] ^= 1;  // A corrupted byte fails the CRC.
  EXPECT_TRUE(DecodePng(png).empty());
}

// The number after "key": inside the object "object": { ... } of a JSON text.
double JsonNumberIn(const std::string& json, const std::string& object,
                    const std::string& key) {
  size_t pos = 0;
  if (!object.empty()) {
    pos = json.find("\"" + object + "\": {");
    if (pos == std::string::npos) return NAN;
  }
  pos = json.find("\"" + key + "\": ", pos);
  if (pos == std::string::npos) return NAN;
  return std::strtod(json.c_str() + pos + key.size() + 4, nullptr);
}

Trajectory Synthetic(bool estimate) {
  Trajectory t;
  for (int i = 0; i < 400; ++i) {
    const double s = 0.03 * i;
    StampedPose p;
    p.stamp = 1700000000 * kNanosecondsPerSecond + i * 50000000ll;
    Eigen::Vector3d x(8.0 * std::cos(s), 5.0 * std::sin(s),
                      0.3 * std::sin(3 * s));
    Eigen::Quaterniond q(Eigen::AngleAxisd(s, Eigen::Vector3d::UnitZ()));
    if (estimate) {
      // A drift, then a rigid offset, and stamps 3 ms late.
      x += Eigen::Vector3d(0.002 * i, 0.05 * std::sin(0.2 * i), 0.0);
      q = q * Eigen::Quaterniond(Eigen::AngleAxisd(0.01 * std::sin(0.1 * i),
                                                   Eigen::Vector3d::UnitX()));
      const Eigen::Quaterniond r(
          Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
      x = r * x + Eigen::Vector3d(2.0, -1.0, 0.5);
      q = r * q;
      p.stamp += 3000000;
    }
    p.pose = Pose3(x, q);
    t.push_back(p);
  }
  return t;
}

class EvalCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::TempDir();
    ref_ = dir_ + "/ref.tum";
    est_ = dir_ + "/est.tum";
    std::string error;
    ASSERT_TRUE(
        WriteTrajectory(ref_, Synthetic(false), TrajectoryFormat::kTum, &error))
        << error;
    ASSERT_TRUE(
        WriteTrajectory(est_, Synthetic(true), TrajectoryFormat::kTum, &error))
        << error;
  }
  std::string dir_, ref_, est_;
};

TEST_F(EvalCommandTest, TableReportAndPlotsAgreeWithTheLibrary) {
  const std::string log = dir_ + "/log.txt";
  const std::string report = dir_ + "/report.json";
  const std::string plots = dir_ + "/plots";
  ASSERT_EQ(testing::RunSlam("eval --ref " + ref_ + " --est " + est_ +
                                 " --rpe_delta 2 --rpe_unit m --report " +
                                 report + " --plot " + plots,
                             log),
            0)
      << ReadText(log);
  const std::string out = ReadText(log);
  EXPECT_NE(out.find("400 of max. 400 possible pairs"), std::string::npos)
      << out;
  EXPECT_NE(out.find("APE translation [m]"), std::string::npos);
  EXPECT_NE(out.find("SE(3) Umeyama"), std::string::npos);

  EvalSettings s;
  s.rpe.delta = 2.0;
  s.rpe.unit = DeltaUnit::kMeters;
  EvalResult r;
  std::string error;
  ASSERT_TRUE(
      EvaluateTrajectories(Synthetic(false), Synthetic(true), s, &r, &error))
      << error;
  const std::string json = ReadText(report);
  EXPECT_EQ(JsonNumberIn(json, "", "matched_pairs"), 400.0) << json;
  for (const char* object :
       {"ape_translation", "ape_rotation", "rpe_translation", "rpe_rotation"}) {
    for (const char* key :
         {"rmse", "mean", "median", "std", "min", "max", "sse"}) {
      EXPECT_TRUE(std::isfinite(JsonNumberIn(json, object, key)))
          << object << " " << key;
    }
  }
  EXPECT_NEAR(JsonNumberIn(json, "ape_translation", "rmse"),
              r.ape_translation_stats.rmse, 1e-12);
  EXPECT_NEAR(JsonNumberIn(json, "ape_translation", "median"),
              r.ape_translation_stats.median, 1e-12);
  EXPECT_NEAR(JsonNumberIn(json, "ape_rotation", "max"),
              r.ape_rotation_stats.max, 1e-10);
  EXPECT_NEAR(JsonNumberIn(json, "rpe_translation", "mean"),
              r.rpe_translation_stats.mean, 1e-12);
  EXPECT_NEAR(JsonNumberIn(json, "rpe_translation", "std"),
              r.rpe_translation_stats.std, 1e-12);
  EXPECT_NEAR(JsonNumberIn(json, "rpe_rotation", "rmse"),
              r.rpe_rotation_stats.rmse, 1e-10);
  EXPECT_NEAR(JsonNumberIn(json, "settings", "t_max_diff"), 0.01, 0);
  EXPECT_EQ(json.find("\"kitti\": {"), std::string::npos);  // Not asked for.
  // The rigid offset is found and removed: APE well below the offset.
  EXPECT_LT(r.ape_translation_stats.rmse, 0.5);

  for (const char* name :
       {"trajectories.png", "ape_map.png", "ape.png", "rpe.png"}) {
    const cv::Mat img = DecodePng(ReadText(plots + "/" + name));
    ASSERT_FALSE(img.empty()) << name;
    EXPECT_EQ(img.cols, 1400) << name;
    // Not blank: some dark pixels (text, axes) and some coloured ones.
    cv::Mat gray;
    cv::extractChannel(img, gray, 0);
    EXPECT_GT(cv::countNonZero(gray < 100), 1000) << name;
  }
}

TEST_F(EvalCommandTest, PositionalFormAndAlignmentChoices) {
  const std::string log = dir_ + "/log.txt";
  ASSERT_EQ(
      testing::RunSlam("eval " + ref_ + " " + est_ + " --align none", log), 0)
      << ReadText(log);
  EXPECT_NE(ReadText(log).find("alignment: none"), std::string::npos);
  ASSERT_EQ(
      testing::RunSlam("eval " + ref_ + " " + est_ + " --align sim3", log), 0)
      << ReadText(log);
  EXPECT_NE(ReadText(log).find("Sim(3) Umeyama on all 400 pairs"),
            std::string::npos)
      << ReadText(log);
}

TEST_F(EvalCommandTest, UsageAndInputErrors) {
  const std::string log = dir_ + "/log.txt";
  EXPECT_EQ(testing::RunSlam("eval --ref " + ref_, log), 2);
  EXPECT_NE(ReadText(log).find("give the reference and the estimate"),
            std::string::npos);
  EXPECT_EQ(
      testing::RunSlam(
          "eval --ref " + ref_ + " --est " + est_ + " --align affine", log),
      2);
  EXPECT_NE(ReadText(log).find("--align must be"), std::string::npos);
  EXPECT_EQ(testing::RunSlam(
                "eval --ref " + ref_ + " --est " + dir_ + "/missing.txt", log),
            1);
  EXPECT_NE(ReadText(log).find("missing.txt: cannot open"), std::string::npos)
      << ReadText(log);
  EXPECT_EQ(
      testing::RunSlam(
          "eval --ref " + ref_ + " --est " + est_ + " --format kitti", log),
      1);
  EXPECT_NE(ReadText(log).find("ref.tum:2: expected 12 values"),
            std::string::npos)
      << ReadText(log);
}

TEST_F(EvalCommandTest, NoMatchingStampsSaysWhyAndOffsetFixesIt) {
  Trajectory late = Synthetic(true);
  for (auto& p : late) p.stamp += 100 * kNanosecondsPerSecond;
  const std::string late_path = dir_ + "/late.tum";
  std::string error;
  ASSERT_TRUE(WriteTrajectory(late_path, late, TrajectoryFormat::kTum, &error));
  const std::string log = dir_ + "/log.txt";
  EXPECT_EQ(testing::RunSlam("eval --ref " + ref_ + " --est " + late_path, log),
            1);
  const std::string out = ReadText(log);
  EXPECT_NE(out.find("found no matching timestamps"), std::string::npos) << out;
  EXPECT_NE(out.find("--t_offset -100.003"), std::string::npos) << out;
  EXPECT_EQ(testing::RunSlam("eval --ref " + ref_ + " --est " + late_path +
                                 " --t_offset -100",
                             log),
            0)
      << ReadText(log);
  EXPECT_NE(ReadText(log).find("400 of max. 400"), std::string::npos);
}

TEST_F(EvalCommandTest, BadOffsetsAndHugeDeltasAreRefusedCleanly) {
  const std::string log = dir_ + "/log.txt";
  const std::string both = "eval --ref " + ref_ + " --est " + est_;
  // NaN offset: refused before the association (UBSan: negation overflow).
  EXPECT_EQ(testing::RunSlam(both + " --t_offset nan", log), 2);
  EXPECT_NE(ReadText(log).find("t_offset must be a finite"), std::string::npos)
      << ReadText(log);
  // 2^64 frames and more: no pair (the size_t cast wrapped to 0 and the pair
  // loop grew memory without end).
  EXPECT_EQ(testing::RunSlam(both + " --rpe_delta 18446744073709551616", log),
            1);
  EXPECT_NE(ReadText(log).find("produced no pose pair"), std::string::npos)
      << ReadText(log);
  // 1e10 s overflowed int64 nanoseconds: every consecutive pair was taken.
  EXPECT_EQ(testing::RunSlam(both + " --rpe_delta 1e10 --rpe_unit s", log), 1);
  EXPECT_NE(ReadText(log).find("produced no pose pair"), std::string::npos)
      << ReadText(log);
}

TEST_F(EvalCommandTest, DuplicateStampsAreReadWithAWarningAndUniquePairs) {
  // A reference with one duplicate stamp (as evo's fr2_desk_groundtruth.txt)
  // is read, with a warning; the estimate's pose at that stamp pairs with the
  // first of the two.
  std::ofstream(dir_ + "/dup_ref.tum") << "1.0 0 0 0 0 0 0 1\n"
                                          "2.0 1 0 0 0 0 0 1\n"
                                          "2.0 9 0 0 0 0 0 1\n"
                                          "3.0 2 0 0 0 0 0 1\n";
  std::ofstream(dir_ + "/dup_est.tum") << "1.0 0 0 0 0 0 0 1\n"
                                          "2.0 1 0 0 0 0 0 1\n"
                                          "3.0 2 0 0 0 0 0 1\n";
  const std::string log = dir_ + "/log.txt";
  const std::string report = dir_ + "/dup.json";
  ASSERT_EQ(testing::RunSlam("eval " + dir_ + "/dup_ref.tum " + dir_ +
                                 "/dup_est.tum --align none --report " + report,
                             log),
            0)
      << ReadText(log);
  EXPECT_NE(ReadText(log).find("dup_ref.tum:3: timestamp 2.000000000 s is a "
                               "duplicate of the one on line 2"),
            std::string::npos)
      << ReadText(log);
  EXPECT_EQ(JsonNumberIn(ReadText(report), "", "matched_pairs"), 3.0);
  EXPECT_EQ(JsonNumberIn(ReadText(report), "ape_translation", "max"), 0.0);
  // A reference pose paired twice (t_max_diff above half the sampling
  // interval) stays paired twice, as evo; --unique_pairs keeps the closer.
  std::ofstream(dir_ + "/sparse_ref.tum") << "1.0 0 0 0 0 0 0 1\n"
                                             "2.0 1 0 0 0 0 0 1\n"
                                             "3.0 2 0 0 0 0 0 1\n"
                                             "4.0 3 0 0 0 0 0 1\n";
  std::ofstream(dir_ + "/dense_est.tum") << "1.0 0 0 0 0 0 0 1\n"
                                            "2.0 1 0 0 0 0 0 1\n"
                                            "2.25 1 0 0 0 0 0 1\n";
  const std::string pair = "eval " + dir_ + "/sparse_ref.tum " + dir_ +
                           "/dense_est.tum --align none --t_max_diff 0.3 "
                           "--report " +
                           report;
  ASSERT_EQ(testing::RunSlam(pair, log), 0) << ReadText(log);
  EXPECT_EQ(JsonNumberIn(ReadText(report), "", "matched_pairs"), 3.0);
  EXPECT_EQ(JsonNumberIn(ReadText(report), "association", "reused_poses"), 1.0);
  ASSERT_EQ(testing::RunSlam(pair + " --unique_pairs", log), 0)
      << ReadText(log);
  EXPECT_EQ(JsonNumberIn(ReadText(report), "", "matched_pairs"), 2.0);
  EXPECT_EQ(JsonNumberIn(ReadText(report), "association", "dropped_duplicates"),
            1.0);
}

TEST_F(EvalCommandTest, ConfigFileAndDumpConfig) {
  const std::string log = dir_ + "/log.txt";
  const std::string config = dir_ + "/eval.yaml";
  std::ofstream(config)
      << "eval:\n  align: sim3\n  rpe_delta: 3\n  rpe_unit: m\n";
  ASSERT_EQ(testing::RunSlam("eval --config " + config + " --dump_config", log),
            0)
      << ReadText(log);
  std::string out = ReadText(log);
  EXPECT_NE(out.find("align: sim3"), std::string::npos) << out;
  EXPECT_NE(out.find("rpe_unit: m"), std::string::npos) << out;
  // An explicit flag wins over the file.
  ASSERT_EQ(
      testing::RunSlam(
          "eval --config " + config + " --align origin --dump_config", log),
      0);
  EXPECT_NE(ReadText(log).find("align: origin"), std::string::npos);
  std::ofstream(config) << "eval:\n  algin: sim3\n";
  EXPECT_EQ(
      testing::RunSlam(
          "eval --config " + config + " --ref " + ref_ + " --est " + est_, log),
      2);
  EXPECT_NE(ReadText(log).find("unknown key 'algin'"), std::string::npos)
      << ReadText(log);
}

TEST(EvalCommandRealDataTest, Kitti00WithTheKittiMetric) {
  const std::string dir = testing::DatasetPath("trajectories_evo");
  SLAM_REQUIRE_DATASET(dir + "/KITTI_00_gt.txt");
  const std::string tmp = testing::TempDir();
  const std::string log = tmp + "/log.txt";
  const std::string report = tmp + "/kitti.json";
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(
      testing::RunSlam("eval --ref " + dir + "/KITTI_00_gt.txt --est " + dir +
                           "/KITTI_00_ORB.txt --rpe_delta 10 "
                           "--rpe_unit m --kitti --report " +
                           report,
                       log),
      0)
      << ReadText(log);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  std::printf(
      "slam eval KITTI 00 (APE, RPE 10 m, KITTI metric, JSON), whole "
      "process: %.0f ms\n%s",
      1e3 * seconds, ReadText(log).c_str());
  // The time is printed, not asserted: it depends on the machine's load and
  // the build (30 % over 1 s under ASan); scripts/benchmark_eval_scale.py
  // measures it.
  const std::string json = ReadText(report);
  EXPECT_EQ(JsonNumberIn(json, "", "matched_pairs"), 4541.0);
  EXPECT_NEAR(JsonNumberIn(json, "ape_translation", "rmse"), 1.303450, 5e-7);
  EXPECT_NEAR(JsonNumberIn(json, "kitti", "t_rel_percent"), 0.6997, 5e-5);
  // The devkit's figure on the raw files: 0.002533521 deg/m.
  EXPECT_NEAR(JsonNumberIn(json, "kitti", "r_rel_deg_per_100m"), 0.2533521,
              5e-8);
  EXPECT_NE(ReadText(log).find("r_rel 0.002533521 deg/m"), std::string::npos)
      << ReadText(log);
  EXPECT_NE(ReadText(log).find("association: by index, 4541 pairs"),
            std::string::npos);
}

}  // namespace
}  // namespace slam
