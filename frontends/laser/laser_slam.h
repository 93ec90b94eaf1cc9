// 2D laser SLAM: scan-to-submap tracking, keyframes, loop closure, all as
// factors in one pose graph (core/graph.h) optimized with core/optimizer.h.
//
// Per scan (in log order):
//  1. Beam endpoints in the laser frame (readings in [min_range, max_range)),
//     moved into the robot frame by the scan's laser offset and thinned
//     (VoxelFilter, voxel_size).
//  2. Prediction: the tracked pose of the previous scan composed with the
//     odometry increment between the two scans.
//  3. Tracking: point-to-line ICP of the scan against the local submap (the
//     points of the last `submap_keyframes` keyframes in the world frame, at
//     their current estimates), pulled towards the prediction by an odometry
//     prior (tracking_odometry_weight) so that it cannot slide along
//     corridors. When ICP fails, fits poorly (fitness below
//     min_tracking_fitness) or jumps more than max_tracking_jump from the
//     prediction, a correlative search (local_correlative) refined by ICP is
//     tried; if that fails too the prediction is kept. Robust tracking
//     (robust_tracking): the odometry is a prior, not the truth; when its
//     increment is implausible or the match fits badly, ICP from the
//     constant-velocity prediction competes, the better fit wins, and the
//     keyframe odometry factor across a rejected increment is dropped; a
//     poorly fitting match seeded by a plausible odometry increment that
//     lies beyond odometry_break_chi2 of it (a slide instead of a fast
//     turn) is not used: the prediction is kept.
//  4. Keyframes: when the tracked pose has moved keyframe_distance or turned
//     keyframe_rotation since the last keyframe, the scan becomes a keyframe
//     (a Pose2 node, id = keyframe index, stamped). Two factors join it to
//     the previous keyframe: the scan match (relative pose of the tracked
//     poses, covariance from the ICP Hessian, frontends/laser/scan_matcher.h)
//     and the odometry (relative odometry pose, differential-drive
//     covariance, frontends/laser/odometry_model.h). Chain links: scan
//     matches to the chain_links keyframes before k-1 (Karto).
//  5. Loop closure (every loop_every-th keyframe k): candidates are older
//     keyframes j at least loop_min_separation metres of path away whose
//     estimated position lies within r = min(loop_max_radius,
//     loop_search_radius + loop_radius_growth * L) of keyframe k, L the path
//     since j or since the last accepted closure plus loop_min_separation,
//     whichever is shorter (dead-reckoning uncertainty grows with the path
//     travelled without a closure). The nearest loop_max_candidates (from
//     different places) are verified by matching the query (the last
//     loop_query_keyframes keyframes as one cloud in k's frame) against the
//     submap of keyframes j-h..j+h (h = loop_submap_half_width) in j's
//     frame: correlative search over +-max(window, r) then ICP, passing
//     LoopMatchPasses (the correlative search prunes every pose scoring
//     below loop_min_score and a candidate where none reaches it gets no
//     ICP; the search's work is bounded, loop_correlative.max_evaluations;
//     the first poses it finds reaching the score are verified by ICP at
//     once, and when loop_search_verifications of them fail it stops).
//     A candidate of a place closed in the last loop_consistency_keyframes
//     keyframes is first verified by ICP alone from the pose that closure
//     predicts (loop_seeded_verification). A passing match is accepted
//     only when the correction it implies agrees (loop_consistency_distance /
//     _angle, both corrections applied to k's estimate, so that the test does
//     not depend on how far the place is from the map's origin) with a passing
//     match of another keyframe within loop_consistency_keyframes; both then
//     enter the graph as between factors with the robust kernel loop_kernel.
//     Places already holding loop_place_max_closures closures are skipped.
//     When nothing closes for loop_global_min_path metres, a global search
//     (loop_global_*) proposes places outside the radius by their Scan
//     Context (frontends/laser/scan_context.h) and verifies them the same
//     way (a search that scores no pose reaching loop_min_score within
//     loop_global_probe_evaluations look-ups stops there), with more
//     agreeing matches; closures with large corrections are
//     optimized without the kernel first and undone when they raise the
//     chi2 of the rest of the graph by more than loop_global_max_chi2 or
//     loop_max_chi2_per_link per factor of the chain they bend.
//  6. Optimization: after a loop closure moving its keyframe by at least
//     loop_optimize_min_correction (at most every loop_optimize_interval
//     keyframes) and every optimize_every keyframes,
//     with at most incremental_iterations iterations; the tracked pose
//     follows its keyframe. Finish() optimizes to convergence, then counts
//     the closures whose robust weight rho'(chi2) ended below
//     loop_reject_weight as rejected, removes them and optimizes again;
//     then a final loop-closure pass (loop_final_*) on the optimized map,
//     optimization and rejection again, and the refinement of every scan
//     against the optimized keyframes around it (refine_*).
//
// Every scan keeps its pose relative to the keyframe it was tracked from,
// so that every scan stamp gets a pose in the output trajectory.
#ifndef SLAM_FRONTENDS_LASER_LASER_SLAM_H_
#define SLAM_FRONTENDS_LASER_LASER_SLAM_H_

#include <memory>
#include <string>
#include <vector>

#include "core/graph.h"
#include "core/optimizer.h"
#include "core/sensors/laser_data.h"
#include "core/trajectory.h"
#include "factors/robust_kernels.h"
#include "frontends/laser/odometry_model.h"
#include "frontends/laser/scan_context.h"
#include "frontends/laser/scan_matcher.h"

namespace slam {

struct LaserSlamConfig {
  // Scan preprocessing.
  double min_range = 0.1;    // m.
  double max_range = 40.0;   // m; longer readings are not used for matching.
  double voxel_size = 0.05;  // m; source thinning.
  // Keyframes.
  double keyframe_distance = 0.3;  // m.
  double keyframe_rotation = 0.2;  // rad.
  // Local tracking.
  int submap_keyframes = 15;
  double submap_voxel = 0.03;   // m; thinning of the submap points.
  double normal_radius = 0.15;  // m.
  IcpOptions icp;
  double min_tracking_fitness = 0.15;
  // Correlative search before ICP on every scan (else only when ICP fails).
  bool always_correlative = false;
  double max_tracking_jump = 0.5;  // m (and the same number in rad).
  // Robust tracking: the odometry is a prior, not the truth (wheel
  // encoders freeze and then jump, wheels slip). An odometry increment that
  // differs from the last tracked one by more than max_tracking_jump is
  // implausible and not used. When the odometry-prior ICP fails or fits
  // below tracking_recheck_ratio times the running mean of the tracking
  // fitness, ICP is also tried from the constant-velocity prediction (with
  // a prior of the last tracked motion's information), then the
  // correlative search, and the best fit wins (an alternative must beat
  // the odometry's fitness by tracking_recheck_margin). When the chosen
  // match is not the odometry's and the odometry increment's chi2 against
  // it exceeds odometry_break_chi2, the odometry is rejected for that
  // scan: the keyframe odometry factor spanning it is dropped (kept with
  // its standard deviations times odometry_break_inflation when no scan
  // match joins the two keyframes), chain links use the tracked motion as
  // prior. Conversely, when the match came from the odometry's prediction,
  // the odometry increment was plausible, the match fits below
  // tracking_recheck_ratio times the running fitness and its chi2 against
  // the increment exceeds odometry_break_chi2, the match is not used and
  // the prediction is kept (tracking_slides_rejected).
  bool robust_tracking = true;
  double tracking_recheck_ratio = 0.7;
  double tracking_recheck_margin = 0.05;
  double odometry_break_chi2 = 100.0;
  double odometry_break_inflation = 100.0;
  // Tracking ICP is pulled towards the odometry prediction with the
  // odometry increment's information (odometry model below) times this
  // weight, converted to ICP's units with icp.sigma_min^2 *
  // icp.covariance_scale (IcpPrior); 0: no prior. It stops the scan from
  // sliding along corridors where the points barely constrain it.
  double tracking_odometry_weight = 1.0;
  CorrelativeOptions local_correlative{0.05, 3, 0.05, 0.4, 0.3, 0.01};
  // Chain links (Karto): each new keyframe k is also matched by ICP
  // against keyframes k-2 .. k-1-chain_links alone (from the tracked
  // relative pose, with the odometry prior of tracking) and joined to each
  // by a scan-match factor, which stiffens the local chain against
  // closures pulling single keyframes. 0: off.
  int chain_links = 2;
  OdometryNoise odometry;
  // Added (as variances) to the matcher's Hessian covariance of every
  // scan-match and loop-closure factor: the Hessian bound ignores
  // correlated errors (range bias, discretization, wrong normals) and would
  // make a chain of scan matches too stiff for loop closures to bend.
  double match_min_sigma_xy = 0.01;      // m.
  double match_min_sigma_theta = 0.003;  // rad.
  // Loop closure.
  bool loop_closure = true;
  double loop_min_separation = 10.0;  // m of path.
  double loop_search_radius = 2.0;    // m.
  double loop_radius_growth = 0.03;   // m per m of path.
  double loop_max_radius = 8.0;       // m.
  int loop_max_candidates = 2;
  int loop_submap_half_width = 6;  // keyframes.
  int loop_query_keyframes = 10;   // Last keyframes matched as one cloud.
  double loop_query_voxel = 0.1;   // m; thinning of that cloud.
  double loop_search_voxel = 0.2;  // m; further thinning for the search.
  // At most 2e6 look-ups per search (max_evaluations, about 10 ms): the
  // exact search's cost has no bound (ACES and MIT CSAIL: median 2-4e6,
  // 10 % above 8e6, 3e7 over a 7 m window where nothing fits well; most
  // of it proves that the pose found first is the best). Bounded, a
  // search returns the best pose of the branches it explored first (the
  // most promising). 2e6 is a guess from ACES and MIT CSAIL (4e6 left
  // ACES unchanged but moved MIT's rotation std to 0.42 deg, 2e6 0.33:
  // that figure flips with any change of the loop search order).
  CorrelativeOptions loop_correlative{0.05, 6, 0.05, 1.5, 0.35, 0.01, 0.0, 2e6};
  int loop_every = 2;  // Check every n-th keyframe.
  // A place (keyframes j-h..j+h, h = loop_submap_half_width) that already
  // holds this many closures is not searched again (incremental and final
  // pass): more closures add little there, and searching every revisit of
  // every place makes the cost grow with the square of the log length
  // (a log played three times cost 8.8 times one playing). <= 0: no limit.
  int loop_place_max_closures = 32;
  // For this many metres of path after a closure accepted against a place
  // closed on an earlier visit (visited at least three times), the
  // estimate is anchored to a well-connected map: local candidates are
  // verified by ICP alone from the estimate (no correlative search; the
  // match may move k by at most loop_final_max_correction), which keeps
  // the loop search cost of repeated traversals near that of the first
  // (a log played three times cost 8.8 times one playing). 0: always
  // search.
  double loop_anchored_path = 10.0;
  // An accepted closure triggers an incremental optimization only when it
  // moves its keyframe by at least this (m, and the same number in rad);
  // smaller corrections wait for the periodic and the final optimization.
  double loop_optimize_min_correction = 0.05;
  // A local candidate j of a place closed in the last
  // loop_consistency_keyframes keyframes (a closure from keyframe k' to
  // j' within loop_submap_half_width of j) is first verified by ICP alone
  // from the pose that closure predicts for k in j's frame (it may move
  // k by at most loop_final_max_correction, as in the final pass); the
  // correlative search runs only when that match fails. Along a revisit
  // most candidates are of a place just closed, and the correlative
  // search was about 80 % of the loop search (profile of issue 24).
  bool loop_seeded_verification = true;
  // Verified search: a loop candidate's correlative search hands each pose
  // it finds that reaches loop_min_score and beats the ones before
  // (CorrelativeOptions: depth-first, highest bound first) to ICP and
  // LoopMatchPasses at once, until one passes; after this many have failed
  // the search stops and the candidate is rejected. Once one passes, the
  // search goes on to its best pose as without it. 0: off (every search runs
  // to its best pose or its work bound). Measured on ACES, MIT CSAIL and
  // Intel (all candidates reaching the score): where the best pose failed
  // ICP, the first one had failed too in 234 of 239 searches, and those
  // searches spent 1.5-1.9e6 look-ups each (means) against medians of
  // 3e4-6e5 to the first; of 53 accepted closures, the first pose of 51
  // passed (the other 2 are lost with 1). 1 is set from those (a guess;
  // allowing 3 failures at distinct ICP results kept the 2 but saved a
  // fifth as many look-ups: consecutive poses climb one failing peak).
  int loop_search_verifications = 1;
  double loop_min_score = 0.2;
  int loop_min_inliers = 100;
  double loop_min_fitness = 0.0;  // Inliers / query points (overlap).
  // Largest standard deviation of the match's position (m, from the ICP
  // covariance); <= 0: no limit. On ACES 0.03 halves the closures the
  // kernel later rejects (13 -> 4) but not the relation error (0.0491 m
  // against 0.0485 m without), so it is off by default.
  double loop_max_sigma = 0.0;
  double loop_min_inlier_ratio = 0.7;  // Of the correspondences.
  int loop_consistency_keyframes = 8;
  double loop_consistency_distance = 0.1;  // m.
  double loop_consistency_angle = 0.02;    // rad.
  RobustKernelSpec loop_kernel{"cauchy", 3.0};
  double loop_reject_weight = 0.1;
  // Global loop search, for drift beyond the local radius. At every
  // loop_global_every-th loop check without an accepted closure when no
  // closure was accepted for loop_global_min_path metres of path: the
  // loop query's Scan Context (scan_context.h, loop_context; stored per
  // keyframe) is compared with those of the older keyframes outside the
  // local radius (loop_min_separation of path away, place not saturated):
  // the loop_global_preselect nearest by ring key, then the
  // loop_global_candidates (from different places) with the smallest
  // descriptor distance, at most loop_global_max_distance, are verified
  // like local candidates but from the descriptor's rotation over
  // +-loop_global_window (m) and +-2 sectors (the descriptor's rotation is
  // good to a sector). The ring key (scan_context.h) holds each ring's
  // occupancy and its harmonics' magnitudes: the occupancy alone is about
  // the same for every corridor and preselected arbitrary corridors. A
  // global match is accepted only when
  // loop_global_min_agreeing other passing matches of recent keyframes
  // imply the same correction (local ones need one). Closures (global or
  // local) moving their keyframe by more than 2 m or 0.35 rad are first
  // optimized without the robust kernel (far outside its width they would
  // get no weight), then given the kernel like every closure, or undone
  // (loop_global_max_chi2).
  bool loop_global = true;
  ScanContextOptions loop_context;
  double loop_global_min_path = 10.0;  // m.
  int loop_global_every = 2;
  int loop_global_preselect = 10;
  int loop_global_candidates = 2;
  double loop_global_max_distance = 0.5;
  double loop_global_window = 3.0;  // m.
  // A global candidate's search stops after this many look-ups when it
  // has scored no pose reaching loop_min_score (CorrelativeOptions::
  // probe_evaluations; 0: off). Where the place is right the peak
  // dominates the bounds and such a pose is found within 3e4-4e5 look-ups
  // (the simulated revisits, LaserSlamTest); on ACES and MIT CSAIL, where
  // no global candidate is right, 27 and 73 % of them found none and each
  // spent the whole work bound (2e6) proving it. 5e5 is a guess from those.
  double loop_global_probe_evaluations = 5e5;
  int loop_global_min_agreeing = 2;
  // The first optimization with such closures (see above) may raise the
  // chi2 of the other factors by at most loop_global_max_chi2, or by
  // loop_max_chi2_per_link per factor on the shortest path between the
  // closure's two keyframes through the scan-match and odometry factors
  // (the chain it bends; chain links make a factor span up to
  // chain_links + 1 keyframes); else the closures are removed and the
  // graph restored (a wrong match bends the whole chain). The scan-match
  // covariances are overconfident (their errors are correlated along a
  // log): drift accumulated through hundreds of them is corrected only by
  // raising the chi2 of each a little, above any fixed bound over a long
  // excursion, yet below a wrong closure's rise per link (simulated,
  // LaserSlamTest: true corrections of 23 deg 0.8 per link over 127
  // links, wrong closures 1.7 to 2.3 per link on a ring or a building,
  // 17 and far more when they turn a corridor round). 1 per link is a guess
  // from those simulations, held on the shared logs.
  double loop_global_max_chi2 = 100.0;
  double loop_max_chi2_per_link = 1.0;
  // For this many keyframes, a passing match whose correction is within 10
  // times loop_consistency_distance / _angle of an undone one is dropped
  // without another test (each test is a full optimization).
  int loop_undone_memory = 50;
  // Final loop-closure pass (Finish, after the first global optimization
  // and rejection): the map is now consistent, so every loop_every-th
  // keyframe k is matched by ICP alone, from the optimized relative pose,
  // against older keyframes j within loop_final_radius (m) and at least
  // loop_min_separation of path away (the nearest loop_max_candidates
  // places, query and submap as above). A match passing LoopMatchPasses
  // (without the correlative score) that moves k by at most
  // loop_final_max_correction (m, and the same number in rad) from the
  // optimized estimate becomes one more closure; then the graph is
  // optimized and the closures checked again. Revisits the incremental
  // search missed or closed only loosely get constraints all along.
  bool loop_final_pass = true;
  double loop_final_radius = 1.5;
  double loop_final_max_correction = 0.3;
  // Backend.
  int optimize_every = 200;         // keyframes.
  int loop_optimize_interval = 10;  // keyframes.
  int incremental_iterations = 10;
  OptimizerOptions optimizer;  // Final optimization (verbose is ignored).
  // Final refinement (Finish, after the global optimization): every scan is
  // registered again by ICP, from its current pose, against a map of the
  // optimized keyframes around the keyframe it belongs to (that keyframe
  // excluded): the refine_window keyframes before and after it in time and
  // the keyframes within refine_radius (m) of it. Each scan's output pose
  // then agrees with the optimized map, not only with the keyframes it was
  // tracked against. The ICP has a prior at the current pose with the
  // information of the odometry since the keyframe (IcpPrior, scaled as in
  // tracking by tracking_odometry_weight), so that scans do not slide
  // along corridors. A match moving the scan more than refine_max_jump (m
  // and the same number in rad) or fitting below min_tracking_fitness
  // leaves the scan where it was.
  bool refine_scans = true;
  // Output poses of the scans between two keyframes blend both keyframes'
  // estimates (ScanRecord).
  bool interpolate_scans = true;
  int refine_window = 8;       // Keyframes on each side.
  double refine_radius = 0.0;  // m; <= 0: no spatial neighbours.
  double refine_max_jump = 0.2;
};

struct LaserSlamStats {
  int scans = 0;
  int keyframes = 0;
  int tracking_correlative = 0;  // Scans that needed the correlative search.
  int tracking_failures = 0;     // Scans left at the odometry prediction.
  int tracking_rechecks = 0;     // Scans also matched from constant velocity.
  int odometry_rejected = 0;     // Scans whose odometry tracking rejected.
  // Scans whose match, seeded by a plausible odometry increment, fitted
  // poorly and lay beyond odometry_break_chi2 of it: left at the odometry.
  int tracking_slides_rejected = 0;
  int odometry_factors_dropped = 0;   // Keyframe odometry factors dropped...
  int odometry_factors_weakened = 0;  // ... or down-weighted (no scan match).
  int closures_proposed = 0;          // Candidates verified by matching.
  int closures_accepted = 0;          // Incremental (local + global).
  int global_closures_proposed = 0;   // Global search (place recognition).
  int global_closures_accepted = 0;
  // Correlative searches of global candidates: likelihood look-ups, and
  // the searches the probe (loop_global_probe_evaluations) or the work
  // bound (loop_correlative.max_evaluations) stopped.
  double global_search_evaluations = 0.0;
  int global_searches_probe_stopped = 0;
  int global_searches_budget_stopped = 0;
  // Every loop candidate's correlative search (local and global): searches,
  // look-ups, and those a failed verification stopped
  // (loop_search_verifications).
  int loop_searches = 0;
  double loop_search_evaluations = 0.0;
  int loop_searches_verify_stopped = 0;
  // Local candidates verified by ICP from a recent closure's prediction.
  int seeded_verifications = 0;
  int closures_reverted = 0;  // Large corrections undone by the chi2 test.
  // Largest correction an accepted closure implied for its keyframe's
  // estimate when it was accepted (m, deg).
  double largest_correction_m = 0.0;
  double largest_correction_deg = 0.0;
  int closures_rejected = 0;        // Accepted, then down-weighted (Finish).
  int final_closures_proposed = 0;  // Final pass (Finish).
  int final_closures_accepted = 0;
  int optimizations = 0;
  int scans_refined = 0;  // Scans moved by the final refinement.
  double matching_seconds = 0.0;
  double loop_seconds = 0.0;
  // Split of loop_seconds: building the submap targets of candidates,
  // correlative searches (with their likelihood grids), ICP, the
  // optimizations and chi2 tests of closures with large corrections, and
  // the final pass; the rest is candidate selection, queries and
  // descriptors.
  double loop_target_seconds = 0.0;
  double loop_correlative_seconds = 0.0;
  double loop_icp_seconds = 0.0;
  double loop_chi2_seconds = 0.0;
  double loop_final_seconds = 0.0;
  double optimization_seconds = 0.0;
  double refine_seconds = 0.0;
};

// The per-match test of a loop-closure candidate (before the consistency
// check): ICP succeeded, correlative score >= loop_min_score, at least
// loop_min_inliers inliers, inliers >= loop_min_fitness of the query points
// and >= loop_min_inlier_ratio of the correspondences, and no position
// direction with a standard deviation above loop_max_sigma.
bool LoopMatchPasses(const MatchResult& match, const LaserSlamConfig& config);

class LaserSlam {
 public:
  explicit LaserSlam(const LaserSlamConfig& config);

  // Scans must come in time order.
  void AddScan(const LaserScan& scan);
  // Global optimization and the rejected-closure count.
  void Finish();

  const Graph& graph() const { return graph_; }
  const LaserSlamStats& stats() const { return stats_; }
  // Every scan's robot pose (keyframe estimate * relative pose).
  Trajectory ScanTrajectory() const;
  // Per keyframe: robot pose and points in the robot frame (for maps).
  size_t NumKeyframes() const { return keyframes_.size(); }
  Pose2 KeyframePose(size_t k) const;
  const Points2& KeyframePoints(size_t k) const { return keyframes_[k].points; }
  // Keyframe of each scan and the scan's pose relative to it.
  // With interpolate_scans, a scan between keyframes k and k+1 also keeps
  // its pose relative to k+1 (from the tracked poses before any
  // optimization moved them apart) and its time fraction alpha between the
  // two; its output pose moves from the k-anchored to the k+1-anchored pose
  // by alpha, so that the correction the optimization applies to k and k+1
  // reaches the scans between them continuously instead of as a jump at
  // each keyframe.
  struct ScanRecord {
    TimeNs stamp = 0;
    int keyframe = 0;
    Pose2 relative;
    bool has_next = false;
    Pose2 relative_next;
    double alpha = 0.0;
  };
  const std::vector<ScanRecord>& scan_records() const { return scans_; }

 private:
  struct Keyframe {
    TimeNs stamp = 0;
    Points2 points;  // Robot frame.
    Pose2 odom;
    double path = 0.0;                    // Path length from the start (m).
    std::shared_ptr<MatchTarget> target;  // Own points (chain links).
    // Tracking rejected the odometry between keyframe k-1 and k.
    bool odometry_break = false;
    int closures = 0;  // Loop-closure factors joined to this keyframe.
    // Path (of the other keyframe) of the first closure to this one.
    double first_closed_path = 1e300;
    ScanContext context;  // Of the loop query (global search).
  };

  void AddKeyframe(const LaserScan& scan, const Points2& points,
                   const MatchResult* match);
  void RebuildLocalSubmap();
  // True when an accepted closure moves its keyframe by at least
  // loop_optimize_min_correction.
  bool DetectLoopClosures(int k);
  void OptimizeGraph(int max_iterations);
  void RefineScans();
  // A prior at `pose` with the information of the odometry motion between
  // the two odometry poses, in ICP's units (tracking_odometry_weight).
  IcpPrior OdometryPrior(const Pose2& pose, const Pose2& odom_from,
                         const Pose2& odom_to) const;
  // The chi2 of a tracked increment under the odometry noise model of the
  // odometry increment odom_step.
  double OdometryDisagreement(const Pose2& odom_step,
                              const Pose2& increment) const;
  void CloseLoopsFinal();
  // Updates the largest-correction statistics with an accepted closure's:
  // it moves a keyframe from `before` to `after`. True when the move is
  // at least loop_optimize_min_correction.
  bool NoteCorrection(const Pose2& before, const Pose2& after);
  // Keyframes j-h..j+h (h = loop_submap_half_width) already hold
  // loop_place_max_closures closures.
  bool PlaceSaturated(int j) const;
  // Removes the closures the robust kernel has switched off (counted in
  // closures_rejected) and optimizes again.
  void RejectClosures();
  // The points of keyframes lo..hi in the frame whose inverse is frame_inv.
  Points2 KeyframeCloud(int lo, int hi, const Pose2& frame_inv) const;
  struct LoopHypothesis;
  // The matcher's covariance plus the floor match_min_sigma_*.
  Eigen::Matrix3d MatchCovariance(const MatchResult& match) const;
  Eigen::Matrix3d MatchCovariance(const LoopHypothesis& h) const;
  Eigen::Matrix3d MatchCovariance(const Eigen::Matrix3d& c) const;
  // The factor's id, -1 when cov is not positive definite.
  FactorId AddBetween(int i, int j, const Pose2& z, const Eigen::Matrix3d& cov,
                      std::shared_ptr<ceres::LossFunction> loss, bool loop);

  LaserSlamConfig config_;
  Graph graph_;
  LaserSlamStats stats_;
  std::vector<Keyframe> keyframes_;
  std::vector<ScanRecord> scans_;
  std::vector<Points2> scan_points_;  // Robot frame, per scan (refinement).
  std::vector<Pose2> scan_odom_;      // Odometry pose, per scan (refinement).
  Pose2 ScanPose(size_t i) const;     // Output pose of scan i.
  std::vector<FactorId> loop_factors_;
  MatchTarget local_submap_;
  Pose2 tracked_;                // Robot pose of the last scan (world).
  Pose2 last_odom_;              // Odometry pose of the last scan.
  Pose2 velocity_;               // Tracked increment of the last scan.
  double recent_fitness_ = 0.0;  // Running mean of the tracking fitness.
  bool odometry_break_ = false;  // Since the last keyframe.
  double path_ = 0.0;
  int last_optimized_keyframe_ = 0;
  double last_closure_path_ = -1e300;
  double anchored_from_path_ = -1e300;  // loop_anchored_path.
  struct LoopHypothesis {
    int k, j;
    Pose2 z;
    Eigen::Matrix3d covariance;
    Pose2 correction;
    bool added;
    bool global;  // Found by the global search.
  };
  // Verifies candidate j for keyframe k: correlative search from `guess`
  // (k in j's frame) over `search`, ICP, LoopMatchPasses, consistency; adds
  // the closures that pass. True when some were added; sets *significant
  // when one moves its keyframe by loop_optimize_min_correction, *passed
  // when the match passed (before the consistency test).
  bool VerifyLoop(int k, int j, const Pose2& guess,
                  const CorrelativeOptions* search, bool global,
                  const Points2& query, const Points2& search_query,
                  bool* significant, bool* passed);
  // Optimizes with the closures added without the robust kernel (large
  // corrections), then gives them the kernel; or, when they raise the chi2
  // of the rest of the graph by more than loop_global_max_chi2, removes
  // them and restores the graph (false).
  bool ApplyPlainClosures();
  // Factors on the shortest path joining the two keyframes of a closure
  // of plain_closures_ through the scan-match and odometry factors (the
  // shortest over the closures).
  int ChainLinks() const;
  std::vector<std::pair<FactorId, LoopHypothesis>> plain_closures_;
  // Keyframe and correction of the closures the chi2 test undid.
  std::vector<std::pair<int, Pose2>> undone_corrections_;
  std::vector<LoopHypothesis> hypotheses_;
  bool pending_loop_ = false;
};

}  // namespace slam

#endif  // SLAM_FRONTENDS_LASER_LASER_SLAM_H_
