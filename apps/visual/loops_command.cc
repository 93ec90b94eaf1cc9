// slam loops: visual loop detection (frontends/bow/loop_detector.h) over an
// image sequence, scored against a ground-truth loop matrix:
//
//   slam loops --images DIR [--gt GT_MATRIX] [--config FILE] [--voc VOC]
//              [--plot DIR] [--report FILE.json] [--dump_config]
//
// Images are taken in natural order (2.jpg before 10.jpg). GT_MATRIX is an
// image (BMP, PNG) of N x N pixels for N images whose pixel (i, j) is
// non-zero where image i revisits image j (rtabmap's `-gt` format; OpenCV
// reads bottom-up BMPs the right way up).
//
// Vocabulary: --voc or `loops.vocabulary` (binary or DBoW2 YAML); by default
// one is trained on the sequence itself first (offline batch use, see
// apps/visual/loops_config.h for its size).
//
// Scoring, over the query images: a query's accepted loop is a true positive
// when the ground truth marks (query, candidate), else a false positive;
// precision = TP / accepted, recall = TP / images that have a true loop.
// The precision-recall curve sweeps the acceptance threshold
// (min_normalized_score) with the rest of the pipeline unchanged; its area
// (trapezoids over recall, starting at recall 0 with the first point's
// precision) and the largest recall at 100 % precision are reported.
// Per-query time: bag of words + database query + islands + verification
// (feature extraction excluded), median over the queries; database_ms:
// bag of words + database query alone (queries that reached the database).
// Outputs (--report, --plot DIR: pr_curve.png, loop_matrix.png) are written
// only once everything succeeded.
#include <gflags/gflags.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/common_flags.h"
#include "apps/json.h"
#include "apps/plot/plot.h"
#include "apps/visual/image_features.h"
#include "apps/visual/loops_config.h"
#include "apps/visual/visual_commands.h"
#include "datasets/atomic_file.h"
#include "frontends/bow/loop_detector.h"
#include "frontends/image_io.h"

DECLARE_string(images);
DECLARE_string(voc);
DECLARE_int32(orb_features);

namespace slam {
namespace {

using Clock = std::chrono::steady_clock;

struct Scores {
  int accepted = 0;
  int true_positives = 0;
  int false_positives = 0;
  int positives = 0;  // Queries with a true loop.
  double precision = 1.0;
  double recall = 0.0;
};

std::vector<bow::LoopResult> Detect(const bow::Vocabulary& vocabulary,
                                    const bow::LoopDetectorConfig& config,
                                    const std::vector<ImageFeatures>& features,
                                    std::vector<double>* ms) {
  bow::LoopDetector detector(&vocabulary, config);
  std::vector<bow::LoopResult> results;
  for (size_t i = 0; i < features.size(); ++i) {
    bow::LoopKeyframe keyframe;
    keyframe.id = static_cast<int64_t>(i);
    keyframe.stamp = static_cast<TimeNs>(i);
    keyframe.descriptors = features[i].descriptors;
    keyframe.keypoints = features[i].keypoints;
    const auto start = Clock::now();
    results.push_back(detector.Process(std::move(keyframe)));
    if (ms != nullptr) {
      ms->push_back(
          std::chrono::duration<double, std::milli>(Clock::now() - start)
              .count());
    }
  }
  return results;
}

bool IsTrueLoop(const cv::Mat& gt, int64_t query, int64_t candidate) {
  return candidate >= 0 && gt.at<uint8_t>(static_cast<int>(query),
                                          static_cast<int>(candidate)) != 0;
}

Scores Score(const std::vector<bow::LoopResult>& results, const cv::Mat& gt) {
  Scores s;
  for (int i = 0; i < gt.rows; ++i)
    if (cv::countNonZero(gt.row(i)) > 0) ++s.positives;
  for (const bow::LoopResult& r : results) {
    if (r.status != bow::LoopStatus::kAccepted) continue;
    ++s.accepted;
    if (IsTrueLoop(gt, r.query_id, r.candidate_id)) {
      ++s.true_positives;
    } else {
      ++s.false_positives;
    }
  }
  s.precision =
      s.accepted > 0 ? static_cast<double>(s.true_positives) / s.accepted : 1.0;
  s.recall = s.positives > 0
                 ? static_cast<double>(s.true_positives) / s.positives
                 : 0.0;
  return s;
}

std::string Name(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

bool ReadGroundTruth(const std::string& path, size_t num_images, cv::Mat* gt,
                     std::string* error) {
  // An N x N matrix (checked below): a header declaring more than that or
  // the usual image bound is refused unread.
  const int64_t n = static_cast<int64_t>(num_images);
  if (!ReadGrayImage(path, 1, gt, error,
                     std::max<int64_t>(kMaxImagePixels, n * n))) {
    *error += " (the ground-truth loop matrix: an image of " +
              std::to_string(n) + " x " + std::to_string(n) +
              " pixels, e.g. BMP or PNG, is expected)";
    return false;
  }
  if (gt->rows != static_cast<int>(num_images) ||
      gt->cols != static_cast<int>(num_images)) {
    *error = path + ": ground-truth matrix is " + std::to_string(gt->cols) +
             " x " + std::to_string(gt->rows) + " pixels but there are " +
             std::to_string(num_images) + " images (expected " +
             std::to_string(num_images) + " x " + std::to_string(num_images) +
             ")";
    return false;
  }
  return true;
}

}  // namespace

int RunLoopsCommand(const std::vector<std::string>& args) {
  auto fail = [](const std::string& message) {
    std::fprintf(stderr, "slam loops: %s\n", message.c_str());
    return 1;
  };
  if (!args.empty()) {
    std::fprintf(stderr, "slam loops: unexpected argument '%s'\n",
                 args[0].c_str());
    return 2;
  }
  std::string error;
  LoopsConfig config;
  if (!FLAGS_config.empty() && !LoadLoopsConfig(FLAGS_config, &config, &error))
    return fail(error);
  if (!gflags::GetCommandLineFlagInfoOrDie("voc").is_default)
    config.vocabulary = FLAGS_voc;
  if (!gflags::GetCommandLineFlagInfoOrDie("orb_features").is_default)
    config.orb_features = FLAGS_orb_features;
  if (!ValidateLoopsConfig(config, &error)) return fail("loops." + error);
  if (FLAGS_dump_config) {
    std::printf("%s", LoopsConfigToYaml(config).c_str());
    return 0;
  }
  if (FLAGS_images.empty()) {
    std::fprintf(stderr, "slam loops: --images DIR is required\n");
    return 2;
  }
  if (config.detector.verification == bow::Verification::kStereoPnp)
    return fail(
        "verification stereo_pnp needs stereo keyframes; slam loops "
        "reads monocular images (use fundamental or none)");

  // Outputs and inputs first (all checked before any work). The plot
  // folder made here is removed again if the command fails
  // (CreateOutputFolder).
  if (!FLAGS_report.empty() && !CheckOutputFile(FLAGS_report, &error))
    return fail("--report " + error);
  if (!FLAGS_plot.empty() && !CreateOutputFolder(FLAGS_plot, &error))
    return fail("--plot " + error);
  std::vector<std::string> paths;
  if (!ListImages(FLAGS_images, &paths, &error)) return fail(error);
  cv::Mat gt;
  if (!FLAGS_gt.empty() &&
      !ReadGroundTruth(FLAGS_gt, paths.size(), &gt, &error))
    return fail(error);
  bow::Vocabulary vocabulary;
  if (!config.vocabulary.empty() && !vocabulary.Load(config.vocabulary, &error))
    return fail(error);

  const auto feature_start = Clock::now();
  std::vector<ImageFeatures> features;
  if (!ExtractOrbFeatures(paths, config.orb_features, &features, &error))
    return fail(error);
  const double feature_seconds =
      std::chrono::duration<double>(Clock::now() - feature_start).count();

  double vocabulary_seconds = 0.0;
  std::string vocabulary_source = config.vocabulary;
  if (config.vocabulary.empty()) {
    size_t count = 0;
    const std::vector<cv::Mat> descriptors = DescriptorsOf(features, &count);
    const auto start = Clock::now();
    if (!TrainVocabulary(config, descriptors, count, &vocabulary, &error))
      return fail(error);
    vocabulary_seconds =
        std::chrono::duration<double>(Clock::now() - start).count();
    vocabulary_source = "trained on the sequence";
  }
  std::printf("%zu images, %s vocabulary: k = %d, L = %d, %zu words\n",
              paths.size(), vocabulary_source.c_str(), vocabulary.k(),
              vocabulary.levels(), vocabulary.size());

  std::vector<double> ms;
  const std::vector<bow::LoopResult> results =
      Detect(vocabulary, config.detector, features, &ms);
  std::vector<double> database_ms;
  for (const bow::LoopResult& r : results)
    if (r.database_ms > 0.0) database_ms.push_back(r.database_ms);
  std::sort(database_ms.begin(), database_ms.end());
  std::vector<double> sorted_ms = ms;
  std::sort(sorted_ms.begin(), sorted_ms.end());
  const double median_ms =
      sorted_ms.empty() ? 0.0 : sorted_ms[sorted_ms.size() / 2];

  // Per query: accepted loops, and missed true loops.
  int accepted = 0;
  for (size_t i = 0; i < results.size(); ++i) {
    const bow::LoopResult& r = results[i];
    const bool has_loop = !gt.empty() && cv::countNonZero(gt.row(i)) > 0;
    if (r.status == bow::LoopStatus::kAccepted) {
      ++accepted;
      std::printf("  %-12s -> %-12s score %.3f (x%.2f)  inliers %3d%s\n",
                  Name(paths[i]).c_str(), Name(paths[r.candidate_id]).c_str(),
                  r.score, r.normalized_score, r.inliers,
                  gt.empty()                                   ? ""
                  : IsTrueLoop(gt, r.query_id, r.candidate_id) ? "  true"
                                                               : "  FALSE");
    } else if (has_loop) {
      std::printf("  %-12s    missed: %s", Name(paths[i]).c_str(),
                  bow::LoopStatusName(r.status));
      if (r.candidate_id >= 0) {
        std::printf(" (best %s, x%.2f, matches %d, inliers %d)",
                    Name(paths[r.candidate_id]).c_str(), r.normalized_score,
                    r.matches, r.inliers);
      }
      std::printf("\n");
    }
  }

  JsonObject report;
  report.Add("images", paths.size())
      .Add("queries", results.size())
      .Add("accepted", accepted)
      .Add("query_ms_median", median_ms)
      .Add("query_ms_max", sorted_ms.empty() ? 0.0 : sorted_ms.back())
      .Add("database_ms_median",
           database_ms.empty() ? 0.0 : database_ms[database_ms.size() / 2])
      .Add("feature_seconds", feature_seconds)
      .Add("vocabulary", vocabulary_source)
      .Add("vocabulary_words", vocabulary.size())
      .Add("vocabulary_seconds", vocabulary_seconds);

  std::vector<double> thresholds, precisions, recalls;
  Scores scores;
  double auc = 0.0, recall_at_100 = 0.0;
  if (!gt.empty()) {
    scores = Score(results, gt);
    // Sweep of the acceptance threshold.
    bow::LoopDetectorConfig sweep = config.detector;
    for (int step = 0; step <= 60; ++step) {
      sweep.min_normalized_score = 0.05 * step;
      const Scores s = Score(Detect(vocabulary, sweep, features, nullptr), gt);
      if (s.accepted == 0) break;
      thresholds.push_back(sweep.min_normalized_score);
      precisions.push_back(s.precision);
      recalls.push_back(s.recall);
      if (s.precision >= 1.0) recall_at_100 = std::max(recall_at_100, s.recall);
    }
    std::vector<std::pair<double, double>> curve;  // (recall, precision).
    for (size_t i = 0; i < recalls.size(); ++i)
      curve.emplace_back(recalls[i], precisions[i]);
    std::sort(curve.begin(), curve.end());
    if (!curve.empty()) {
      double last_r = 0.0, last_p = curve.front().second;
      for (const auto& [r, p] : curve) {
        auc += (r - last_r) * 0.5 * (p + last_p);
        last_r = r;
        last_p = p;
      }
    }
    std::printf(
        "\nprecision %.3f (%d / %d accepted)  recall %.3f (%d / %d images "
        "with a loop)\nrecall at 100%% precision %.3f  PR AUC %.3f  query "
        "median %.3f ms\n",
        scores.precision, scores.true_positives, scores.accepted, scores.recall,
        scores.true_positives, scores.positives, recall_at_100, auc, median_ms);
    report.Add("precision", scores.precision)
        .Add("recall", scores.recall)
        .Add("recall_at_100_precision", recall_at_100)
        .Add("auc", auc)
        .Add("true_positives", scores.true_positives)
        .Add("false_positives", scores.false_positives)
        .Add("images_with_loop", scores.positives)
        .Add("threshold", config.detector.min_normalized_score)
        .Add("curve_thresholds", thresholds)
        .Add("curve_precision", precisions)
        .Add("curve_recall", recalls);
  } else {
    std::printf(
        "\n%d loops accepted; query median %.3f ms (no --gt: not "
        "scored)\n",
        accepted, median_ms);
  }
  std::string detections = "[";
  for (const bow::LoopResult& r : results) {
    if (r.status != bow::LoopStatus::kAccepted) continue;
    if (detections.size() > 1) detections += ", ";
    JsonObject d;
    d.Add("query", Name(paths[r.query_id]))
        .Add("match", Name(paths[r.candidate_id]))
        .Add("normalized_score", r.normalized_score)
        .Add("inliers", r.inliers);
    if (!gt.empty()) d.Add("true", IsTrueLoop(gt, r.query_id, r.candidate_id));
    detections += d.ToString(2);
  }
  report.AddRaw("detections", detections + "]");

  // Outputs.
  if (!FLAGS_plot.empty()) {
    if (!gt.empty()) {
      plot::Axes axes;
      axes.title = "Loop detection: precision-recall over the threshold";
      axes.xlabel = "recall";
      axes.ylabel = "precision";
      plot::Line line;
      line.x = recalls;
      line.y = precisions;
      line.label = "AUC " + std::to_string(auc).substr(0, 5);
      axes.lines.push_back(line);
      plot::Marker marker;
      marker.x = scores.recall;
      marker.y = scores.precision;
      marker.color = plot::kRed;
      marker.label = "default threshold";
      axes.markers.push_back(marker);
      // Pins the axes to [0, 1].
      plot::Line frame;
      frame.x = {0.0, 1.0};
      frame.y = {0.0, 1.0};
      frame.color = cv::Scalar(255, 255, 255);
      frame.thickness = 1;
      axes.lines.push_back(frame);
      if (!plot::SavePng(FLAGS_plot + "/pr_curve.png",
                         plot::RenderFigure({axes}, 900, 800), &error))
        return fail(error);
    }
    // Loop matrix: ground truth grey, accepted true loops green, false red.
    const int n = static_cast<int>(paths.size());
    const int scale = std::max(1, 800 / std::max(n, 1));
    cv::Mat image(n, n, CV_8UC3, cv::Scalar(255, 255, 255));
    if (!gt.empty()) image.setTo(cv::Scalar(170, 170, 170), gt);
    for (const bow::LoopResult& r : results) {
      if (r.status != bow::LoopStatus::kAccepted) continue;
      const bool ok = gt.empty() || IsTrueLoop(gt, r.query_id, r.candidate_id);
      image.at<cv::Vec3b>(static_cast<int>(r.query_id),
                          static_cast<int>(r.candidate_id)) =
          ok ? cv::Vec3b(44, 160, 44) : cv::Vec3b(40, 39, 214);
    }
    cv::Mat big;
    cv::resize(image, big, cv::Size(n * scale, n * scale), 0, 0,
               cv::INTER_NEAREST);
    if (!plot::SavePng(FLAGS_plot + "/loop_matrix.png", big, &error))
      return fail(error);
  }
  if (!FLAGS_report.empty() &&
      !WriteFileAtomically(FLAGS_report, report.ToString(0) + "\n", &error))
    return fail(error);
  return 0;
}

}  // namespace slam
