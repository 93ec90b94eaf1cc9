// slam eval: evaluate an estimated trajectory against a reference.
//
//   slam eval --ref GT --est EST [--format tum|kitti|euroc|g2o|auto]
//             [--ref_format F] [--est_format F] [--ref_times T] [--est_times T]
//             [--associate auto|time|index] [--t_max_diff 0.01] [--t_offset 0]
//             [--unique_pairs]
//             [--align none|se3|sim3|scale|origin] [--n_to_align N]
//             [--rpe_delta 1] [--rpe_unit frames|m|s] [--rpe_all_pairs]
//             [--rpe_pairs_from_reference] [--rpe_delta_tol 0.1] [--kitti]
//             [--plot DIR] [--report FILE.json] [--config FILE] [--dump_config]
//   slam eval GT EST [flags]         (positional form)
//   slam eval --relations FILE --est EST [--relations_t_max_diff 0.001]
//             [--relations_interpolate] [--report FILE.json]
//             (the relation-based error of Kuemmerle et al. 2009; no --ref)
//
// Definitions: core/metrics/ (evo's APE/RPE, the KITTI devkit metric).
// Exit codes: 0 success, 1 evaluation or file error, 2 usage error.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/commands.h"
#include "apps/common_flags.h"
#include "apps/eval_report.h"
#include "apps/format.h"
#include "apps/json.h"
#include "apps/relation_report.h"
#include "apps/yaml_config.h"
#include "core/metrics/evaluation.h"
#include "datasets/atomic_file.h"
#include "datasets/relations_io.h"
#include "datasets/trajectory_io.h"

DEFINE_string(ref, "", "eval: reference (ground-truth) trajectory file");
DEFINE_string(est, "", "eval: estimated trajectory file");
DEFINE_string(format, "auto",
              "eval: trajectory format of both files: auto, tum, kitti, "
              "euroc or g2o (auto: detected from the content)");
DEFINE_string(ref_format, "",
              "eval: format of the reference (overrides --format)");
DEFINE_string(est_format, "",
              "eval: format of the estimate (overrides --format)");
DEFINE_string(
    ref_times, "",
    "eval: KITTI times file (one stamp in s per pose) for the reference");
DEFINE_string(
    est_times, "",
    "eval: KITTI times file (one stamp in s per pose) for the estimate");
DEFINE_string(associate, "auto",
              "eval: auto, time or index (auto: by index when a file has no "
              "stamps, e.g. KITTI poses without times)");
DEFINE_double(t_max_diff, 0.01,
              "eval: max. stamp difference (s) for associating poses (evo's "
              "default 0.01)");
DEFINE_double(t_offset, 0.0, "eval: offset (s) added to the estimate's stamps");
DEFINE_bool(unique_pairs, false,
            "eval: keep timestamp pairs one-to-one (the closest pair of a "
            "pose matched twice); a deviation from evo, which keeps both");
DEFINE_string(
    align, "se3",
    "eval: alignment of the estimate onto the reference: none, se3 "
    "(Umeyama), sim3 (Umeyama with scale), scale, origin (first pose)");
DEFINE_int32(n_to_align, -1,
             "eval: align on the first N matched poses only (-1: all)");
DEFINE_double(rpe_delta, 1.0, "eval: RPE pair distance, in --rpe_unit");
DEFINE_string(rpe_unit, "frames",
              "eval: RPE delta unit: frames, m (path length) or s");
DEFINE_bool(rpe_all_pairs, false,
            "eval: RPE over all pairs with the delta instead of consecutive "
            "pairs");
DEFINE_bool(rpe_pairs_from_reference, false,
            "eval: choose the RPE pairs on the reference (default: on the "
            "estimate, as evo)");
DEFINE_double(rpe_delta_tol, 0.1,
              "eval: relative delta tolerance for --rpe_all_pairs with m or s");
DEFINE_bool(kitti, false,
            "eval: also the KITTI odometry devkit metric (segments of 100..800 "
            "m: t_rel %, r_rel deg/100m)");

DEFINE_string(relations, "",
              "eval: ground-truth relations file ('t1 t2 x y z roll pitch "
              "yaw', e.g. aces.relations): report the relation-based error of "
              "Kuemmerle et al. 2009 of --est instead of APE/RPE");
DEFINE_double(relations_t_max_diff, 0.001,
              "eval: --relations: max. difference (s) between a relation "
              "stamp and the estimate's nearest stamp");
DEFINE_bool(relations_interpolate, false,
            "eval: --relations: interpolate the estimate between its poses "
            "for stamps without a pose within --relations_t_max_diff");

namespace slam {
namespace {

bool FlagSet(const char* name) {
  gflags::CommandLineFlagInfo info;
  return gflags::GetCommandLineFlagInfo(name, &info) && !info.is_default;
}

int Fail(const std::string& message, int code = 1) {
  std::cerr << "slam eval: " << message << "\n";
  return code;
}

bool ParseFormatFlag(const std::string& value, const char* flag,
                     TrajectoryFormat* format, std::string* error) {
  if (ParseTrajectoryFormat(value, format)) return true;
  *error = std::string("--") + flag +
           " must be auto, tum, kitti, euroc or g2o, not '" + value + "'";
  return false;
}

// Settings from --config (eval: section), then explicit flags over them.
bool BuildSettings(EvalSettings* s, bool* associate_auto, std::string* error) {
  *associate_auto = true;
  if (!FLAGS_config.empty()) {
    YAML::Node root;
    if (!LoadYamlFile(FLAGS_config, &root, error)) return false;
    if (!CheckTopLevelSections(root, FLAGS_config, error)) return false;
    if (!root.IsMap() || !root["eval"]) {
      *error = FLAGS_config + ": no 'eval:' section";
      return false;
    }
    if (!ReadEvalSettingsYaml(root["eval"], FLAGS_config + " (eval)", s,
                              associate_auto, error)) {
      return false;
    }
  }
  auto use = [&](const char* name) {
    return FLAGS_config.empty() || FlagSet(name);
  };
  if (use("associate")) {
    if (FLAGS_associate == "auto") {
      *associate_auto = true;
    } else if (FLAGS_associate == "time" || FLAGS_associate == "timestamp") {
      *associate_auto = false;
      s->association = AssociationMethod::kTimestamp;
    } else if (FLAGS_associate == "index") {
      *associate_auto = false;
      s->association = AssociationMethod::kIndex;
    } else {
      *error = "--associate must be auto, time or index, not '" +
               FLAGS_associate + "'";
      return false;
    }
  }
  if (use("t_max_diff")) s->sync.t_max_diff = FLAGS_t_max_diff;
  if (use("t_offset")) s->sync.t_offset = FLAGS_t_offset;
  if (use("unique_pairs")) s->sync.unique_pairs = FLAGS_unique_pairs;
  if (use("align") && !ParseAlignmentMethod(FLAGS_align, &s->align)) {
    *error = "--align must be none, se3, sim3, scale or origin, not '" +
             FLAGS_align + "'";
    return false;
  }
  if (use("n_to_align")) s->n_to_align = FLAGS_n_to_align;
  if (use("rpe_delta")) s->rpe.delta = FLAGS_rpe_delta;
  if (use("rpe_unit") && !ParseDeltaUnit(FLAGS_rpe_unit, &s->rpe.unit)) {
    *error = "--rpe_unit must be frames, m or s, not '" + FLAGS_rpe_unit + "'";
    return false;
  }
  if (use("rpe_all_pairs")) s->rpe.all_pairs = FLAGS_rpe_all_pairs;
  if (use("rpe_pairs_from_reference")) {
    s->rpe.pairs_from_reference = FLAGS_rpe_pairs_from_reference;
  }
  if (use("rpe_delta_tol")) s->rpe.rel_delta_tol = FLAGS_rpe_delta_tol;
  if (use("kitti")) s->kitti = FLAGS_kitti;
  if (use("relations_t_max_diff")) {
    s->relations.t_max_diff = FLAGS_relations_t_max_diff;
  }
  if (use("relations_interpolate")) {
    s->relations.interpolate = FLAGS_relations_interpolate;
  }
  return CheckEvalSettings(*s, error);
}

std::string Describe(const TrajectoryData& d) {
  std::string s = d.path + " (" + TrajectoryFormatName(d.format) + ", " +
                  std::to_string(d.poses.size()) + " poses";
  if (!d.has_stamps) {
    s += ", no stamps";
  } else if (!d.poses.empty()) {
    s += ", " + FormatStampSeconds(d.poses.front().stamp) + " .. " +
         FormatStampSeconds(d.poses.back().stamp) + " s";
  }
  return s + ")";
}

// slam eval --relations FILE --est EST.
int RunRelationEval(const std::string& est_path,
                    const TrajectoryReadOptions& est_options,
                    const EvalSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  std::vector<PoseRelation> relations;
  if (!ReadRelations(FLAGS_relations, &relations, &error)) return Fail(error);
  TrajectoryData est;
  if (!ReadTrajectory(est_path, est_options, &est, &error)) return Fail(error);
  if (!est.has_stamps) {
    return Fail(est.path +
                ": the relation error needs stamps (give KITTI "
                "times with --est_times)");
  }
  std::cout << "relations: " << FLAGS_relations << " (" << relations.size()
            << " relations, " << FormatStampSeconds(relations.front().t1)
            << " .. " << FormatStampSeconds(relations.back().t2) << " s)\n"
            << "estimate:  " << Describe(est) << "\n";
  RelationErrorResult result;
  if (!ComputeRelationError(est.poses, relations, settings.relations, &result,
                            &error)) {
    return Fail(error);
  }
  PrintRelationError(result, settings.relations, std::cout);
  const double ms = std::chrono::duration<double, std::milli>(
                        std::chrono::steady_clock::now() - start)
                        .count();
  std::cout << "time: " << Fmt("%.1f", ms) << " ms\n";
  if (!FLAGS_report.empty()) {
    JsonObject report, relations_json, est_json;
    relations_json.Add("path", FLAGS_relations).Add("count", relations.size());
    est_json.Add("path", est.path)
        .Add("format", TrajectoryFormatName(est.format))
        .Add("poses", est.poses.size());
    report.Add("command", "eval")
        .Add("relations", relations_json)
        .Add("estimate", est_json)
        .Add("relation_error", RelationErrorJson(result, settings.relations));
    if (!WriteFileAtomically(FLAGS_report, report.ToString(0) + "\n", &error)) {
      return Fail(error);
    }
    std::cout << "report: " << FLAGS_report << "\n";
  }
  return 0;
}

}  // namespace

int RunEvalCommand(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string ref_path = FLAGS_ref;
  std::string est_path = FLAGS_est;
  std::vector<std::string> rest = args;
  const bool relations = !FLAGS_relations.empty();
  if (relations && est_path.empty() && !rest.empty()) {
    est_path = rest.front();  // slam eval --relations FILE EST.
    rest.erase(rest.begin());
  }
  if (!relations && ref_path.empty() && !rest.empty()) {
    ref_path = rest.front();
    rest.erase(rest.begin());
  }
  if (est_path.empty() && !rest.empty()) {
    est_path = rest.front();
    rest.erase(rest.begin());
  }
  if (!rest.empty()) {
    return Fail("unexpected argument '" + rest.front() +
                    "' (usage: slam eval --ref GT --est EST [flags])",
                2);
  }

  EvalSettings settings;
  bool associate_auto = true;
  std::string error;
  if (!BuildSettings(&settings, &associate_auto, &error)) return Fail(error, 2);
  if (FLAGS_dump_config) {
    std::cout << "eval:\n" << EvalSettingsYaml(settings, associate_auto, 2);
    return 0;
  }
  if (relations) {
    if (!ref_path.empty()) {
      return Fail(
          "--ref is not used with --relations (the relations are "
          "the ground truth)",
          2);
    }
    if (est_path.empty()) {
      return Fail("give the estimate: slam eval --relations FILE --est EST", 2);
    }
  } else if (ref_path.empty() || est_path.empty()) {
    return Fail(
        "give the reference and the estimate: slam eval --ref GT "
        "--est EST [flags] (slam eval --help lists the flags)",
        2);
  }

  TrajectoryFormat common = TrajectoryFormat::kAuto;
  TrajectoryReadOptions ref_options, est_options;
  if (!ParseFormatFlag(FLAGS_format, "format", &common, &error)) {
    return Fail(error, 2);
  }
  ref_options.format = est_options.format = common;
  if (!FLAGS_ref_format.empty() &&
      !ParseFormatFlag(FLAGS_ref_format, "ref_format", &ref_options.format,
                       &error)) {
    return Fail(error, 2);
  }
  if (!FLAGS_est_format.empty() &&
      !ParseFormatFlag(FLAGS_est_format, "est_format", &est_options.format,
                       &error)) {
    return Fail(error, 2);
  }
  ref_options.kitti_times_path = FLAGS_ref_times;
  est_options.kitti_times_path = FLAGS_est_times;
  // As evo, files with duplicate or unsorted stamps are read (with a
  // warning); the association follows evo's on them.
  for (TrajectoryReadOptions* o : {&ref_options, &est_options}) {
    // Not for the relation error, which needs increasing stamps.
    o->allow_duplicate_stamps = o->allow_unsorted_stamps = !relations;
  }
  if (relations) return RunRelationEval(est_path, est_options, settings);

  TrajectoryData ref, est;
  if (!ReadTrajectory(ref_path, ref_options, &ref, &error)) return Fail(error);
  if (!ReadTrajectory(est_path, est_options, &est, &error)) return Fail(error);
  const EvalTrajectory ref_eval = ToEvalTrajectory(ref);
  const EvalTrajectory est_eval = ToEvalTrajectory(est);
  const auto loaded = std::chrono::steady_clock::now();
  std::cout << "reference: " << Describe(ref) << "\n"
            << "estimate:  " << Describe(est) << "\n";
  for (TrajectoryData* d : {&ref, &est}) {
    if (!d->warning.empty())
      std::cerr << "slam eval: warning: " << d->warning << "\n";
    // The evaluation works on the copies above; giving this memory back
    // lets it reuse the pages instead of faulting in new ones (a third of
    // the time of a million-pose evaluation).
    d->poses = Trajectory();
    d->seconds = std::vector<double>();
    d->matrices = std::vector<Eigen::Matrix3d>();
  }
  if (associate_auto) {
    settings.association = ChooseAssociation(ref.has_stamps, est.has_stamps);
  } else if (settings.association == AssociationMethod::kTimestamp &&
             (!ref.has_stamps || !est.has_stamps)) {
    return Fail(
        "--associate time needs stamps in both files (give KITTI "
        "times with --ref_times / --est_times)",
        2);
  }

  EvalLabels labels;
  labels.ref_name = std::filesystem::path(ref.path).filename().string();
  labels.est_name = std::filesystem::path(est.path).filename().string();
  EvalResult result;
  if (!EvaluateAndReport(ref_eval, est_eval, settings, labels, FLAGS_plot,
                         std::cout, &result, &error)) {
    return Fail(error);
  }
  const auto done = std::chrono::steady_clock::now();
  const double load_ms =
      std::chrono::duration<double, std::milli>(loaded - start).count();
  const double eval_ms =
      std::chrono::duration<double, std::milli>(done - loaded).count();
  char buf[128];
  std::snprintf(buf, sizeof(buf),
                "time: reading %.1f ms, evaluation%s %.1f ms\n", load_ms,
                FLAGS_plot.empty() ? "" : " and plots", eval_ms);
  std::cout << buf;

  if (!FLAGS_report.empty()) {
    JsonObject report;
    JsonObject ref_json, est_json;
    ref_json.Add("path", ref.path)
        .Add("format", TrajectoryFormatName(ref.format))
        .Add("poses", ref_eval.size())
        .Add("has_stamps", ref.has_stamps);
    est_json.Add("path", est.path)
        .Add("format", TrajectoryFormatName(est.format))
        .Add("poses", est_eval.size())
        .Add("has_stamps", est.has_stamps);
    report.Add("command", "eval")
        .Add("reference", ref_json)
        .Add("estimate", est_json)
        .Add("settings", EvalSettingsJson(settings));
    JsonObject timing;
    timing.Add("read_ms", load_ms).Add("evaluate_ms", eval_ms);
    report.Add("timing", timing);
    AddEvalResultJson(result, settings, &report);
    const std::string text = report.ToString(0) + "\n";
    if (!WriteFileAtomically(FLAGS_report, text, &error)) return Fail(error);
    std::cout << "report: " << FLAGS_report << "\n";
  }
  return 0;
}

}  // namespace slam
