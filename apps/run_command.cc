// slam run: 2D laser SLAM on a CARMEN log (frontends/laser/laser_slam.h).
//
//   slam run --config configs/aces.yaml [--datasets DIR] [--output_dir DIR]
//
// The log (and the optional relations file) are named relative to the
// datasets directory: --datasets, else $SLAM_DATASETS, else
// ../shared/datasets beside the repository holding the config file (the
// config's directory's parent), else ../shared/datasets from the working
// directory. Absolute paths are used as they are.
//
// Outputs in output_dir: trajectory.tum (every scan's robot pose, TUM),
// graph.g2o (the keyframe pose graph), and the occupancy-grid map when
// enabled. Progress bars while reading and processing; a summary at the end.
#include <gflags/gflags.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <unistd.h>

#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/map_png.h"
#include "apps/progress_bar.h"
#include "apps/run_config.h"
#include "datasets/atomic_file.h"
#include "datasets/carmen_io.h"
#include "datasets/g2o_io.h"
#include "datasets/relations_io.h"
#include "datasets/trajectory_io.h"
#include "frontends/laser/laser_map.h"
#include "frontends/laser/laser_slam.h"
#include "frontends/laser/occupancy_grid.h"

DEFINE_string(datasets, "",
              "run: datasets directory the log path is relative to (default "
              "$SLAM_DATASETS, else ../shared/datasets beside the repository)");
DEFINE_string(output_dir, "", "run: output directory (overrides the config)");

namespace slam {
namespace {

namespace fs = std::filesystem;

// The scan trajectory as trajectory.tum and the relation evaluation want it:
// sorted by stamp (stable: log order among equal stamps), one pose per
// stamp (the first scan of the log with it). *duplicates: poses dropped.
Trajectory SortedByStamp(Trajectory trajectory, int64_t* duplicates) {
  std::stable_sort(trajectory.begin(), trajectory.end(),
                   [](const StampedPose& a, const StampedPose& b) {
                     return a.stamp < b.stamp;
                   });
  const size_t before = trajectory.size();
  trajectory.erase(std::unique(trajectory.begin(), trajectory.end(),
                               [](const StampedPose& a, const StampedPose& b) {
                                 return a.stamp == b.stamp;
                               }),
                   trajectory.end());
  *duplicates = static_cast<int64_t>(before - trajectory.size());
  return trajectory;
}

// Relations that can match a scan: both stamps within the log's scan
// stamps. None: a relations file of another log.
bool CheckRelationsMatchLog(const std::string& path,
                            const std::vector<PoseRelation>& relations,
                            const CarmenLog& log, std::string* error) {
  TimeNs first = log.scans.front().stamp, last = first;
  for (const LaserScan& scan : log.scans) {
    first = std::min(first, scan.stamp);
    last = std::max(last, scan.stamp);
  }
  for (const PoseRelation& r : relations) {
    if (std::min(r.t1, r.t2) >= first && std::max(r.t1, r.t2) <= last) {
      return true;
    }
  }
  *error = path + ": none of the " + std::to_string(relations.size()) +
           " relations lies within the scan stamps of the log (" +
           FormatStampSeconds(first) + " .. " + FormatStampSeconds(last) +
           " s): the relations of another log?";
  return false;
}

double Since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

// The occupancy grid from the keyframe scans at their optimized poses:
// map.pgm + map.yaml (map_server, full resolution) and map.png with the
// trajectory (at most kMapPngMaxSide pixels on a side: cells merged).
bool WriteMap(const RunConfig& config, const LaserSlam& slam,
              const CarmenLog& log, std::string* summary, std::string* error) {
  OccupancyGrid grid(config.map);
  InsertKeyframeScans(slam, log.scans, &grid);
  const fs::path dir(config.output_dir);
  std::vector<Eigen::Vector2d> path;
  for (const StampedPose& p : slam.ScanTrajectory()) {
    path.push_back(p.pose.t.head<2>());
  }
  const MapImage picture = grid.ToImage(kMapPngMaxSide);
  if (!WriteMapPgmYaml((dir / "map.pgm").string(), (dir / "map.yaml").string(),
                       grid, error) ||
      !WriteMapPng((dir / "map.png").string(), picture, path, error)) {
    return false;
  }
  const MapSharpness sharpness = MeasureSharpness(grid);
  int64_t cols = 0, rows = 0;
  grid.ObservedExtent(&cols, &rows);
  const int64_t merged = std::max<int64_t>(
      1, std::llround(picture.resolution / config.map.resolution));
  char text[384];
  std::snprintf(text, sizeof(text),
                "map %lld x %lld cells at %.3f m (%.0f MB of tiles; picture "
                "%d x %d, %lld x %lld cells a pixel): %zu observed, %zu "
                "occupied, %zu mixed-evidence (%.1f%% of mixed + occupied: "
                "lower is sharper), wrote map.pgm, map.yaml, map.png",
                static_cast<long long>(cols), static_cast<long long>(rows),
                config.map.resolution, grid.allocated_cells() * 8.0 / 1e6,
                picture.width, picture.height, static_cast<long long>(merged),
                static_cast<long long>(merged), sharpness.observed,
                sharpness.occupied, sharpness.mixed,
                100.0 * sharpness.MixedFraction());
  *summary = text;
  return true;
}

}  // namespace

std::string ResolveDatasetPath(const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute()) return path;
  std::vector<std::string> dirs;
  if (!FLAGS_datasets.empty()) {
    dirs.push_back(FLAGS_datasets);
  } else {
    if (const char* env = std::getenv("SLAM_DATASETS")) dirs.push_back(env);
    if (!FLAGS_config.empty()) {
      dirs.push_back((fs::absolute(FLAGS_config).parent_path().parent_path() /
                      ".." / "shared" / "datasets")
                         .string());
    }
    dirs.push_back("../shared/datasets");
  }
  for (const std::string& dir : dirs) {
    const fs::path candidate = fs::path(dir) / path;
    if (fs::exists(candidate)) return candidate.string();
  }
  return (fs::path(dirs.front()) / path).string();
}

int RunRunCommand(const std::vector<std::string>& args) {
  if (!args.empty()) {
    std::cerr << "run: unexpected argument '" << args[0] << "'\n";
    return 2;
  }
  RunConfig config;
  std::string error;
  if (!FLAGS_config.empty() && !LoadRunConfig(FLAGS_config, &config, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  if (!FLAGS_output_dir.empty()) config.output_dir = FLAGS_output_dir;
  if (FLAGS_dump_config) {
    std::cout << RunConfigToYaml(config);
    return 0;
  }
  if (config.pipeline != "laser") {
    std::cerr << FLAGS_config << ": run.pipeline '" << config.pipeline
              << "' is not the laser pipeline (laser, stereo, rgbd)\n";
    return 2;
  }
  if (config.log.empty()) {
    std::cerr << "run: no log named (run.log in --config)\n";
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  const std::string log_path = ResolveDatasetPath(config.log);
  CarmenLog log;
  {
    ProgressBar bar("reading");
    if (!ReadCarmenLog(log_path, config.lasers, &log, &error,
                       [&bar](double f) { bar.Update(f); })) {
      std::cerr << "\n" << error << "\n";
      return 1;
    }
    bar.Done();
  }
  for (const std::string& w : log.warnings)
    std::cerr << "warning: " << w << "\n";
  if (log.scans.empty()) {
    std::cerr << log_path << ": no laser scans of the selected lasers\n";
    return 1;
  }
  std::vector<PoseRelation> relations;
  if (!config.relations.empty()) {
    const std::string path = ResolveDatasetPath(config.relations);
    if (!ReadRelations(path, &relations, &error) ||
        !CheckRelationsMatchLog(path, relations, log, &error)) {
      std::cerr << error << "\n";
      return 1;
    }
  }
  // Fail before the work on an output folder that cannot be made.
  // Removed again if the run fails (datasets/atomic_file.h).
  if (!CreateOutputFolder(config.output_dir, &error)) {
    std::cerr << error << "\n";
    return 1;
  }
  const double read_seconds = Since(start);

  const auto slam_start = std::chrono::steady_clock::now();
  LaserSlam slam(config.slam);
  {
    ProgressBar bar("processing");
    for (size_t i = 0; i < log.scans.size(); ++i) {
      slam.AddScan(log.scans[i]);
      bar.Update(static_cast<double>(i + 1) / log.scans.size());
    }
  }
  slam.Finish();
  const double slam_seconds = Since(slam_start);

  const std::string trajectory_path =
      (fs::path(config.output_dir) / "trajectory.tum").string();
  const std::string graph_path =
      (fs::path(config.output_dir) / "graph.g2o").string();
  // Logs whose stamps go backwards are processed in log order; the
  // trajectory file is sorted by stamp so that `slam eval` can use it.
  int64_t duplicate_stamps = 0;
  const Trajectory trajectory =
      SortedByStamp(slam.ScanTrajectory(), &duplicate_stamps);
  if (!WriteTrajectory(trajectory_path, trajectory, TrajectoryFormat::kTum,
                       &error) ||
      !WriteG2o(graph_path, slam.graph(), &error)) {
    std::cerr << error << "\n";
    return 1;
  }

  std::string map_summary;
  if (config.write_map) {
    const auto map_start = std::chrono::steady_clock::now();
    if (!WriteMap(config, slam, log, &map_summary, &error)) {
      std::cerr << error << "\n";
      return 1;
    }
    char seconds[32];
    std::snprintf(seconds, sizeof(seconds), " (%.2f s)", Since(map_start));
    map_summary += seconds;
  }

  const LaserSlamStats& s = slam.stats();
  // One line, "N keyframes ... loop closures: N proposed, N accepted, N
  // rejected" as scripts/benchmark_laser.py reads it; proposed = searched
  // (verified by matching), all passes together.
  std::printf(
      "run: %d scans, %d keyframes; loop closures: %d proposed, %d accepted, "
      "%d rejected (searched %d local, %d global, %d final pass; accepted %d "
      "global, %d final pass; %d undone by the chi2 test; largest "
      "correction %.3f m, %.2f deg); "
      "tracking: %d correlative, %d rechecked from constant velocity, %d "
      "odometry only (%d of them slides off the odometry), odometry "
      "rejected on %d scans (keyframe odometry "
      "factors %d dropped, %d down-weighted); %d optimizations; %d scans "
      "refined\n",
      s.scans, s.keyframes, s.closures_proposed + s.final_closures_proposed,
      s.closures_accepted + s.final_closures_accepted, s.closures_rejected,
      s.closures_proposed - s.global_closures_proposed,
      s.global_closures_proposed, s.final_closures_proposed,
      s.global_closures_accepted, s.final_closures_accepted,
      s.closures_reverted, s.largest_correction_m, s.largest_correction_deg,
      s.tracking_correlative, s.tracking_rechecks, s.tracking_failures,
      s.tracking_slides_rejected, s.odometry_rejected,
      s.odometry_factors_dropped, s.odometry_factors_weakened, s.optimizations,
      s.scans_refined);
  std::printf(
      "run: time %.2f s (read %.2f s, slam %.2f s: matching %.2f, loops %.2f, "
      "optimization %.2f, refinement %.2f)\n",
      Since(start), read_seconds, slam_seconds, s.matching_seconds,
      s.loop_seconds, s.optimization_seconds, s.refine_seconds);
  std::printf(
      "run: loop search %.2f s: submap targets %.2f, correlative %.2f, ICP "
      "%.2f, chi2 tests %.2f, final pass %.2f; %d local candidates verified "
      "from a recent closure; global searches %.2g look-ups each (mean), "
      "%d of %d stopped by the probe, %d by the work bound; all searches "
      "%.2g look-ups each (mean), %d of %d stopped by a failed "
      "verification\n",
      s.loop_seconds, s.loop_target_seconds, s.loop_correlative_seconds,
      s.loop_icp_seconds, s.loop_chi2_seconds, s.loop_final_seconds,
      s.seeded_verifications,
      s.global_search_evaluations / std::max(1, s.global_closures_proposed),
      s.global_searches_probe_stopped, s.global_closures_proposed,
      s.global_searches_budget_stopped,
      s.loop_search_evaluations / std::max(1, s.loop_searches),
      s.loop_searches_verify_stopped, s.loop_searches);
  std::printf("run: wrote %s, %s\n", trajectory_path.c_str(),
              graph_path.c_str());
  if (log.scans_out_of_order > 0 || duplicate_stamps > 0) {
    std::printf(
        "run: %lld of %zu scans have a stamp not after the previous one in "
        "the log (processed in log order); trajectory.tum is sorted by stamp, "
        "%lld scan(s) with a stamp already taken dropped from it (the first "
        "scan in the log with each stamp kept)\n",
        static_cast<long long>(log.scans_out_of_order), log.scans.size(),
        static_cast<long long>(duplicate_stamps));
  }
  if (!map_summary.empty()) std::printf("run: %s\n", map_summary.c_str());
  if (!relations.empty()) {
    RelationErrorResult r;
    if (!ComputeRelationError(trajectory, relations, RelationErrorOptions(), &r,
                              &error)) {
      std::cerr << error << "\n";
      return 1;
    }
    std::printf(
        "run: relation error (%zu of %zu relations): translation %.4f +- "
        "%.4f m (squared %.5f +- %.5f m^2), rotation %.3f +- %.3f deg "
        "(squared %.3f +- %.3f deg^2)\n",
        r.used.size(), r.relations, r.translation_abs.mean,
        r.translation_abs.std, r.translation_sq.mean, r.translation_sq.std,
        r.rotation_abs.mean, r.rotation_abs.std, r.rotation_sq.mean,
        r.rotation_sq.std);
  }
  return 0;
}

}  // namespace slam
