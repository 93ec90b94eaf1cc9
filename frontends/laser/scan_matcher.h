// 2D scan matching: point-to-line ICP (Gauss-Newton on point-to-line
// distances, normals from neighbouring target points) and a correlative
// search (Olson, "Real-time correlative scan matching", ICRA 2009) on a
// likelihood grid with an exact multi-level branch and bound over the
// translations (a max-pyramid as in Hess et al., ICRA 2016), refined by
// ICP.
//
// Frames: a MatchTarget holds points in its own frame T (a keyframe's body
// frame or the world frame of a local submap). A match estimates the pose
// X = (t, theta) of the source scan's frame S in T: p_T = R(theta) p_S + t.
//
// Covariance: right (body-frame) perturbation of X, translation first
// (core/conventions.h), so it is the covariance of the (dx, dy, dtheta) error
// of a between factor whose second node is the scan's pose. It is
//   Sigma = scale * sigma^2 * H^-1,  H = sum_i J_i^T J_i,
// J_i the 1x3 Jacobian of the i-th point-to-line distance over the inliers
// and sigma^2 = max(sigma_min^2, sum r_i^2 / (n - 3)) the residual variance.
// Neighbouring laser points do not have independent errors (the same wall,
// the same range bias); `covariance_scale` inflates the otherwise too
// optimistic Hessian bound. In a corridor H is nearly singular along the
// corridor, so the covariance is large along it and small across it.
#ifndef SLAM_FRONTENDS_LASER_SCAN_MATCHER_H_
#define SLAM_FRONTENDS_LASER_SCAN_MATCHER_H_

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/lie.h"

namespace slam {

using Points2 = std::vector<Eigen::Vector2d>;

// p -> R p + t for every point.
Points2 TransformPoints(const Pose2& pose, const Points2& points);
// Beam endpoints in the laser frame; readings outside [min_range,
// max_range) or not finite are dropped.
Points2 RangesToPoints(const std::vector<float>& ranges, double angle_min,
                       double angle_increment, double min_range,
                       double max_range);
// One point per occupied cell of a square grid of side `cell` (the centroid
// of the points falling into it), in first-seen order.
Points2 VoxelFilter(const Points2& points, double cell);

struct IcpOptions {
  // Correspondences farther than this (m) from the transformed point are
  // dropped (trimming).
  double max_correspondence_distance = 0.3;
  int max_iterations = 30;
  // Largest Gauss-Newton step per iteration (m, rad).
  double max_step_translation = 0.2;
  double max_step_rotation = 0.1;
  // Huber kernel width on the point-to-line distance (m).
  double huber_width = 0.03;
  // Stop when the step is below both (m, rad).
  double translation_tolerance = 1e-5;
  double rotation_tolerance = 1e-6;
  // A point counts as an inlier (fitness) when its point-to-line distance
  // is below this (m).
  double inlier_distance = 0.05;
  // Covariance (see the file comment).
  double sigma_min = 0.01;
  double covariance_scale = 10.0;
};

struct CorrelativeOptions {
  double resolution = 0.05;  // Fine grid cell (m).
  // Branch-and-bound levels above the fine grid: level l bounds blocks of
  // 2^l x 2^l fine offsets (0: exhaustive search at the fine level).
  int levels = 3;
  double sigma = 0.05;        // Likelihood exp(-d^2 / 2 sigma^2) (m).
  double window_xy = 0.3;     // Search +-window around the guess (m).
  double window_theta = 0.2;  // ... (rad).
  double step_theta = 0.005;  // Angular step (rad).
  // Poses scoring (mean likelihood) below this are not searched: the bound
  // prunes them at the coarsest level. When none reaches it, the search
  // returns the initial pose with score 0. Loop verification sets it to
  // the score a closure needs (most candidates fail, and proving that
  // nothing reaches the score is cheap where proving which pose is best
  // is not).
  double min_score = 0.0;
  // Work bound: at most this many likelihood look-ups (one per source
  // point and pose or bound evaluated); when reached, the search stops and
  // returns the best pose found so far, i.e. the best of the branches it
  // explored first, the most promising by their bounds (0: no bound, the
  // search is exact). Wide windows where nothing fits well prune little
  // and cost tens of times a typical search.
  double max_evaluations = 0.0;
  // Probe (with min_score > 0): a search that has scored no pose reaching
  // min_score after this many look-ups stops there and reports nothing
  // (the initial pose, score 0); 0: no probe. The depth-first order
  // descends into the branches of highest bound first: where the place is
  // right, the peak dominates the bounds and a pose reaching the score is
  // found early, and where it is wrong most of the work goes into proving
  // that none does (loose bounds over a wide window), up to the work bound.
  double probe_evaluations = 0.0;
  // The likelihood grids are built this far (m) beyond where the source
  // can land, so that the next searches nearby (tracking) reuse them; a
  // target searched once (loop verification) needs none: building the
  // grids and their pyramid costs in proportion to their area.
  double grid_margin = 5.0;
};

// What a correlative search did.
struct CorrelativeWork {
  double evaluations = 0.0;     // Likelihood look-ups.
  bool probe_stopped = false;   // Stopped by probe_evaluations.
  bool budget_stopped = false;  // Stopped by max_evaluations.
  // Look-ups when the first pose reaching min_score was scored (0: none).
  double first_found_evaluations = 0.0;
  int verified = 0;             // Poses handed to the verifier.
  bool verify_stopped = false;  // Stopped by the verifier.
};

struct MatchResult {
  Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  int num_points = 0;  // Source points used.
  int num_correspondences = 0;
  int num_inliers = 0;
  double fitness = 0.0;  // num_inliers / num_points.
  double rmse = 0.0;     // Of the inlier distances (m).
  double score = 0.0;    // Correlative score (mean likelihood), if run.
  int iterations = 0;
  bool success = false;  // Enough correspondences, H well conditioned.
};

// A Gaussian prior on the matched pose X (e.g. the odometry prediction):
// the cost e^T W e is added to ICP's, e = (R_p^T (t - t_p), theta -
// theta_p). W is in ICP's units: the point-to-line residuals enter with unit
// weight, so a prior of covariance C (m, rad) for residuals of variance s2
// is W = s2 * C^-1. Along directions the points constrain well the prior is
// negligible; along a corridor it keeps the match from sliding. The result's
// covariance is that of the points alone (the prior is usually a separate
// factor of the graph).
struct IcpPrior {
  Pose2 pose;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
};

// Points in frame T with normals, a grid hash for nearest-neighbour lookup
// and (built on demand) the likelihood grids of the correlative search.
class MatchTarget {
 public:
  MatchTarget() = default;
  // `points` should already be thinned (VoxelFilter). Normals come from the
  // neighbours within `normal_radius` (principal axes); with fewer than 3
  // neighbours, from the line to the nearest point within 4 radii (PL-ICP's
  // segment). Points without a dominant direction (corners, clutter) have
  // no normal and are not matched against.
  void Build(Points2 points, double cell_size, double normal_radius);

  const Points2& points() const { return points_; }
  bool empty() const { return points_.empty(); }

  // Nearest target point within max_distance; -1 if none.
  int Nearest(const Eigen::Vector2d& query, double max_distance) const;

  // Point-to-line ICP from `initial`.
  MatchResult Icp(const Points2& source, const Pose2& initial,
                  const IcpOptions& options,
                  const IcpPrior* prior = nullptr) const;

  // Best pose on the search lattice around `initial` by the correlative
  // score (mean likelihood of the source points); writes the score (and
  // what the search did, when `work` is given).
  //
  // `verify` (optional) is called with each pose that becomes the best
  // (reaching min_score), in the order the search finds them, and its score;
  // when it returns false the search stops there and reports nothing (the
  // initial pose, score 0; CorrelativeWork::verify_stopped).
  using Verifier = std::function<bool(const Pose2& pose, double score)>;
  Pose2 Correlative(const Points2& source, const Pose2& initial,
                    const CorrelativeOptions& options, double* score,
                    CorrelativeWork* work = nullptr,
                    const Verifier* verify = nullptr) const;

  // Correlative search, then ICP from its result.
  MatchResult Match(const Points2& source, const Pose2& initial,
                    const CorrelativeOptions& correlative,
                    const IcpOptions& icp) const;

 private:
  struct LikelihoodGrids {
    double resolution = 0.0, sigma = 0.0;
    int levels = -1;
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    int width = 0, height = 0;
    // pyramid[l][i, j] = max of fine over [i, i + 2^l) x [j, j + 2^l);
    // pyramid[0] is the fine grid.
    std::vector<std::vector<float>> pyramid;
    // The part of the plane the grids are valid for (outside: 0).
    Eigen::Vector2d valid_lo = Eigen::Vector2d::Zero();
    Eigen::Vector2d valid_hi = Eigen::Vector2d::Zero();
  };
  // Makes the grids valid over [lo, hi] (where the source points can land);
  // they are rebuilt only when the options change or the box is not covered.
  void BuildLikelihood(const CorrelativeOptions& options,
                       const Eigen::Vector2d& lo,
                       const Eigen::Vector2d& hi) const;

  Points2 points_;
  std::vector<Eigen::Vector2d> normals_;
  std::vector<uint8_t> has_normal_;
  // Grid hash over the bounding box: cell_start_[c]..cell_start_[c+1] index
  // into cell_points_.
  double cell_size_ = 0.3;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int grid_width_ = 0, grid_height_ = 0;
  std::vector<int> cell_start_;
  std::vector<int> cell_points_;
  mutable LikelihoodGrids likelihood_;
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_LASER_SCAN_MATCHER_H_
