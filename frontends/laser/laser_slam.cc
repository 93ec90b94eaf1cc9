#include "frontends/laser/laser_slam.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "factors/pose_factors.h"
#include "frontends/laser/scan_context.h"

namespace slam {
namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
      .count();
}

bool SmallMotion(const Pose2& a, const Pose2& b, double max_distance,
                 double max_angle) {
  return (a.t - b.t).norm() <= max_distance &&
         std::abs(NormalizeAngle(a.theta - b.theta)) <= max_angle;
}

// Two loop-closure corrections (world-frame transforms taking a keyframe's
// estimate to where a match puts it) compared where they act, on the
// estimate `at`: in the world frame a rotation difference of 0.002 rad
// would move the translation by 0.1 m per 50 m from the origin.
Pose2 CorrectionDifference(const Pose2& a, const Pose2& b, const Pose2& at) {
  return (a * at).Inverse() * (b * at);
}

}  // namespace

bool LoopMatchPasses(const MatchResult& match, const LaserSlamConfig& config) {
  // Degenerate geometry (a plain corridor) leaves a direction unconstrained:
  // the match may have slid along it.
  const double max_variance =
      match.success ? Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(
                          match.covariance.topLeftCorner<2, 2>())
                          .eigenvalues()[1]
                    : 0.0;
  return match.success && match.score >= config.loop_min_score &&
         (config.loop_max_sigma <= 0 ||
          max_variance <= config.loop_max_sigma * config.loop_max_sigma) &&
         match.num_inliers >= config.loop_min_inliers &&
         match.fitness >= config.loop_min_fitness &&
         match.num_inliers >=
             config.loop_min_inlier_ratio * match.num_correspondences;
}

LaserSlam::LaserSlam(const LaserSlamConfig& config) : config_(config) {}

Eigen::Matrix3d LaserSlam::MatchCovariance(const MatchResult& match) const {
  return MatchCovariance(match.covariance);
}

Eigen::Matrix3d LaserSlam::MatchCovariance(const LoopHypothesis& h) const {
  return MatchCovariance(h.covariance);
}

Eigen::Matrix3d LaserSlam::MatchCovariance(const Eigen::Matrix3d& c) const {
  Eigen::Matrix3d out = c;
  out.diagonal() += Eigen::Vector3d(
      config_.match_min_sigma_xy * config_.match_min_sigma_xy,
      config_.match_min_sigma_xy * config_.match_min_sigma_xy,
      config_.match_min_sigma_theta * config_.match_min_sigma_theta);
  return out;
}

IcpPrior LaserSlam::OdometryPrior(const Pose2& pose, const Pose2& odom_from,
                                  const Pose2& odom_to) const {
  IcpPrior prior;
  prior.pose = pose;
  if (config_.tracking_odometry_weight > 0) {
    prior.information = config_.tracking_odometry_weight *
                        config_.icp.sigma_min * config_.icp.sigma_min *
                        config_.icp.covariance_scale *
                        OdometryMotion(odom_from, odom_to, config_.odometry)
                            .covariance.inverse();
  }
  return prior;
}

double LaserSlam::OdometryDisagreement(const Pose2& odom_step,
                                       const Pose2& increment) const {
  const OdometryDelta d = OdometryMotion(Pose2(), odom_step, config_.odometry);
  const Pose2 e = d.delta.Inverse() * increment;
  const Eigen::Vector3d v(e.t.x(), e.t.y(), e.theta);
  return v.dot(d.covariance.inverse() * v);
}

bool LaserSlam::PlaceSaturated(int j) const {
  if (config_.loop_place_max_closures <= 0) return false;
  const int n = static_cast<int>(keyframes_.size());
  int closures = 0;
  for (int m = std::max(0, j - config_.loop_submap_half_width);
       m <= std::min(n - 1, j + config_.loop_submap_half_width); ++m) {
    closures += keyframes_[m].closures;
  }
  return closures >= config_.loop_place_max_closures;
}

bool LaserSlam::NoteCorrection(const Pose2& before, const Pose2& after) {
  stats_.largest_correction_m =
      std::max(stats_.largest_correction_m, (after.t - before.t).norm());
  stats_.largest_correction_deg = std::max(
      stats_.largest_correction_deg,
      std::abs(NormalizeAngle(after.theta - before.theta)) * 180.0 / M_PI);
  return !SmallMotion(before, after, config_.loop_optimize_min_correction,
                      config_.loop_optimize_min_correction);
}

Pose2 LaserSlam::KeyframePose(size_t k) const {
  return NodePose2(*graph_.FindNode(Pose2Key(static_cast<int64_t>(k))));
}

FactorId LaserSlam::AddBetween(int i, int j, const Pose2& z,
                               const Eigen::Matrix3d& cov,
                               std::shared_ptr<ceres::LossFunction> loss,
                               bool loop) {
  Factor factor;
  std::string error;
  const Eigen::Matrix3d information = cov.inverse();
  if (!MakeBetweenSE2(Pose2Key(i), Pose2Key(j), z,
                      0.5 * (information + information.transpose()), &factor,
                      &error)) {
    return -1;  // Not positive definite: the measurement carries no weight.
  }
  factor.loss = std::move(loss);
  const FactorId id = graph_.AddFactor(std::move(factor));
  if (loop && id >= 0) {
    loop_factors_.push_back(id);
    ++keyframes_[i].closures;
    ++keyframes_[j].closures;
  }
  return id;
}

void LaserSlam::AddScan(const LaserScan& scan) {
  const auto start = std::chrono::steady_clock::now();
  ++stats_.scans;
  Points2 points = RangesToPoints(
      scan.ranges, scan.angle_min, scan.angle_increment, config_.min_range,
      std::min(config_.max_range,
               scan.max_range > 0 ? scan.max_range : config_.max_range));
  points = VoxelFilter(TransformPoints(scan.laser_offset, points),
                       config_.voxel_size);

  if (keyframes_.empty()) {
    tracked_ = scan.odom;
    last_odom_ = scan.odom;
    AddKeyframe(scan, points, nullptr);
    scans_.push_back({scan.stamp, 0, Pose2(), false, Pose2(), 0.0});
    if (config_.refine_scans) {
      scan_points_.push_back(points);
      scan_odom_.push_back(scan.odom);
    }
    stats_.matching_seconds += Seconds(start);
    return;
  }

  const Pose2 odom_step = last_odom_.Inverse() * scan.odom;
  const Pose2 predicted = tracked_ * odom_step;
  const IcpPrior prior = OdometryPrior(predicted, last_odom_, scan.odom);
  const IcpPrior* tracking_prior =
      config_.tracking_odometry_weight > 0 ? &prior : nullptr;
  last_odom_ = scan.odom;
  const double jump = config_.max_tracking_jump;
  // The constant-velocity prediction: the last tracked increment again.
  const Pose2 cv_predicted = tracked_ * velocity_;
  // No robot changes its motion between two scans by a tracking jump: such
  // an odometry increment is wrong (a jump, the catch-up after a freeze).
  const bool odometry_implausible =
      config_.robust_tracking && scans_.size() >= 2 &&
      !SmallMotion(odom_step, velocity_, jump, jump);
  MatchResult match;
  bool matched = false;
  bool odometry_rejected = false;
  if (points.size() >= 10 && !local_submap_.empty()) {
    auto good = [&](const MatchResult& m, const Pose2& from, double scale) {
      return m.success && m.fitness >= config_.min_tracking_fitness &&
             SmallMotion(m.pose, from, scale * jump, scale * jump);
    };
    // A match fits well when its fitness is not far below the recent ones.
    auto fits_well = [&](const MatchResult& m) {
      return !config_.robust_tracking ||
             m.fitness >= config_.tracking_recheck_ratio * recent_fitness_;
    };
    if (config_.always_correlative) {
      match = local_submap_.Match(
          points, odometry_implausible ? cv_predicted : predicted,
          config_.local_correlative, config_.icp);
      matched =
          good(match, odometry_implausible ? cv_predicted : predicted, 2.0);
    } else {
      match = local_submap_.Icp(points, predicted, config_.icp, tracking_prior);
      matched = good(match, predicted, 1.0);
      bool from_odometry = matched;
      if (config_.robust_tracking &&
          (odometry_implausible || !(matched && fits_well(match)))) {
        // The odometry may be wrong (frozen, jumping): also try the
        // constant-velocity prediction, pulled towards it with the
        // information of the last tracked motion, and keep the better fit
        // (by a margin in favour of the odometry, unless it is
        // implausible).
        ++stats_.tracking_rechecks;
        const IcpPrior cv_prior =
            OdometryPrior(cv_predicted, Pose2(), velocity_);
        const MatchResult cv = local_submap_.Icp(
            points, cv_predicted, config_.icp,
            config_.tracking_odometry_weight > 0 ? &cv_prior : nullptr);
        const double margin = config_.tracking_recheck_margin;
        if (good(cv, cv_predicted, 1.0) &&
            (!matched ||
             (odometry_implausible ? cv.fitness + margin >= match.fitness
                                   : cv.fitness > match.fitness + margin))) {
          match = cv;
          matched = true;
          from_odometry = false;
        }
      }
      if (!(matched && fits_well(match))) {
        ++stats_.tracking_correlative;
        const bool centre_odometry = from_odometry || !matched;
        const Pose2 centre = centre_odometry ? predicted : cv_predicted;
        const MatchResult second = local_submap_.Match(
            points, centre, config_.local_correlative, config_.icp);
        if (good(second, centre, 2.0) &&
            (!matched || second.fitness >
                             match.fitness + config_.tracking_recheck_margin)) {
          from_odometry = centre_odometry;
          match = second;
          matched = true;
        }
      }
      // A match seeded by a plausible odometry increment that lands where
      // that increment is unlikely, and does not fit well either: the
      // search slid into another optimum (ACES, a turn of 22 degrees in
      // one scan matched as 1 degree and a 0.75 m slide, fitness 0.179
      // against a running 0.256; the next scans followed it and the pass
      // was mapped 81 degrees off). The odometry's prediction is kept.
      if (config_.robust_tracking && matched && from_odometry &&
          !odometry_implausible && !fits_well(match) &&
          OdometryDisagreement(odom_step, tracked_.Inverse() * match.pose) >
              config_.odometry_break_chi2) {
        matched = false;
        ++stats_.tracking_slides_rejected;
      }
      // The scan disagrees with the odometry: the match came from another
      // prediction and lies where the odometry increment is unlikely.
      if (config_.robust_tracking && matched && !from_odometry) {
        if (OdometryDisagreement(odom_step, tracked_.Inverse() * match.pose) >
            config_.odometry_break_chi2) {
          odometry_rejected = true;
        }
      }
    }
  }
  if (!matched) ++stats_.tracking_failures;
  if (matched) {
    recent_fitness_ = scans_.size() <= 1
                          ? match.fitness
                          : 0.9 * recent_fitness_ + 0.1 * match.fitness;
  }
  if (odometry_rejected) {
    ++stats_.odometry_rejected;
    odometry_break_ = true;
  }
  const Pose2 previous = tracked_;
  tracked_ = matched ? match.pose : predicted;
  velocity_ = previous.Inverse() * tracked_;
  // Path length: the odometry's, unless it was rejected.
  path_ += odometry_rejected ? velocity_.t.norm() : odom_step.t.norm();
  if (config_.refine_scans) {
    scan_points_.push_back(points);
    scan_odom_.push_back(scan.odom);
  }
  stats_.matching_seconds += Seconds(start);

  const int last = static_cast<int>(keyframes_.size()) - 1;
  const Pose2 last_pose = KeyframePose(last);
  if (!SmallMotion(tracked_, last_pose, config_.keyframe_distance,
                   config_.keyframe_rotation)) {
    AddKeyframe(scan, points, matched ? &match : nullptr);
    const int k = static_cast<int>(keyframes_.size()) - 1;
    // The scans of keyframe `last` relative to the new keyframe, before an
    // optimization moves the two apart.
    const Pose2 k_inv = tracked_.Inverse();
    const double span =
        static_cast<double>(scan.stamp - keyframes_[last].stamp);
    for (auto s = scans_.rbegin(); s != scans_.rend() && s->keyframe == last;
         ++s) {
      s->relative_next = k_inv * (last_pose * s->relative);
      s->alpha =
          span > 0
              ? static_cast<double>(s->stamp - keyframes_[last].stamp) / span
              : 0.0;
      s->has_next = true;
    }
    scans_.push_back({scan.stamp, k, Pose2(), false, Pose2(), 0.0});
    if (config_.loop_closure) {
      const auto loop_start = std::chrono::steady_clock::now();
      if (DetectLoopClosures(k)) pending_loop_ = true;
      stats_.loop_seconds += Seconds(loop_start);
    }
    const bool loop_due = pending_loop_ && k - last_optimized_keyframe_ >=
                                               config_.loop_optimize_interval;
    const bool periodic =
        config_.optimize_every > 0 &&
        k - last_optimized_keyframe_ >= config_.optimize_every;
    if (loop_due || periodic) {
      OptimizeGraph(config_.incremental_iterations);
      pending_loop_ = false;
      last_optimized_keyframe_ = k;
    }
  } else {
    scans_.push_back({scan.stamp, last, last_pose.Inverse() * tracked_, false,
                      Pose2(), 0.0});
  }
}

void LaserSlam::AddKeyframe(const LaserScan& scan, const Points2& points,
                            const MatchResult* match) {
  const int k = static_cast<int>(keyframes_.size());
  Node* node = graph_.AddNode(Pose2Key(k), Pose2Value(tracked_));
  node->stamp = scan.stamp;
  node->has_stamp = true;
  if (k == 0) graph_.SetFixed(Pose2Key(0), true);
  Keyframe keyframe;
  keyframe.stamp = scan.stamp;
  keyframe.points = points;
  keyframe.odom = scan.odom;
  keyframe.path = path_;
  keyframe.odometry_break = odometry_break_;
  keyframes_.push_back(std::move(keyframe));
  odometry_break_ = false;
  ++stats_.keyframes;
  if (k > 0) {
    const Pose2 prev = KeyframePose(k - 1);
    if (match != nullptr) {
      AddBetween(k - 1, k, prev.Inverse() * tracked_, MatchCovariance(*match),
                 nullptr, false);
    }
    const OdometryDelta odom =
        OdometryMotion(keyframes_[k - 1].odom, scan.odom, config_.odometry);
    if (!keyframes_[k].odometry_break) {
      AddBetween(k - 1, k, odom.delta, odom.covariance, nullptr, false);
    } else if (match == nullptr) {
      // Nothing else joins k to k-1: keep the odometry, but so weak that
      // any other constraint overrides it.
      AddBetween(k - 1, k, odom.delta,
                 odom.covariance * (config_.odometry_break_inflation *
                                    config_.odometry_break_inflation),
                 nullptr, false);
      ++stats_.odometry_factors_weakened;
    } else {
      ++stats_.odometry_factors_dropped;
    }
  }
  if (config_.chain_links > 0) {
    keyframes_[k].target = std::make_shared<MatchTarget>();
    keyframes_[k].target->Build(VoxelFilter(points, config_.submap_voxel),
                                config_.icp.max_correspondence_distance,
                                config_.normal_radius);
    // Across rejected odometry the prior comes from the tracked motion.
    bool odometry_break = keyframes_[k].odometry_break;
    for (int m = k - 2; m >= std::max(0, k - 1 - config_.chain_links); --m) {
      odometry_break |= keyframes_[m + 1].odometry_break;
      const Pose2 relative = KeyframePose(m).Inverse() * tracked_;
      const IcpPrior prior =
          odometry_break
              ? OdometryPrior(relative, Pose2(), relative)
              : OdometryPrior(relative, keyframes_[m].odom, scan.odom);
      const MatchResult link =
          keyframes_[m].target->Icp(points, prior.pose, config_.icp, &prior);
      if (link.success && link.fitness >= config_.min_tracking_fitness &&
          SmallMotion(link.pose, prior.pose, config_.max_tracking_jump,
                      config_.max_tracking_jump)) {
        AddBetween(m, k, link.pose, MatchCovariance(link), nullptr, false);
      }
    }
  }
  RebuildLocalSubmap();
}

void LaserSlam::RebuildLocalSubmap() {
  const int n = static_cast<int>(keyframes_.size());
  Points2 world;
  for (int k = std::max(0, n - config_.submap_keyframes); k < n; ++k) {
    const Points2 p = TransformPoints(KeyframePose(k), keyframes_[k].points);
    world.insert(world.end(), p.begin(), p.end());
  }
  local_submap_.Build(VoxelFilter(world, config_.submap_voxel),
                      config_.icp.max_correspondence_distance,
                      config_.normal_radius);
}

bool LaserSlam::DetectLoopClosures(int k) {
  Keyframe& current = keyframes_[k];
  if (current.points.size() < 20) return false;
  if (config_.loop_every > 1 && k % config_.loop_every != 0) return false;
  const Pose2 pose_k = KeyframePose(k);
  struct Candidate {
    double distance;
    int index;
    double radius;
  };
  std::vector<Candidate> candidates;
  // Per older keyframe: the local search radius (drift bound).
  std::vector<double> radii(std::max(0, k - config_.submap_keyframes), -1.0);
  for (int j = 0; j < k - config_.submap_keyframes; ++j) {
    const double separation = current.path - keyframes_[j].path;
    if (separation < config_.loop_min_separation) continue;
    // Dead-reckoning drift grows with the path since j, or since the last
    // accepted closure (which re-anchored the recent trajectory), whichever
    // is shorter.
    const double drift_path =
        std::min(separation, current.path - last_closure_path_ +
                                 config_.loop_min_separation);
    const double radius = std::min(
        config_.loop_max_radius,
        config_.loop_search_radius + config_.loop_radius_growth * drift_path);
    radii[j] = radius;
    const double d = (KeyframePose(j).t - pose_k.t).norm();
    if (d <= radius && !PlaceSaturated(j)) candidates.push_back({d, j, radius});
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) {
              return a.distance < b.distance;
            });
  std::vector<Candidate> chosen;
  for (const Candidate& c : candidates) {
    if (static_cast<int>(chosen.size()) >= config_.loop_max_candidates) break;
    bool near_chosen = false;
    for (const Candidate& o : chosen) {
      near_chosen |=
          std::abs(o.index - c.index) <= 2 * config_.loop_submap_half_width;
    }
    if (!near_chosen) chosen.push_back(c);
  }
  const bool global = config_.loop_global;
  if (chosen.empty() && !global) return false;
  // Just closed against a place closed on an earlier visit: the estimate is
  // anchored to a well-connected map, ICP from it suffices.
  const bool anchored =
      current.path - anchored_from_path_ < config_.loop_anchored_path;
  // The query: the last loop_query_keyframes keyframes in k's frame, so that
  // both sides of the match are local maps of several metres.
  const Points2 query = VoxelFilter(
      KeyframeCloud(std::max(0, k - config_.loop_query_keyframes + 1), k,
                    pose_k.Inverse()),
      config_.loop_query_voxel);
  const Points2 search_query =
      config_.loop_search_voxel > config_.loop_query_voxel
          ? VoxelFilter(query, config_.loop_search_voxel)
          : query;
  if (global) current.context = MakeScanContext(query, config_.loop_context);
  bool significant = false;
  bool accepted = false;
  for (const Candidate& candidate : chosen) {
    // The search window covers the uncertainty the candidate was found with.
    CorrelativeOptions search = config_.loop_correlative;
    search.window_xy = std::max(search.window_xy, candidate.radius);
    const int j = candidate.index;
    const Pose2 pose_j = KeyframePose(j);
    // A closure accepted to the same place in the last
    // loop_consistency_keyframes keyframes predicts where k lies in j's
    // frame (through the current estimates of both neighbourhoods): ICP
    // from that prediction verifies the candidate, and the correlative
    // search runs only when it fails.
    const LoopHypothesis* seed = nullptr;
    if (config_.loop_seeded_verification && !anchored) {
      for (const LoopHypothesis& o : hypotheses_) {
        if (o.added && o.k != k &&
            std::abs(o.j - j) <= config_.loop_submap_half_width &&
            (seed == nullptr || o.k > seed->k)) {
          seed = &o;
        }
      }
    }
    bool passed = false;
    if (seed != nullptr) {
      const Pose2 predicted = pose_j.Inverse() * KeyframePose(seed->j) *
                              seed->z * KeyframePose(seed->k).Inverse() *
                              pose_k;
      ++stats_.seeded_verifications;
      accepted |= VerifyLoop(k, j, predicted, nullptr, false, query,
                             search_query, &significant, &passed);
      if (passed) continue;
    }
    accepted |= VerifyLoop(k, j, pose_j.Inverse() * pose_k,
                           anchored ? nullptr : &search, false, query,
                           search_query, &significant, &passed);
  }
  // Global search: the local searches have found nothing for
  // loop_global_min_path metres; the places outside their radius whose
  // Scan Context is nearest are verified over a wide window.
  const int loop_index = k / std::max(1, config_.loop_every);
  if (global && !accepted &&
      current.path - last_closure_path_ >= config_.loop_global_min_path &&
      loop_index % std::max(1, config_.loop_global_every) == 0) {
    std::vector<std::pair<double, int>> by_key;
    for (int j = 0; j < static_cast<int>(radii.size()); ++j) {
      if (radii[j] < 0 || keyframes_[j].context.empty() ||
          (KeyframePose(j).t - pose_k.t).norm() <= radii[j] ||
          PlaceSaturated(j)) {
        continue;
      }
      by_key.push_back(
          {RingKeyDistance(current.context, keyframes_[j].context), j});
    }
    const size_t preselect = std::min<size_t>(
        by_key.size(), std::max(1, config_.loop_global_preselect));
    std::partial_sort(by_key.begin(), by_key.begin() + preselect, by_key.end());
    struct Place {
      double distance;
      int index;
      double rotation;
    };
    std::vector<Place> places;
    for (size_t i = 0; i < preselect; ++i) {
      double rotation = 0.0;
      const double d = ScanContextDistance(
          current.context, keyframes_[by_key[i].second].context, &rotation);
      if (d <= config_.loop_global_max_distance) {
        places.push_back({d, by_key[i].second, rotation});
      }
    }
    std::sort(places.begin(), places.end(), [](const Place& a, const Place& b) {
      return a.distance < b.distance;
    });
    std::vector<int> tried;
    for (const Place& place : places) {
      if (static_cast<int>(tried.size()) >= config_.loop_global_candidates) {
        break;
      }
      bool near_tried = false;
      for (int o : tried) {
        near_tried |=
            std::abs(o - place.index) <= 2 * config_.loop_submap_half_width;
      }
      if (near_tried) continue;
      tried.push_back(place.index);
      CorrelativeOptions search = config_.loop_correlative;
      search.window_xy = config_.loop_global_window;
      // The descriptor's rotation is good to a sector: two sectors of
      // angular window suffice (0.21 rad with 60 sectors, not 0.35).
      search.window_theta =
          std::min(search.window_theta,
                   4.0 * M_PI / std::max(1, config_.loop_context.sectors));
      search.probe_evaluations = config_.loop_global_probe_evaluations;
      ++stats_.global_closures_proposed;
      bool passed = false;
      VerifyLoop(k, place.index, Pose2(0.0, 0.0, place.rotation), &search, true,
                 query, search_query, &significant, &passed);
    }
  }
  hypotheses_.erase(std::remove_if(hypotheses_.begin(), hypotheses_.end(),
                                   [&](const LoopHypothesis& o) {
                                     return k - o.k >
                                            config_.loop_consistency_keyframes;
                                   }),
                    hypotheses_.end());
  return significant;
}

bool LaserSlam::VerifyLoop(int k, int j, const Pose2& guess,
                           const CorrelativeOptions* search, bool global,
                           const Points2& query, const Points2& search_query,
                           bool* significant, bool* passed) {
  *passed = false;
  const Pose2 pose_k = KeyframePose(k);
  const Pose2 pose_j = KeyframePose(j);
  const Points2 submap =
      KeyframeCloud(std::max(0, j - config_.loop_submap_half_width),
                    std::min(k - config_.submap_keyframes,
                             j + config_.loop_submap_half_width),
                    pose_j.Inverse());
  auto clock = std::chrono::steady_clock::now();
  MatchTarget target;
  target.Build(VoxelFilter(submap, config_.submap_voxel),
               config_.icp.max_correspondence_distance, config_.normal_radius);
  stats_.loop_target_seconds += Seconds(clock);
  // The search on a sparser copy of the query (its cost is linear in the
  // points), ICP on the whole query.
  // Without a search (anchored), ICP alone may only correct the guess
  // slightly, as in the final pass.
  double score = 0.0;
  Pose2 coarse = guess;
  // The verified search's passing match (reused when it is the best pose).
  bool verified = false;
  Pose2 verified_pose;
  MatchResult verified_match;
  ++stats_.closures_proposed;
  if (search != nullptr) {
    // Only poses reaching loop_min_score can pass: the search prunes the
    // rest, and a candidate where none does is not refined.
    CorrelativeOptions options = *search;
    options.min_score = std::max(options.min_score, config_.loop_min_score);
    options.grid_margin = 0.0;  // The target is searched once.
    clock = std::chrono::steady_clock::now();
    CorrelativeWork work;
    // Verified search: the poses found reaching the score are matched by
    // ICP at once, until one passes; when loop_search_verifications have
    // failed, the place is taken to be wrong and the search stops (most
    // wrong places fail at their first such pose, and proving which pose
    // is best costs most of a search).
    int failed = 0;
    double icp_seconds = 0.0;
    const MatchTarget::Verifier verify = [&](const Pose2& pose, double s) {
      if (verified) return true;
      const auto icp_clock = std::chrono::steady_clock::now();
      MatchResult m = target.Icp(query, pose, config_.icp);
      icp_seconds += Seconds(icp_clock);
      m.score = s;
      verified = LoopMatchPasses(m, config_);
      if (verified) {
        verified_pose = pose;
        verified_match = m;
      }
      return verified || ++failed < config_.loop_search_verifications;
    };
    coarse = target.Correlative(
        search_query, guess, options, &score, &work,
        config_.loop_search_verifications > 0 ? &verify : nullptr);
    stats_.loop_correlative_seconds += Seconds(clock) - icp_seconds;
    stats_.loop_icp_seconds += icp_seconds;
    ++stats_.loop_searches;
    stats_.loop_search_evaluations += work.evaluations;
    stats_.loop_searches_verify_stopped += work.verify_stopped ? 1 : 0;
    if (global) {
      stats_.global_search_evaluations += work.evaluations;
      stats_.global_searches_probe_stopped += work.probe_stopped ? 1 : 0;
      stats_.global_searches_budget_stopped += work.budget_stopped ? 1 : 0;
    }
    if (score < config_.loop_min_score) return false;
  }
  clock = std::chrono::steady_clock::now();
  const bool reuse = verified && verified_pose.t == coarse.t &&
                     verified_pose.theta == coarse.theta;
  MatchResult match =
      reuse ? verified_match : target.Icp(query, coarse, config_.icp);
  stats_.loop_icp_seconds += Seconds(clock);
  match.score = score;
  if (search == nullptr) {
    LaserSlamConfig checks = config_;
    checks.loop_min_score = 0.0;
    if (!LoopMatchPasses(match, checks) ||
        !SmallMotion(match.pose, guess, config_.loop_final_max_correction,
                     config_.loop_final_max_correction)) {
      return false;
    }
  } else if (!LoopMatchPasses(match, config_)) {
    return false;
  }
  *passed = true;
  // Geometric consistency: the correction this closure implies (the
  // transform taking k's estimate to where the match puts it) must agree
  // with another recent keyframe's passing matches (global ones: with
  // loop_global_min_agreeing of them).
  LoopHypothesis h{k,
                   j,
                   match.pose,
                   match.covariance,
                   pose_j * match.pose * pose_k.Inverse(),
                   false,
                   global};
  // A correction the chi2 test has undone recently is not tried again.
  for (const auto& [when, correction] : undone_corrections_) {
    const Pose2 diff = CorrectionDifference(correction, h.correction, pose_k);
    if (k - when <= config_.loop_undone_memory &&
        diff.t.norm() <= config_.loop_consistency_distance * 10 &&
        std::abs(diff.theta) <= config_.loop_consistency_angle * 10) {
      return false;
    }
  }
  std::vector<LoopHypothesis*> agreeing;
  for (LoopHypothesis& other : hypotheses_) {
    if (k - other.k > config_.loop_consistency_keyframes || other.k == k) {
      continue;
    }
    const Pose2 diff =
        CorrectionDifference(other.correction, h.correction, pose_k);
    if (diff.t.norm() <= config_.loop_consistency_distance &&
        std::abs(diff.theta) <= config_.loop_consistency_angle) {
      agreeing.push_back(&other);
    }
  }
  bool any_global = global;
  for (const LoopHypothesis* other : agreeing) any_global |= other->global;
  const size_t needed =
      any_global ? std::max(1, config_.loop_global_min_agreeing) : 1;
  if (agreeing.size() < needed) {
    hypotheses_.push_back(h);
    return false;
  }
  agreeing.push_back(&h);
  const LaserSlamStats stats_before = stats_;
  // Whether the place was closed on an earlier visit (a closure from a
  // keyframe more than loop_min_separation of path before k).
  bool place_closed = false;
  for (int m = std::max(0, j - config_.loop_submap_half_width);
       m <= std::min(k, j + config_.loop_submap_half_width); ++m) {
    place_closed |= keyframes_[m].first_closed_path <
                    keyframes_[k].path - config_.loop_min_separation;
  }
  for (LoopHypothesis* a : agreeing) {
    if (a->added) continue;
    const Pose2 before = KeyframePose(a->k);
    const Pose2 after = KeyframePose(a->j) * a->z;
    *significant |= NoteCorrection(before, after);
    // A large correction (a global closure, or drift the local search
    // caught) lies far outside the robust kernel's width: the first
    // optimization applies it without the kernel, and the chi2 test of
    // ApplyPlainClosures decides whether it stays.
    const bool plain = !SmallMotion(before, after, 2.0, 0.35);
    const FactorId id =
        AddBetween(a->j, a->k, a->z, MatchCovariance(*a),
                   plain ? nullptr : MakeLoss(config_.loop_kernel), true);
    if (plain && id >= 0) plain_closures_.push_back({id, *a});
    a->added = true;
    ++stats_.closures_accepted;
    if (a->global) ++stats_.global_closures_accepted;
    double& first = keyframes_[a->j].first_closed_path;
    first = std::min(first, keyframes_[a->k].path);
  }
  hypotheses_.push_back(h);
  if (!plain_closures_.empty()) {
    // Optimize now: each group of large corrections is tested on its own.
    const auto chi2_start = std::chrono::steady_clock::now();
    const bool kept = ApplyPlainClosures();
    stats_.loop_chi2_seconds += Seconds(chi2_start);
    if (!kept) {
      // Undone: neither counted nor kept as evidence for later matches.
      undone_corrections_.emplace_back(k, h.correction);
      undone_corrections_.erase(
          std::remove_if(undone_corrections_.begin(), undone_corrections_.end(),
                         [&](const std::pair<int, Pose2>& u) {
                           return k - u.first > config_.loop_undone_memory;
                         }),
          undone_corrections_.end());
      stats_.largest_correction_m = stats_before.largest_correction_m;
      stats_.largest_correction_deg = stats_before.largest_correction_deg;
      hypotheses_.erase(
          std::remove_if(hypotheses_.begin(), hypotheses_.end(),
                         [](const LoopHypothesis& o) { return o.added; }),
          hypotheses_.end());
      return false;
    }
    *significant = false;
  }
  last_closure_path_ = keyframes_[k].path;
  if (place_closed) anchored_from_path_ = keyframes_[k].path;
  return true;
}

int LaserSlam::ChainLinks() const {
  // Breadth-first search over the keyframes joined by scan-match and
  // odometry factors (no loop closures: the kernel may have switched an
  // earlier one off, and the drift to correct accumulated along the
  // chain), from each closure's keyframe j to its k.
  const int n = static_cast<int>(keyframes_.size());
  std::vector<FactorId> loops = loop_factors_;
  std::sort(loops.begin(), loops.end());
  std::vector<std::vector<int>> neighbours(n);
  for (const auto& [id, factor] : graph_.factors()) {
    if (std::binary_search(loops.begin(), loops.end(), id) ||
        factor.keys.size() != 2) {
      continue;
    }
    const int64_t a = factor.keys[0].id, b = factor.keys[1].id;
    if (a < 0 || b < 0 || a >= n || b >= n) continue;
    neighbours[a].push_back(static_cast<int>(b));
    neighbours[b].push_back(static_cast<int>(a));
  }
  int shortest = n;
  std::vector<int> hops(n);
  std::vector<int> queue;
  for (const auto& [id, h] : plain_closures_) {
    std::fill(hops.begin(), hops.end(), -1);
    queue.assign(1, h.j);
    hops[h.j] = 0;
    for (size_t q = 0; q < queue.size() && hops[h.k] < 0; ++q) {
      for (int m : neighbours[queue[q]]) {
        if (hops[m] >= 0) continue;
        hops[m] = hops[queue[q]] + 1;
        queue.push_back(m);
      }
    }
    if (hops[h.k] >= 0) shortest = std::min(shortest, hops[h.k]);
  }
  return shortest;
}

bool LaserSlam::ApplyPlainClosures() {
  // The chi2 of every other factor (robustified where it has a kernel):
  // how much the closures make the rest of the graph bend.
  auto rest_chi2 = [&]() {
    double sum = 0.0;
    for (const auto& [id, factor] : graph_.factors()) {
      bool plain = false;
      for (const auto& p : plain_closures_) plain |= p.first == id;
      double chi2 = 0.0;
      if (plain || !graph_.FactorChi2(factor, &chi2)) continue;
      double rho[3] = {chi2, 1.0, 0.0};
      if (factor.loss) factor.loss->Evaluate(chi2, rho);
      sum += rho[0];
    }
    return sum;
  };
  const int n = static_cast<int>(keyframes_.size());
  std::vector<std::vector<double>> saved(n);
  for (int k = 0; k < n; ++k) saved[k] = graph_.FindNode(Pose2Key(k))->value;
  const Pose2 saved_tracked = tracked_;
  const double before = rest_chi2();
  OptimizeGraph(0);
  const double increase = rest_chi2() - before;
  last_optimized_keyframe_ = n - 1;
  pending_loop_ = false;
  // The bound grows with the links of the chain the closures bend:
  // a true correction of drift accumulated over many overconfident factors
  // bends each of them a little, a wrong one bends them a lot.
  const bool keep =
      increase <= std::max(config_.loop_global_max_chi2,
                           config_.loop_max_chi2_per_link * ChainLinks());
  for (const auto& [id, h] : plain_closures_) {
    if (graph_.FindFactor(id) == nullptr) continue;
    graph_.RemoveFactor(id);
    loop_factors_.erase(
        std::remove(loop_factors_.begin(), loop_factors_.end(), id),
        loop_factors_.end());
    --keyframes_[h.j].closures;
    --keyframes_[h.k].closures;
    if (keep) {
      AddBetween(h.j, h.k, h.z, MatchCovariance(h),
                 MakeLoss(config_.loop_kernel), true);
    } else {
      --stats_.closures_accepted;
      if (h.global) --stats_.global_closures_accepted;
      ++stats_.closures_reverted;
    }
  }
  plain_closures_.clear();
  if (keep) {
    OptimizeGraph(0);
    return true;
  }
  // The closures would bend the graph beyond what its factors allow: a
  // wrong match; the graph returns to where it was.
  for (int k = 0; k < n; ++k) {
    std::vector<double>& value = graph_.FindNode(Pose2Key(k))->value;
    std::copy(saved[k].begin(), saved[k].end(), value.begin());
  }
  tracked_ = saved_tracked;
  RebuildLocalSubmap();
  return false;
}

void LaserSlam::OptimizeGraph(int max_iterations) {
  if (graph_.NumFactors() == 0) return;
  const auto start = std::chrono::steady_clock::now();
  const int last = static_cast<int>(keyframes_.size()) - 1;
  const Pose2 relative = KeyframePose(last).Inverse() * tracked_;
  OptimizerOptions options = config_.optimizer;
  options.verbose = false;
  if (max_iterations > 0) options.max_iterations = max_iterations;
  Optimize(&graph_, options, nullptr);
  ++stats_.optimizations;
  tracked_ = KeyframePose(last) * relative;
  RebuildLocalSubmap();
  stats_.optimization_seconds += Seconds(start);
}

Points2 LaserSlam::KeyframeCloud(int lo, int hi, const Pose2& frame_inv) const {
  Points2 cloud;
  for (int m = lo; m <= hi; ++m) {
    const Points2 p =
        TransformPoints(frame_inv * KeyframePose(m), keyframes_[m].points);
    cloud.insert(cloud.end(), p.begin(), p.end());
  }
  return cloud;
}

void LaserSlam::Finish() {
  if (keyframes_.empty()) return;
  OptimizeGraph(0);
  RejectClosures();
  if (config_.loop_closure && config_.loop_final_pass) {
    const auto start = std::chrono::steady_clock::now();
    CloseLoopsFinal();
    stats_.loop_seconds += Seconds(start);
    stats_.loop_final_seconds += Seconds(start);
    if (stats_.final_closures_accepted > 0) {
      OptimizeGraph(0);
      RejectClosures();
    }
  }
  if (config_.refine_scans) RefineScans();
}

void LaserSlam::CloseLoopsFinal() {
  const int n = static_cast<int>(keyframes_.size());
  std::vector<Pose2> poses(n);
  for (int k = 0; k < n; ++k) poses[k] = KeyframePose(k);
  // The correlative score is not computed here: ICP starts from the
  // optimized estimate and may only correct it slightly.
  LaserSlamConfig checks = config_;
  checks.loop_min_score = 0.0;
  const double r2 = config_.loop_final_radius * config_.loop_final_radius;
  const int step = std::max(1, config_.loop_every);
  for (int k = 0; k < n; k += step) {
    if (keyframes_[k].points.size() < 20) continue;
    std::vector<std::pair<double, int>> candidates;
    for (int j = 0; j < k - config_.submap_keyframes; ++j) {
      if (keyframes_[k].path - keyframes_[j].path <
          config_.loop_min_separation) {
        continue;
      }
      const double d2 = (poses[j].t - poses[k].t).squaredNorm();
      if (d2 <= r2 && !PlaceSaturated(j)) candidates.push_back({d2, j});
    }
    if (candidates.empty()) continue;
    std::sort(candidates.begin(), candidates.end());
    std::vector<int> chosen;
    for (const auto& c : candidates) {
      if (static_cast<int>(chosen.size()) >= config_.loop_max_candidates) break;
      bool near_chosen = false;
      for (int o : chosen) {
        near_chosen |=
            std::abs(o - c.second) <= 2 * config_.loop_submap_half_width;
      }
      if (!near_chosen) chosen.push_back(c.second);
    }
    const Points2 query = VoxelFilter(
        KeyframeCloud(std::max(0, k - config_.loop_query_keyframes + 1), k,
                      poses[k].Inverse()),
        config_.loop_query_voxel);
    for (int j : chosen) {
      const Pose2 j_inv = poses[j].Inverse();
      MatchTarget target;
      target.Build(
          VoxelFilter(
              KeyframeCloud(std::max(0, j - config_.loop_submap_half_width),
                            std::min(k - config_.submap_keyframes,
                                     j + config_.loop_submap_half_width),
                            j_inv),
              config_.submap_voxel),
          config_.icp.max_correspondence_distance, config_.normal_radius);
      const Pose2 initial = j_inv * poses[k];
      const MatchResult match = target.Icp(query, initial, config_.icp);
      ++stats_.final_closures_proposed;
      if (!LoopMatchPasses(match, checks) ||
          !SmallMotion(match.pose, initial, config_.loop_final_max_correction,
                       config_.loop_final_max_correction)) {
        continue;
      }
      AddBetween(j, k, match.pose, MatchCovariance(match),
                 MakeLoss(config_.loop_kernel), true);
      NoteCorrection(poses[k], poses[j] * match.pose);
      ++stats_.final_closures_accepted;
    }
  }
}

void LaserSlam::RejectClosures() {
  // Closures the robust kernel has switched off.
  std::vector<FactorId> rejected;
  for (FactorId id : loop_factors_) {
    const Factor* factor = graph_.FindFactor(id);
    double chi2 = 0.0;
    if (factor == nullptr || !graph_.FactorChi2(*factor, &chi2)) continue;
    double rho[3] = {chi2, 1.0, 0.0};
    if (factor->loss) factor->loss->Evaluate(chi2, rho);
    if (rho[1] < config_.loop_reject_weight) rejected.push_back(id);
  }
  stats_.closures_rejected += static_cast<int>(rejected.size());
  if (!rejected.empty()) {
    for (FactorId id : rejected) graph_.RemoveFactor(id);
    loop_factors_.erase(
        std::remove_if(loop_factors_.begin(), loop_factors_.end(),
                       [&](FactorId id) { return !graph_.FindFactor(id); }),
        loop_factors_.end());
    OptimizeGraph(0);
  }
}

void LaserSlam::RefineScans() {
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(keyframes_.size());
  std::vector<Pose2> poses(n);
  for (int k = 0; k < n; ++k) poses[k] = KeyframePose(k);
  const double r2 = config_.refine_radius * config_.refine_radius;
  size_t s = 0;
  for (int k = 0; k < n; ++k) {
    const size_t first = s;
    while (s < scans_.size() && scans_[s].keyframe == k) ++s;
    if (s == first) continue;
    Points2 world;
    auto add = [&](int m) {
      const Points2 p = TransformPoints(poses[m], keyframes_[m].points);
      world.insert(world.end(), p.begin(), p.end());
    };
    const int lo = std::max(0, k - config_.refine_window);
    const int hi = std::min(n - 1, k + config_.refine_window);
    for (int m = lo; m <= hi; ++m) {
      if (m != k) add(m);
    }
    if (config_.refine_radius > 0) {
      for (int m = 0; m < n; ++m) {
        if ((m < lo || m > hi) &&
            (poses[m].t - poses[k].t).squaredNorm() <= r2) {
          add(m);
        }
      }
    }
    MatchTarget target;
    target.Build(VoxelFilter(world, config_.submap_voxel),
                 config_.icp.max_correspondence_distance,
                 config_.normal_radius);
    const Pose2 k_inv = poses[k].Inverse();
    for (size_t i = first; i < s; ++i) {
      if (scan_points_[i].size() < 10) continue;
      const Pose2 current = ScanPose(i);
      const IcpPrior prior =
          OdometryPrior(current, keyframes_[k].odom, scan_odom_[i]);
      const MatchResult m =
          target.Icp(scan_points_[i], current, config_.icp, &prior);
      if (m.success && m.fitness >= config_.min_tracking_fitness &&
          SmallMotion(m.pose, current, config_.refine_max_jump,
                      config_.refine_max_jump)) {
        scans_[i].relative = k_inv * m.pose;
        scans_[i].has_next = false;
        ++stats_.scans_refined;
      }
    }
  }
  stats_.refine_seconds += Seconds(start);
}

Pose2 LaserSlam::ScanPose(size_t i) const {
  const ScanRecord& s = scans_[i];
  Pose2 pose = KeyframePose(s.keyframe) * s.relative;
  if (config_.interpolate_scans && s.has_next) {
    const Pose2 next = KeyframePose(s.keyframe + 1) * s.relative_next;
    const Pose2 d = pose.Inverse() * next;
    pose =
        pose * Pose2(s.alpha * d.t.x(), s.alpha * d.t.y(), s.alpha * d.theta);
  }
  return pose;
}

Trajectory LaserSlam::ScanTrajectory() const {
  Trajectory out;
  out.reserve(scans_.size());
  for (size_t i = 0; i < scans_.size(); ++i) {
    out.push_back({scans_[i].stamp, LiftPose2(ScanPose(i))});
  }
  return out;
}

}  // namespace slam
