// The evaluation plots, drawn with OpenCV (core, imgproc) and written as PNG.
// Built into the plot module (libslam_plot.so) that `slam` loads only when
// it draws, so that the OpenCV libraries do not slow down the start of every
// command (about 9 ms per process on this machine class).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "apps/eval_report.h"
#include "apps/format.h"
#include "apps/plot/plot.h"
#include "datasets/atomic_file.h"

namespace slam {
namespace {

// x values of the plots: seconds from the first matched estimate stamp, or
// the pair index when associated by index.
std::vector<double> TimeAxis(const EvalResult& r) {
  std::vector<double> t(r.est_stamps.size());
  for (size_t i = 0; i < t.size(); ++i) {
    t[i] = r.association.by_index
               ? static_cast<double>(i)
               : NsToSeconds(r.est_stamps[i] - r.est_stamps[0]);
  }
  return t;
}

std::string TimeLabel(const EvalResult& r) {
  return r.association.by_index ? "pose index"
                                : "time from the first matched pose [s]";
}

// "over time" or "over the pose index", as the x axis is.
std::string OverAxis(const EvalResult& r) {
  return r.association.by_index ? "over the pose index" : "over time";
}

void AddStatLines(const ErrorStatistics& s, const char* unit,
                  plot::Axes* axes) {
  axes->hlines.push_back(
      {s.rmse, plot::kRed, true, "rmse " + Fmt("%.4g", s.rmse) + " " + unit});
  axes->hlines.push_back({s.median, plot::kOrange, true,
                          "median " + Fmt("%.4g", s.median) + " " + unit});
  axes->hlines.push_back(
      {s.mean, plot::kGreen, true, "mean " + Fmt("%.4g", s.mean) + " " + unit});
}

}  // namespace

bool WriteEvalPlotsImpl(const std::string& dir, const EvalResult& r,
                        const EvalSettings& s, const EvalLabels& labels,
                        std::vector<std::string>* written, std::string* error) {
  // Removed again if the command fails (datasets/atomic_file.h).
  if (!CreateOutputFolder(dir, error)) return false;
  // Project on a plane: drop the axis along which the reference moves least
  // (z for a ground vehicle in a z-up world, y for KITTI's camera frames).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-1e300);
  for (const MatrixPose& p : r.ref) {
    lo = lo.cwiseMin(p.t);
    hi = hi.cwiseMax(p.t);
  }
  const Eigen::Vector3d extent = hi - lo;
  int drop = 2;
  if (extent.x() < extent[drop]) drop = 0;
  if (extent.y() < extent[drop]) drop = 1;
  if (extent.z() <= extent[drop]) drop = 2;
  const int ax = drop == 0 ? 1 : 0;
  const int ay = drop == 2 ? 1 : 2;
  const char* names = "xyz";
  const std::string plane = std::string(1, names[ax]) + "-" + names[ay];
  const std::string plane_text =
      plane + " plane (" + names[drop] + ", the axis of least extent, dropped)";
  auto xs = [&](const std::vector<MatrixPose>& v) {
    std::vector<double> out;
    for (const MatrixPose& p : v) out.push_back(p.t[ax]);
    return out;
  };
  auto ys = [&](const std::vector<MatrixPose>& v) {
    std::vector<double> out;
    for (const MatrixPose& p : v) out.push_back(p.t[ay]);
    return out;
  };
  const std::string xl = std::string(1, names[ax]) + " [m]";
  const std::string yl = std::string(1, names[ay]) + " [m]";
  const char* const align_names[] = {"not aligned", "SE(3)-aligned",
                                     "Sim(3)-aligned", "scale-corrected",
                                     "aligned at the first pose"};
  const std::string align_name = align_names[static_cast<int>(s.align)];

  auto save = [&](const std::string& name, const cv::Mat& img) {
    const std::string path = dir + "/" + name;
    if (!plot::SavePng(path, img, error)) return false;
    written->push_back(path);
    return true;
  };

  {  // Trajectories projected on the plane.
    plot::Axes a;
    a.title = "Trajectories in the " + plane_text + ", estimate " + align_name;
    a.xlabel = xl;
    a.ylabel = yl;
    a.equal_aspect = true;
    a.lines.push_back({xs(r.ref), ys(r.ref), plot::kGray, 2, true,
                       labels.ref_name + " (reference)"});
    a.lines.push_back({xs(r.est_aligned), ys(r.est_aligned), plot::kBlue, 2,
                       false, labels.est_name + " (estimate)"});
    if (!r.ref.empty()) {
      a.markers.push_back({r.ref.front().t[ax], r.ref.front().t[ay],
                           plot::kGreen, false, "start"});
      a.markers.push_back(
          {r.ref.back().t[ax], r.ref.back().t[ay], plot::kRed, true, "end"});
    }
    if (!save("trajectories.png", plot::RenderFigure({a}, 1400, 1050))) {
      return false;
    }
  }
  {  // APE along the path.
    plot::Axes a;
    const ErrorStatistics& st = r.ape_translation_stats;
    a.title = "APE translation along the estimate (rmse " +
              Fmt("%.4g", st.rmse) + " m, max " + Fmt("%.4g", st.max) +
              " m), estimate " + align_name + ", " + plane + " plane";
    a.xlabel = xl;
    a.ylabel = yl;
    a.equal_aspect = true;
    a.lines.push_back({xs(r.ref), ys(r.ref), plot::kGray, 1, true,
                       labels.ref_name + " (reference)"});
    plot::ColoredPath path;
    path.x = xs(r.est_aligned);
    path.y = ys(r.est_aligned);
    path.value = r.ape_translation;
    path.vmin = st.min;
    path.vmax = st.max;
    path.colorbar_label = "APE translation [m]";
    path.label = labels.est_name + " coloured by APE";
    a.paths.push_back(path);
    if (!save("ape_map.png", plot::RenderFigure({a}, 1400, 1050))) {
      return false;
    }
  }
  const std::vector<double> t = TimeAxis(r);
  {  // APE over time.
    plot::Axes at, ar;
    at.title =
        "APE translation " + OverAxis(r) + " (estimate " + align_name + ")";
    at.xlabel = TimeLabel(r);
    at.ylabel = "APE translation [m]";
    at.lines.push_back(
        {t, r.ape_translation, plot::kBlue, 2, false, "APE translation"});
    AddStatLines(r.ape_translation_stats, "m", &at);
    ar.title = "APE rotation " + OverAxis(r) +
               " (angle of inv(P_est) * P_ref, estimate " + align_name + ")";
    ar.xlabel = TimeLabel(r);
    ar.ylabel = "APE rotation [deg]";
    ar.lines.push_back(
        {t, r.ape_rotation_deg, plot::kPurple, 2, false, "APE rotation"});
    AddStatLines(r.ape_rotation_stats, "deg", &ar);
    if (!save("ape.png", plot::RenderFigure({at, ar}, 1400, 620))) {
      return false;
    }
  }
  {  // RPE over time, at the second pose of each pair.
    std::vector<double> tj;
    for (const auto& pr : r.rpe.pairs) tj.push_back(t[pr.second]);
    plot::Axes at, ar;
    // Short enough for the width: the delta, the pairs, the alignment.
    std::string rpe = "delta " + Fmt("%g", s.rpe.delta) + " " +
                      DeltaUnitName(s.rpe.unit) +
                      (s.rpe.all_pairs ? ", all pairs" : ", consecutive pairs");
    if (s.rpe.pairs_from_reference) rpe += " on the reference";
    at.title = "RPE translation " + OverAxis(r) + " (" + rpe + ", estimate " +
               align_name + ")";
    at.xlabel = TimeLabel(r);
    at.ylabel = "RPE translation [m]";
    at.lines.push_back(
        {tj, r.rpe.translation, plot::kBlue, 2, false, "RPE translation"});
    AddStatLines(r.rpe_translation_stats, "m", &at);
    ar.title = "RPE rotation " + OverAxis(r) + " (" +
               std::to_string(r.rpe.pairs.size()) +
               " pairs, plotted at the end of each pair)";
    ar.xlabel = TimeLabel(r);
    ar.ylabel = "RPE rotation [deg]";
    ar.lines.push_back(
        {tj, r.rpe.rotation_deg, plot::kPurple, 2, false, "RPE rotation"});
    AddStatLines(r.rpe_rotation_stats, "deg", &ar);
    if (!save("rpe.png", plot::RenderFigure({at, ar}, 1400, 620))) {
      return false;
    }
  }
  return true;
}

}  // namespace slam
