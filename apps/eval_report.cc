#include "apps/eval_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "apps/format.h"
#include "apps/plot_module.h"

namespace slam {
namespace {

std::string AlignmentDescription(const EvalSettings& s, size_t pairs) {
  const size_t used = s.n_to_align > 0
                          ? std::min(pairs, static_cast<size_t>(s.n_to_align))
                          : pairs;
  const std::string on = s.n_to_align > 0
                             ? " on the first " + std::to_string(used) +
                                   " of " + std::to_string(pairs) + " pairs"
                             : " on all " + std::to_string(pairs) + " pairs";
  switch (s.align) {
    case AlignmentMethod::kNone:
      return "none (estimate used as is)";
    case AlignmentMethod::kSE3:
      return "SE(3) Umeyama" + on;
    case AlignmentMethod::kSim3:
      return "Sim(3) Umeyama" + on;
    case AlignmentMethod::kScale:
      return "scale only (Umeyama)" + on;
    case AlignmentMethod::kOrigin:
      return "origin (first estimate pose onto the first reference pose)";
  }
  return "?";
}

void PrintStatsRow(std::ostream& out, const char* name,
                   const ErrorStatistics& s) {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "%-21s %11.6f %11.6f %11.6f %11.6f %11.6f %11.6f %14.6f %7zu\n",
                name, s.rmse, s.mean, s.median, s.std, s.min, s.max, s.sse,
                s.count);
  out << buf;
}

}  // namespace

AssociationMethod ChooseAssociation(bool ref_has_stamps, bool est_has_stamps) {
  return ref_has_stamps && est_has_stamps ? AssociationMethod::kTimestamp
                                          : AssociationMethod::kIndex;
}

void PrintAssociationAndAlignment(const EvalResult& r, const EvalSettings& s,
                                  std::ostream& out) {
  const Association& a = r.association;
  if (a.by_index) {
    out << "association: by index, " << a.size() << " pairs\n";
  } else {
    out << "association: by timestamp (t_max_diff "
        << Fmt("%g", s.sync.t_max_diff) << " s, t_offset "
        << Fmt("%g", s.sync.t_offset) << " s): " << a.size() << " of max. "
        << a.max_pairs << " possible pairs, largest |dt| "
        << Fmt("%.6f", a.max_abs_dt) << " s\n";
    if (a.dropped_duplicates > 0) {
      out << "  note: " << a.dropped_duplicates
          << " pair(s) dropped to keep the association one-to-one "
             "(--unique_pairs; evo keeps them)\n";
    }
    if (a.reused_poses > 0) {
      out << "  note: " << a.reused_poses
          << " pair(s) reuse a pose of the longer trajectory already paired "
             "(as evo; t_max_diff is at least half its sampling interval; "
             "--unique_pairs keeps the closest pair only)\n";
    }
  }
  out << "alignment: " << AlignmentDescription(s, a.size()) << "\n";
  if (s.align != AlignmentMethod::kNone) {
    const Similarity3& t = r.alignment;
    char buf[160];
    for (int i = 0; i < 3; ++i) {
      std::snprintf(buf, sizeof(buf),
                    "  %s [%11.8f %11.8f %11.8f]   %s%12.6f\n",
                    i == 0 ? "rotation" : "        ", t.rotation(i, 0),
                    t.rotation(i, 1), t.rotation(i, 2),
                    i == 0 ? "translation " : "            ", t.translation[i]);
      out << buf;
    }
    std::snprintf(buf, sizeof(buf), "  scale %.9f\n", t.scale);
    out << buf;
  }
}

void PrintEvalTable(const EvalResult& r, const EvalSettings& s,
                    std::ostream& out) {
  char buf[256];
  std::snprintf(buf, sizeof(buf),
                "%-21s %11s %11s %11s %11s %11s %11s %14s %7s\n", "", "rmse",
                "mean", "median", "std", "min", "max", "sse", "count");
  out << buf;
  PrintStatsRow(out, "APE translation [m]", r.ape_translation_stats);
  PrintStatsRow(out, "APE rotation [deg]", r.ape_rotation_stats);
  PrintStatsRow(out, "RPE translation [m]", r.rpe_translation_stats);
  PrintStatsRow(out, "RPE rotation [deg]", r.rpe_rotation_stats);
  out << "RPE: " << DescribeRpeOptions(s.rpe) << "\n";
  std::snprintf(buf, sizeof(buf),
                "path length: reference %.3f m, estimate (aligned) %.3f m\n",
                r.ref_path_length, r.est_path_length);
  out << buf;
  if (r.has_kitti) {
    const KittiMetric& k = r.kitti;
    if (k.num_segments == 0) {
      out << "KITTI metric: no segment of 100 m or more along the reference "
             "(path "
          << Fmt("%.1f", r.ref_path_length) << " m): not defined\n";
    } else {
      std::snprintf(buf, sizeof(buf),
                    "KITTI metric (devkit, %zu segments of 100..800 m, every "
                    "10 frames): t_rel %.4f %%, r_rel %.4f deg/100m\n",
                    k.num_segments, k.t_rel_percent, k.r_rel_deg_per_100m);
      out << buf;
      // The devkit's own figures (stats.txt: mean t_err in m/m, mean r_err
      // in rad/m, printed with %f) and r_rel in deg/m.
      std::snprintf(
          buf, sizeof(buf), "  devkit stats.txt: %f %f (r_rel %.9f deg/m)\n",
          k.t_rel_percent / 100.0, k.r_rel_deg_per_100m / 100.0 * M_PI / 180.0,
          k.r_rel_deg_per_100m / 100.0);
      out << buf;
      for (const auto& l : k.by_length) {
        std::snprintf(buf, sizeof(buf),
                      "  %4.0f m: %5zu segments  t_rel %8.4f %%  r_rel %8.4f "
                      "deg/100m\n",
                      l.length, l.count, l.t_rel_percent, l.r_rel_deg_per_100m);
        out << buf;
      }
    }
  }
}

JsonObject StatisticsJson(const ErrorStatistics& s, const char* unit) {
  JsonObject o;
  o.Add("rmse", s.rmse)
      .Add("mean", s.mean)
      .Add("median", s.median)
      .Add("std", s.std)
      .Add("min", s.min)
      .Add("max", s.max)
      .Add("sse", s.sse)
      .Add("count", s.count)
      .Add("unit", unit);
  return o;
}

JsonObject EvalSettingsJson(const EvalSettings& s) {
  JsonObject o;
  o.Add("association",
        s.association == AssociationMethod::kIndex ? "index" : "timestamp")
      .Add("t_max_diff", s.sync.t_max_diff)
      .Add("t_offset", s.sync.t_offset)
      .Add("unique_pairs", s.sync.unique_pairs)
      .Add("align", AlignmentMethodName(s.align))
      .Add("n_to_align", s.n_to_align)
      .Add("rpe_delta", s.rpe.delta)
      .Add("rpe_unit", DeltaUnitName(s.rpe.unit))
      .Add("rpe_all_pairs", s.rpe.all_pairs)
      .Add("rpe_pairs_from",
           s.rpe.pairs_from_reference ? "reference" : "estimate")
      .Add("rpe_delta_tol", s.rpe.rel_delta_tol)
      .Add("kitti", s.kitti);
  return o;
}

JsonObject EvalResultJson(const EvalResult& r, const EvalSettings& s) {
  JsonObject o;
  AddEvalResultJson(r, s, &o);
  return o;
}

void AddEvalResultJson(const EvalResult& r, const EvalSettings& s,
                       JsonObject* out) {
  JsonObject& o = *out;
  o.Add("matched_pairs", r.association.size());
  JsonObject assoc;
  assoc.Add("method", r.association.by_index ? "index" : "timestamp")
      .Add("max_pairs", r.association.max_pairs)
      .Add("reused_poses", r.association.reused_poses)
      .Add("dropped_duplicates", r.association.dropped_duplicates)
      .Add("max_abs_dt", r.association.max_abs_dt);
  o.Add("association", assoc);
  JsonObject align;
  std::vector<double> rot;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) rot.push_back(r.alignment.rotation(i, j));
  }
  align.Add("method", AlignmentMethodName(s.align))
      .Add("n_to_align", s.n_to_align)
      .Add("rotation_row_major", rot)
      .Add("translation", std::vector<double>{r.alignment.translation.x(),
                                              r.alignment.translation.y(),
                                              r.alignment.translation.z()})
      .Add("scale", r.alignment.scale);
  o.Add("alignment", align);
  o.Add("ape_translation", StatisticsJson(r.ape_translation_stats, "m"));
  o.Add("ape_rotation", StatisticsJson(r.ape_rotation_stats, "deg"));
  JsonObject rpe_t = StatisticsJson(r.rpe_translation_stats, "m");
  JsonObject rpe_r = StatisticsJson(r.rpe_rotation_stats, "deg");
  for (JsonObject* o2 : {&rpe_t, &rpe_r}) {
    o2->Add("delta", s.rpe.delta)
        .Add("delta_unit", DeltaUnitName(s.rpe.unit))
        .Add("all_pairs", s.rpe.all_pairs)
        .Add("pairs_from",
             s.rpe.pairs_from_reference ? "reference" : "estimate");
  }
  o.Add("rpe_translation", rpe_t);
  o.Add("rpe_rotation", rpe_r);
  JsonObject path;
  path.Add("reference", r.ref_path_length).Add("estimate", r.est_path_length);
  o.Add("path_length", path);
  if (r.has_kitti) {
    JsonObject k;
    k.Add("t_rel_percent", r.kitti.t_rel_percent)
        .Add("r_rel_deg_per_100m", r.kitti.r_rel_deg_per_100m)
        .Add("segments", r.kitti.num_segments);
    std::string lengths = "[";
    for (size_t i = 0; i < r.kitti.by_length.size(); ++i) {
      const auto& l = r.kitti.by_length[i];
      JsonObject e;
      e.Add("length", l.length)
          .Add("segments", l.count)
          .Add("t_rel_percent", l.t_rel_percent)
          .Add("r_rel_deg_per_100m", l.r_rel_deg_per_100m);
      lengths += (i ? ", " : "") + e.ToString(6);
    }
    k.AddRaw("by_length", lengths + "]");
    if (r.kitti.num_segments == 0) {
      k.Add("note", "no segment of 100 m or more: metric not defined");
    }
    o.Add("kitti", k);
  }
}

bool WriteEvalPlots(const std::string& dir, const EvalResult& result,
                    const EvalSettings& settings, const EvalLabels& labels,
                    std::vector<std::string>* written, std::string* error) {
  using Function =
      bool (*)(const std::string&, const EvalResult&, const EvalSettings&,
               const EvalLabels&, std::vector<std::string>*, std::string*);
  void* symbol = nullptr;
  if (!LoadPlotModuleSymbol("SlamWriteEvalPlots", &symbol, error)) {
    return false;
  }
  return reinterpret_cast<Function>(symbol)(dir, result, settings, labels,
                                            written, error);
}

bool EvaluateAndReport(const Trajectory& ref, const Trajectory& est,
                       const EvalSettings& settings, const EvalLabels& labels,
                       const std::string& plot_dir, std::ostream& out,
                       EvalResult* result, std::string* error) {
  return EvaluateAndReport(ToEvalTrajectory(ref), ToEvalTrajectory(est),
                           settings, labels, plot_dir, out, result, error);
}

bool EvaluateAndReport(const EvalTrajectory& ref, const EvalTrajectory& est,
                       const EvalSettings& settings, const EvalLabels& labels,
                       const std::string& plot_dir, std::ostream& out,
                       EvalResult* result, std::string* error) {
  if (!EvaluateTrajectories(ref, est, settings, result, error)) return false;
  PrintAssociationAndAlignment(*result, settings, out);
  PrintEvalTable(*result, settings, out);
  if (!plot_dir.empty()) {
    std::vector<std::string> written;
    if (!WriteEvalPlots(plot_dir, *result, settings, labels, &written, error)) {
      return false;
    }
    out << "plots:";
    for (const auto& w : written) out << " " << w;
    out << "\n";
  }
  return true;
}

bool EvaluateAndReport(const Trajectory& ref, const Trajectory& est,
                       const EvalSettings& settings,
                       const std::string& plot_dir, std::ostream& out,
                       EvalResult* result, std::string* error) {
  return EvaluateAndReport(ref, est, settings, EvalLabels(), plot_dir, out,
                           result, error);
}

bool EvaluateGraphAgainstGroundTruth(const Graph& graph,
                                     const TrajectoryData& gt,
                                     const std::string& gt_name,
                                     const std::string& config_path,
                                     const std::string& plot_dir,
                                     JsonObject* report, std::string* error) {
  Trajectory estimate;
  if (!TrajectoryFromGraph(graph, false, &estimate, error)) return false;
  EvalSettings settings;
  if (!LoadEvalSectionOfConfig(config_path, &settings, error)) return false;
  settings.association = ChooseAssociation(gt.has_stamps, true);
  EvalLabels labels;
  labels.ref_name = "ground truth";
  labels.est_name = "optimized";
  EvalResult result;
  std::printf("\nevaluation against %s:\n", gt_name.c_str());
  if (!EvaluateAndReport(gt.poses, estimate, settings, labels, plot_dir,
                         std::cout, &result, error)) {
    return false;
  }
  report->Add("evaluation", EvalResultJson(result, settings));
  return true;
}

}  // namespace slam
