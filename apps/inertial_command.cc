// slam inertial: IMU + position-fix estimation with the sliding window
// (fixed-lag smoother) and/or the global batch
// (frontends/inertial/inertial_estimator.h):
//
//   slam inertial -i INPUT -o DIR [--config FILE] [--estimator both]
//                 [--window_size 10] [--keyframe_rate 10] [--gt FILE|input]
//                 [--report FILE.json] [--plot DIR] [--dead_reckoning]
//
// INPUT: an EuRoC-format folder (holding mav0/imu0/data.csv, optional
// leica0 fixes and state_groundtruth_estimate0) or a GTSAM IMU+GPS CSV
// (datasets/imu_io.h). Outputs in DIR (written only when everything
// succeeded):
//   window.tum / batch.tum              trajectory "t x y z qx qy qz qw"
//                                       (window: each keyframe's fixed-lag
//                                       estimate, when it left the window)
//   window_filter.tum                   the newest state right after its
//                                       update (real-time estimate)
//   window_states.csv / batch_states.csv / window_filter_states.csv
//       "#timestamp [ns],vx,vy,vz,bgx,bgy,bgz,bax,bay,baz" (world velocity,
//       gyro then accel bias)
//   covariance_window_filter.csv        the newest state's 15 x 15 marginal
//                                       covariance after its update (format:
//                                       apps/inertial_consistency_report.h)
//   covariance_window.csv               the same for window.tum: each
//                                       keyframe's covariance when it left
//                                       the window
// --gt FILE evaluates each estimate against a reference trajectory (any
// format of `slam eval`), --gt input against the input's ground truth; with
// --gt input the window's estimates (real-time and fixed-lag) are also
// checked for consistency: NEES of position, pose, velocity and bias after
// the first 10 s (frontends/inertial/inertial_consistency.h), raw and after a
// yaw-only alignment of the reference rotation, in the report under
// evaluation.window_filter.nees and evaluation.window.nees.
// Without an initial state in the input the initializer
// (frontends/inertial/inertial_initializer.h) starts both estimators and
// prints when the yaw became observable (report: "initialization").
// Input without position fixes is refused (exit 1) unless
// --dead_reckoning; fix-free stretches over 10 s and IMU gaps are warned
// about on stderr and listed in the report.
// Settings: defaults < --config FILE (`inertial:` section, see
// apps/inertial_config.h) < explicit flags; --dump_config prints them.
#include <gflags/gflags.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/inertial_config.h"
#include "apps/inertial_consistency_report.h"
#include "apps/json.h"
#include "apps/yaml_config.h"
#include "core/sliding_window.h"
#include "datasets/atomic_file.h"
#include "datasets/imu_io.h"
#include "datasets/trajectory_io.h"
#include "frontends/inertial/inertial_estimator.h"
#include "frontends/inertial/inertial_initializer.h"

DECLARE_string(i);
DECLARE_string(o);

DEFINE_string(estimator, "both", "inertial: window | batch | both");
DEFINE_int32(window_size, 10, "inertial: keyframes in the sliding window");
DEFINE_double(keyframe_rate, 10.0, "inertial: keyframe rate [Hz]");
DEFINE_bool(dead_reckoning, false,
            "inertial: run on input without position fixes (IMU alone: "
            "position and heading drift without bound); without it such "
            "input is refused");

namespace slam {
namespace {

bool FlagGiven(const char* name) {
  return !gflags::GetCommandLineFlagInfoOrDie(name).is_default;
}

bool BuildConfig(InertialConfig* config, std::string* error) {
  if (!FLAGS_config.empty() &&
      !LoadInertialConfig(FLAGS_config, config, error)) {
    return false;
  }
  if (FlagGiven("estimator")) config->estimator = FLAGS_estimator;
  if (FlagGiven("window_size")) {
    config->options.window.window_size = FLAGS_window_size;
  }
  if (FlagGiven("keyframe_rate")) {
    config->options.keyframe_rate_hz = FLAGS_keyframe_rate;
  }
  if (!ValidateInertialConfig(*config, error)) {
    *error = "inertial." + *error;
    return false;
  }
  return true;
}

bool ReadInput(const InertialConfig& config, InertialData* data,
               std::string* error) {
  std::string format = config.input_format;
  if (format == "auto") {
    format = std::filesystem::is_directory(FLAGS_i) ? "euroc" : "gtsam";
  }
  if (format == "euroc") return ReadEurocInertial(FLAGS_i, data, error);
  return ReadGtsamImuCsv(FLAGS_i, kGtsamImuDt, data, error);
}

// Prints the initializer's summary (stdout) and, when the heading never
// became observable, a warning (stderr); the report's "initialization".
JsonObject InitializationJson(const InertialRun& run,
                              const std::vector<std::string>& warnings,
                              bool dead_reckoning) {
  JsonObject json;
  json.Add("yaw_observable", run.yaw_observable)
      .Add("yaw_observable_after_s", run.yaw_observable_after_seconds)
      .Add("filter_keyframes_yaw_unknown", run.filter_yaw_unknown)
      .Add("dead_reckoning", dead_reckoning)
      .Add("summary", run.initialization_summary);
  std::string list = "[";
  for (size_t i = 0; i < warnings.size(); ++i) {
    list += (i > 0 ? ", " : "") + JsonQuote(warnings[i]);
  }
  json.AddRaw("warnings", list + "]");
  return json;
}

void PrintInitialization(const InertialRun& run) {
  if (!run.initialization_summary.empty()) {
    std::printf("%s\n", run.initialization_summary.c_str());
  }
  if (!run.yaw_observable) {
    std::fflush(stdout);
    std::cerr << "slam inertial: warning: the heading (yaw) never became "
                 "observable (no horizontal acceleration seen with the "
                 "fixes): every estimate's yaw is arbitrary\n";
  } else if (run.filter_yaw_unknown > 0) {
    std::printf(
        "window_filter: the first %zu real-time estimates (%.2f s) have no "
        "yaw information (heading arbitrary); then %s\n",
        run.filter_yaw_unknown, run.yaw_observable_after_seconds,
        run.yaw_from_window ? "the window's own estimate knows it"
                            : "the window restarts from the aligned state");
  }
}

struct Estimate {
  std::string name;  // "window", "window_filter", "batch"
  Trajectory trajectory;
  // The states and their covariances (NEES), or nullptr (batch).
  const std::vector<InertialState>* states = nullptr;
  const std::vector<Eigen::MatrixXd>* covariances = nullptr;
};

}  // namespace

int RunInertialCommand(const std::vector<std::string>& args) {
  std::string error;
  InertialConfig config;
  if (!BuildConfig(&config, &error)) {
    std::cerr << "slam inertial: " << error << "\n";
    return 1;
  }
  if (FLAGS_dump_config) {
    std::cout << InertialConfigToYaml(config);
    return 0;
  }
  if (FLAGS_i.empty() || FLAGS_o.empty() || !args.empty()) {
    std::cerr << "usage: slam inertial -i INPUT -o DIR [--config FILE] "
                 "[--gt FILE|input] [--dead_reckoning]\n";
    return 2;
  }
  InertialData data;
  if (!ReadInput(config, &data, &error)) {
    std::cerr << "slam inertial: " << error << "\n";
    return 1;
  }
  if (config.gravity_auto) config.options.gravity = data.gravity;
  // The densities the estimators use: data sheet x inflation.
  InertialOptions options = EffectiveInertialOptions(config);
  if (config.initial_state == "ground_truth" &&
      !StartAtGroundTruth(&data, &options.initial_bias, &error)) {
    std::cerr << "slam inertial: " << FLAGS_i << ": " << error << "\n";
    return 1;
  }
  TrajectoryData gt;
  const bool evaluate = !FLAGS_gt.empty();
  if (FLAGS_gt == "input") {
    if (data.ground_truth.empty()) {
      std::cerr << "slam inertial: --gt input: " << FLAGS_i
                << " has no ground truth\n";
      return 1;
    }
    for (const InertialGroundTruth& g : data.ground_truth) {
      gt.poses.push_back({g.stamp, g.pose});
    }
  } else if (evaluate && !ReadTrajectory(FLAGS_gt, {}, &gt, &error)) {
    std::cerr << "slam inertial: " << error << "\n";
    return 1;
  }
  std::printf(
      "input %s: %zu IMU readings, %zu position fixes, gravity "
      "(%g, %g, %g), %s initial state\n",
      FLAGS_i.c_str(), data.imu.size(), data.positions.size(),
      options.gravity.x(), options.gravity.y(), options.gravity.z(),
      data.has_initial_state ? "with" : "without");
  std::printf(
      "noise: gyro %g rad/s/sqrt(Hz) (%g x %g), accel %g m/s^2/sqrt(Hz) (%g x "
      "%g), random walks %g rad/s^2/sqrt(Hz), %g m/s^3/sqrt(Hz)\n",
      options.noise.gyro_noise_density, config.options.noise.gyro_noise_density,
      config.gyro_noise_inflation, options.noise.accel_noise_density,
      config.options.noise.accel_noise_density, config.accel_noise_inflation,
      options.noise.gyro_random_walk, options.noise.accel_random_walk);

  // What the data cannot determine (inertial_initializer.h).
  if (data.positions.empty() && !FLAGS_dead_reckoning) {
    std::cerr << "slam inertial: " << FLAGS_i
              << ": no position fixes: the IMU alone cannot determine the "
                 "position or the heading, and its dead reckoning drifts "
                 "without bound (kilometres within a minute for a MEMS IMU); "
                 "add fixes, or pass --dead_reckoning to run anyway\n";
    return 1;
  }
  const std::vector<std::string> warnings = InertialDataWarnings(data);
  if (data.positions.empty()) {
    std::cerr << "slam inertial: warning: dead reckoning (no position "
                 "fixes): the estimates drift without bound\n";
  }
  for (const std::string& w : warnings) {
    std::cerr << "slam inertial: warning: " << w << "\n";
  }
  const bool run_window = config.estimator != "batch";
  const bool run_batch = config.estimator != "window";
  InertialRun window, batch;
  std::vector<Estimate> estimates;
  std::vector<std::pair<std::string, std::string>> files;  // name, contents
  JsonObject report;
  report.Add("input", FLAGS_i).Add("estimator", config.estimator);
  JsonObject noise;  // As used: data sheet densities x inflation.
  noise.Add("gyro_noise_density", options.noise.gyro_noise_density)
      .Add("accel_noise_density", options.noise.accel_noise_density)
      .Add("gyro_random_walk", options.noise.gyro_random_walk)
      .Add("accel_random_walk", options.noise.accel_random_walk)
      .Add("gyro_noise_inflation", config.gyro_noise_inflation)
      .Add("accel_noise_inflation", config.accel_noise_inflation)
      .Add("position_sigma", options.position_sigma);
  report.Add("noise", noise);
  if (run_window) {
    // The newest state's marginal after every update (covariance CSV, NEES);
    // not part of the timed update.
    options.newest_covariance = true;
    options.smoothed_covariance = true;
    if (!RunSlidingWindow(data, options, &window, &std::cout, &error)) {
      std::cerr << "slam inertial: " << FLAGS_i << ": " << error << "\n";
      return 1;
    }
    PrintInitialization(window);
    estimates.push_back({"window", ToTrajectory(window.smoothed),
                         &window.smoothed, &window.smoothed_covariance});
    estimates.push_back({"window_filter", ToTrajectory(window.filter),
                         &window.filter, &window.newest_covariance});
    files.emplace_back("window_states.csv", StatesCsv(window.smoothed));
    files.emplace_back("window_filter_states.csv", StatesCsv(window.filter));
    files.emplace_back("covariance_window_filter.csv",
                       CovarianceCsv(window.filter, window.newest_covariance));
    files.emplace_back(
        "covariance_window.csv",
        CovarianceCsv(window.smoothed, window.smoothed_covariance));
    const TimingSummary t = SummarizeTimes(window.update_seconds);
    JsonObject timing;
    timing.Add("updates", t.count)
        .Add("median_ms", 1e3 * t.median)
        .Add("p99_ms", 1e3 * t.p99)
        .Add("max_ms", 1e3 * t.max)
        .Add("total_s", window.total_seconds)
        .Add("window_size", config.options.window.window_size);
    report.Add("window", timing);
  }
  if (run_batch) {
    if (!RunBatch(data, options,
                  run_window ? window.smoothed : std::vector<InertialState>(),
                  &batch, &std::cout, &error)) {
      std::cerr << "slam inertial: " << FLAGS_i << ": " << error << "\n";
      return 1;
    }
    if (!run_window) PrintInitialization(batch);
    estimates.push_back({"batch", ToTrajectory(batch.smoothed)});
    files.emplace_back("batch_states.csv", StatesCsv(batch.smoothed));
    JsonObject timing;
    timing.Add("keyframes", batch.smoothed.size())
        .Add("total_s", batch.total_seconds);
    report.Add("batch", timing);
  }

  report.Add("initialization",
             InitializationJson(run_window ? window : batch, warnings,
                                data.positions.empty()));

  if (evaluate) {
    EvalSettings settings;
    if (!LoadEvalSectionOfConfig(FLAGS_config, &settings, &error)) {
      std::cerr << "slam inertial: " << error << "\n";
      return 1;
    }
    settings.association = ChooseAssociation(gt.has_stamps, true);
    JsonObject evaluation;
    for (const Estimate& e : estimates) {
      EvalLabels labels;
      labels.ref_name = "ground truth";
      labels.est_name = e.name;
      EvalResult result;
      std::printf("\nevaluation of %s against %s:\n", e.name.c_str(),
                  FLAGS_gt.c_str());
      const std::string plot_dir =
          FLAGS_plot.empty() ? "" : FLAGS_plot + "/" + e.name;
      if (!EvaluateAndReport(gt.poses, e.trajectory, settings, labels, plot_dir,
                             std::cout, &result, &error)) {
        std::cerr << "slam inertial: evaluation of " << e.name << ": " << error
                  << "\n";
        return 1;
      }
      JsonObject json = EvalResultJson(result, settings);
      if (e.covariances != nullptr && FLAGS_gt == "input") {
        JsonObject nees;
        const InertialRun& run = run_window ? window : batch;
        if (!EvaluateNees(
                e.name, *e.states, *e.covariances, data.ground_truth,
                NeesOptions(),
                run.yaw_observable ? run.yaw_observable_after_seconds : -1.0,
                std::cout, &nees, &error)) {
          std::cerr << "slam inertial: " << error << "\n";
          return 1;
        }
        json.Add("nees", nees);
      }
      evaluation.Add(e.name, json);
    }
    report.Add("evaluation", evaluation);
  }

  if (!CreateOutputFolder(FLAGS_o, &error)) {
    std::cerr << "slam inertial: " << error << "\n";
    return 1;
  }
  for (const Estimate& e : estimates) {
    if (!WriteTrajectory(FLAGS_o + "/" + e.name + ".tum", e.trajectory,
                         TrajectoryFormat::kTum, &error)) {
      std::cerr << "slam inertial: " << error << "\n";
      return 1;
    }
  }
  for (const auto& [name, contents] : files) {
    if (!WriteFileAtomically(FLAGS_o + "/" + name, contents, &error)) {
      std::cerr << "slam inertial: " << error << "\n";
      return 1;
    }
  }
  if (!FLAGS_report.empty() &&
      !WriteFileAtomically(FLAGS_report, report.ToString() + "\n", &error)) {
    std::cerr << "slam inertial: " << error << "\n";
    return 1;
  }
  // Summary line.
  std::printf("\ninertial: %s", FLAGS_i.c_str());
  if (run_window) {
    const TimingSummary t = SummarizeTimes(window.update_seconds);
    std::printf(
        ", window %zu keyframes (size %d): update median %.2f ms, p99 "
        "%.2f ms",
        window.smoothed.size(), config.options.window.window_size,
        1e3 * t.median, 1e3 * t.p99);
  }
  if (run_batch) std::printf(", batch %.3f s", batch.total_seconds);
  std::printf("; wrote %s\n", FLAGS_o.c_str());
  return 0;
}

}  // namespace slam
