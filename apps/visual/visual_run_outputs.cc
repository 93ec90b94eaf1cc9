#include "apps/visual/visual_run_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <utility>
#include <vector>

#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/json.h"
#include "apps/map_plot.h"
#include "apps/progress_bar.h"
#include "apps/run_config.h"
#include "datasets/atomic_file.h"
#include "datasets/g2o_io.h"
#include "datasets/text_util.h"
#include "datasets/trajectory_io.h"

namespace slam {
namespace {

namespace fs = std::filesystem;

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double pos = p * (values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(values.size() - 1, lo + 1);
  return values[lo] + (pos - lo) * (values[hi] - values[lo]);
}

std::string PlyText(const VisualRunInfo& info,
                    const std::vector<Eigen::Vector3d>& points) {
  std::string out = "ply\nformat ascii 1.0\ncomment slam " + info.pipeline +
                    " map points (world frame = first " + info.camera +
                    ", x right, y down, z forward)\nelement vertex " +
                    std::to_string(points.size()) +
                    "\nproperty double x\nproperty double y\nproperty double "
                    "z\nend_header\n";
  for (const Eigen::Vector3d& p : points) {
    text::AppendDouble(p.x(), &out);
    out += ' ';
    text::AppendDouble(p.y(), &out);
    out += ' ';
    text::AppendDouble(p.z(), &out);
    out += '\n';
  }
  return out;
}

std::string TimingsCsv(const std::vector<VisualFrameTiming>& timings) {
  std::string out =
      "# frame, read_ms, features_ms, matching_ms, tracking_ms, local_ba_ms, "
      "total_ms, keyframe, inliers\n";
  char line[256];
  for (const VisualFrameTiming& t : timings) {
    std::snprintf(line, sizeof(line),
                  "%lld,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%d\n",
                  static_cast<long long>(t.frame), t.read_ms,
                  t.features.features_ms, t.features.matching_ms, t.tracking_ms,
                  t.local_ba_ms, t.total_ms, t.keyframe ? 1 : 0, t.inliers);
    out += line;
  }
  return out;
}

JsonObject StageJson(const std::vector<double>& ms) {
  JsonObject o;
  o.Add("median_ms", Percentile(ms, 0.5)).Add("p95_ms", Percentile(ms, 0.95));
  return o;
}

// Map points and the camera path seen from above: the world is the first
// camera's frame (x right, y down, z forward), so the ground plane is x-z
// (a plot chosen by extent could pick the vertical axis on a straight
// drive).
MapPlotData TopView(const Trajectory& trajectory,
                    const std::vector<Eigen::Vector3d>& points) {
  MapPlotData data;
  data.title = "map points and camera path seen from above (x-z plane)";
  data.xlabel = "x [m] (right of the first camera)";
  data.ylabel = "z [m] (ahead of the first camera)";
  for (const StampedPose& p : trajectory) {
    data.trajectory_x.push_back(p.pose.t.x());
    data.trajectory_y.push_back(p.pose.t.z());
  }
  for (const Eigen::Vector3d& p : points) {
    data.landmark_x.push_back(p.x());
    data.landmark_y.push_back(p.z());
  }
  return data;
}

// The summary lines on stdout and the report's statistics and timings.
void ReportStatistics(const VisualRunInfo& info, const VisualSlamResult& result,
                      JsonObject* report) {
  const StereoOdometryStats& s = result.stats;
  std::vector<double> total, features, matching, tracking, local_ba;
  for (const VisualFrameTiming& t : result.timings) {
    total.push_back(t.total_ms);
    features.push_back(t.features.features_ms);
    matching.push_back(t.features.matching_ms);
    tracking.push_back(t.tracking_ms);
    local_ba.push_back(t.local_ba_ms);
  }
  std::printf(
      "run: %d frames, %d keyframes, %zu map points (%d created, %d "
      "observations removed as outliers); %d PnP-RANSAC fallbacks, %d frames "
      "lost; %d local BAs; global BA %.1f ms (robust chi2 %.6g -> %.6g)\n",
      s.frames, s.keyframes, result.map_points.size(), s.points_created,
      s.observations_removed, s.pnp_fallbacks, s.lost_frames,
      s.local_bundle_adjustments,
      s.global_ba_initial_chi2 > 0 ? s.final_ba_ms : 0.0,
      s.global_ba_initial_chi2, s.global_ba_final_chi2);
  if (s.lost_frames > 0) {
    // Their poses are guesses (the motion model, or the origin before the
    // map started).
    std::fprintf(stderr,
                 "run: warning: %d of %d frames lost (no pose from their "
                 "images: too few features or matches; blank, uniform or "
                 "noise images?)\n",
                 s.lost_frames, s.frames);
  }
  std::printf("run: per frame (ms)   median     p95\n");
  const std::pair<const char*, const std::vector<double>*> stages[] = {
      {"features", &features},
      {info.matching_stage.c_str(), &matching},
      {"tracking", &tracking},
      {"local BA", &local_ba},
      {"whole pipeline", &total}};
  for (const auto& [name, values] : stages) {
    std::printf("run:   %-16s %7.2f %7.2f\n", name, Percentile(*values, 0.5),
                Percentile(*values, 0.95));
  }

  report->Add("pipeline", info.pipeline)
      .Add("sequence", info.sequence)
      .Add("frames", static_cast<int>(result.trajectory.size()))
      .Add("keyframes", s.keyframes)
      .Add("map_points", result.map_points.size())
      .Add("pnp_fallbacks", s.pnp_fallbacks)
      .Add("lost_frames", s.lost_frames);
  JsonObject timing = StageJson(total);
  timing.Add("features", StageJson(features))
      .Add(info.matching_key, StageJson(matching))
      .Add("tracking", StageJson(tracking))
      .Add("local_ba", StageJson(local_ba))
      .Add("global_ba_ms", s.final_ba_ms);
  report->Add("timing", timing);
  JsonObject loop_json;
  loop_json.Add("enabled", info.loop_closure_enabled)
      .Add("candidates", result.loops.detected)
      .Add("accepted", result.loops.accepted)
      .Add("rejected", result.loops.rejected)
      .Add("largest_correction_m", result.loops.largest_correction)
      .Add("seconds", result.loop_seconds);
  report->Add("loop_closure", loop_json);
}

}  // namespace

int WriteVisualRun(const VisualRunInfo& info, const VisualSlam& slam,
                   const VisualSlamResult& result) {
  const fs::path out_dir(info.output_dir);
  const std::string kitti_path = (out_dir / "trajectory_kitti.txt").string();
  const std::string tum_path = (out_dir / "trajectory.tum").string();
  const std::string graph_path = (out_dir / "graph.g2o").string();
  const std::string ply_path = (out_dir / "map_points.ply").string();
  const std::string csv_path = (out_dir / "timings.csv").string();
  const std::string map_path = (out_dir / "map.png").string();
  const std::string plot_dir = (out_dir / "plots").string();
  // A failed run publishes none of what it wrote: main() keeps every output
  // in an OutputStage (datasets/atomic_file.h) until the command succeeds.
  std::string error;
  auto fail = [&](const std::string& message) {
    std::cerr << "run: " << message << "\n";
    return 1;
  };
  const Trajectory& trajectory = result.trajectory;
  const std::vector<Eigen::Vector3d>& points = result.map_points;
  if (!WriteTrajectory(kitti_path, trajectory, TrajectoryFormat::kKitti,
                       &error) ||
      !WriteTrajectory(tum_path, trajectory, TrajectoryFormat::kTum, &error) ||
      !WriteG2o(graph_path, slam.odometry().graph(), &error) ||
      !WriteFileAtomically(ply_path, PlyText(info, points), &error) ||
      !WriteFileAtomically(csv_path, TimingsCsv(result.timings), &error) ||
      !WriteMapPlot(map_path, TopView(trajectory, points), &error)) {
    return fail(error);
  }

  JsonObject report;
  ReportStatistics(info, result, &report);
  // An evaluation that cannot be computed (one frame: no pose pair) is
  // reported as such; the run itself succeeded.
  EvalResult check;
  std::string why;
  const bool evaluate = !info.ground_truth.empty() &&
                        EvaluateTrajectories(info.ground_truth, trajectory,
                                             info.eval, &check, &why);
  if (!info.ground_truth.empty() && !evaluate) {
    std::printf("run: evaluation not computed: %s\n", why.c_str());
    JsonObject evaluation;
    evaluation.Add("computed", false).Add("reason", why);
    report.Add("evaluation", evaluation);
  }
  if (evaluate) {
    EvalResult eval;
    EvalLabels labels;
    labels.ref_name = "ground truth";
    labels.est_name = info.est_name;
    if (!EvaluateAndReport(info.ground_truth, trajectory, info.eval, labels,
                           plot_dir, std::cout, &eval, &error)) {
      return fail(error);
    }
    JsonObject evaluation = EvalResultJson(eval, info.eval);
    if (!eval.ref.empty()) {
      const double end_error =
          (eval.est_aligned.back().t - eval.ref.back().t).norm();
      const double percent = 100.0 * end_error / eval.ref_path_length;
      std::printf("run: end-point error %.4f m over a %.2f m path (%.3f %%)\n",
                  end_error, eval.ref_path_length, percent);
      evaluation.Add("end_point_error_m", end_error)
          .Add("end_point_error_percent", percent);
    }
    if (info.rpe_per_second) {
      EvalSettings per_second = info.eval;
      per_second.rpe.delta = 1.0;
      per_second.rpe.unit = DeltaUnit::kSeconds;
      per_second.kitti = false;
      EvalResult second;
      if (!EvaluateTrajectories(info.ground_truth, trajectory, per_second,
                                &second, &error)) {
        return fail("RPE per second: " + error);
      }
      std::printf(
          "run: RPE per second (%s): translation rmse %.4f m, rotation rmse "
          "%.3f deg\n",
          DescribeRpeOptions(per_second.rpe).c_str(),
          second.rpe_translation_stats.rmse, second.rpe_rotation_stats.rmse);
      JsonObject rpe;
      rpe.Add("translation", StatisticsJson(second.rpe_translation_stats, "m"))
          .Add("rotation", StatisticsJson(second.rpe_rotation_stats, "deg"));
      evaluation.Add("rpe_per_second", rpe);
    }
    report.Add("evaluation", evaluation);
  }
  if (!FLAGS_report.empty()) {
    if (!WriteFileAtomically(FLAGS_report, report.ToString(2) + "\n", &error))
      return fail(error);
  }
  std::printf("run: wrote %s, %s, %s, %s, %s, %s%s (%.2f s)\n",
              kitti_path.c_str(), tum_path.c_str(), graph_path.c_str(),
              ply_path.c_str(), csv_path.c_str(), map_path.c_str(),
              !evaluate ? "" : (", " + plot_dir + "/").c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                            info.start)
                  .count());
  return 0;
}

std::string GroundTruthPathOf(const std::string& configured,
                              const std::string& found) {
  if (!FLAGS_gt.empty()) return FLAGS_gt;
  if (!configured.empty()) return ResolveDatasetPath(configured);
  return found;
}

int RunVisualSlamAndWrite(VisualSlamConfig config,
                          const VisualFrameSource& source,
                          const VisualRunInfo& info) {
  // Made now (the stereo command made it before its checks already) and
  // removed again if the run fails or is stopped (datasets/atomic_file.h).
  std::string folder_error;
  if (!CreateOutputFolder(info.output_dir, &folder_error)) {
    std::cerr << "run: " << folder_error << "\n";
    return 1;
  }
  if (!config.loops.vocabulary.empty()) {
    config.loops.vocabulary = ResolveDatasetPath(config.loops.vocabulary);
  }
  VisualSlam slam(config, &source);
  VisualSlamResult result;
  ProgressBar bar("processing");
  VisualSlamCallbacks callbacks;
  callbacks.progress = [&bar](double fraction) { bar.Update(fraction); };
  callbacks.log = [](const std::string& line) {
    std::printf("run: %s\n", line.c_str());
  };
  std::string error;
  if (!slam.Run(callbacks, &result, &error)) {
    std::cerr << "\nrun: " << error << "\n";
    return 1;
  }
  return WriteVisualRun(info, slam, result);
}

}  // namespace slam
