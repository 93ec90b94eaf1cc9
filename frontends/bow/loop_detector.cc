#include "frontends/bow/loop_detector.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace slam::bow {

const char* LoopStatusName(LoopStatus status) {
  switch (status) {
    case LoopStatus::kTooEarly:
      return "too_early";
    case LoopStatus::kLowPriorScore:
      return "low_prior_score";
    case LoopStatus::kNoCandidate:
      return "no_candidate";
    case LoopStatus::kNotConsistent:
      return "not_consistent";
    case LoopStatus::kVerificationFailed:
      return "verification_failed";
    case LoopStatus::kAccepted:
      return "accepted";
  }
  return "unknown";
}

int MinKeyframesForALoop(const LoopDetectorConfig& config) {
  // The query of index i has candidates 0..i-1-exclude_recent (Process).
  return config.exclude_recent + 2;
}

LoopDetector::LoopDetector(const Vocabulary* vocabulary,
                           const LoopDetectorConfig& config)
    : vocabulary_(vocabulary), config_(config), database_(vocabulary) {}

LoopResult LoopDetector::Process(LoopKeyframe keyframe) {
  const auto start = std::chrono::steady_clock::now();
  LoopResult result;
  result.query_id = keyframe.id;
  BowVector bow;
  FeatureVector features;
  vocabulary_->Transform(keyframe.descriptors, config_.direct_index_levels_up,
                         &bow, &features);
  const int64_t index = static_cast<int64_t>(keyframes_.size());
  const int64_t max_entry = index - 1 - config_.exclude_recent;

  // Entries store the keyframe; the detection works on entry indices.
  // A query without island leaves the chain as it is; the next island is
  // compared with the last one if that is at most max_query_gap back.
  auto finish = [&](LoopResult r) {
    database_.Add(std::move(bow), std::move(features));
    keyframes_.push_back(std::move(keyframe));
    return r;
  };

  if (max_entry < 0) return finish(result);
  // The prior score: how alike views of one place are right now, the best
  // score against the last prior_keyframes keyframes (one blank or blurred
  // keyframe then does not blind the next query).
  double prior = 0.0;
  for (int64_t k = index - 1; k >= 0 && k >= index - config_.prior_keyframes;
       --k) {
    prior = std::max(prior, ScoreL1(bow, database_.bow(k)));
  }
  if (prior < config_.min_prior_score) {
    result.status = LoopStatus::kLowPriorScore;
    return finish(result);
  }
  std::vector<QueryResult> found =
      database_.Query(bow, config_.max_query_results, max_entry);
  result.database_ms = std::chrono::duration<double, std::milli>(
                           std::chrono::steady_clock::now() - start)
                           .count();
  std::vector<QueryResult> kept;
  for (const QueryResult& r : found) {
    if (r.score / prior >= config_.min_normalized_score) kept.push_back(r);
  }
  if (kept.empty()) {
    result.status = LoopStatus::kNoCandidate;
    if (!found.empty()) {
      result.candidate_id = keyframes_[found[0].entry].id;
      result.score = found[0].score;
      result.normalized_score = found[0].score / prior;
    }
    return finish(result);
  }
  // Islands: runs of entries at most max_island_gap apart; the best has the
  // largest summed score.
  std::sort(kept.begin(), kept.end(),
            [](const QueryResult& a, const QueryResult& b) {
              return a.entry < b.entry;
            });
  double best_sum = -1.0;
  size_t best_begin = 0, best_end = 0;
  for (size_t begin = 0; begin < kept.size();) {
    size_t end = begin + 1;
    double sum = kept[begin].score;
    while (end < kept.size() &&
           static_cast<int64_t>(kept[end].entry) -
                   static_cast<int64_t>(kept[end - 1].entry) <=
               config_.max_island_gap) {
      sum += kept[end].score;
      ++end;
    }
    if (sum > best_sum) {
      best_sum = sum;
      best_begin = begin;
      best_end = end;
    }
    begin = end;
  }
  size_t best = best_begin;
  for (size_t i = best_begin; i < best_end; ++i)
    if (kept[i].score > kept[best].score) best = i;
  const int64_t first = kept[best_begin].entry;
  const int64_t last = kept[best_end - 1].entry;
  const EntryId candidate = kept[best].entry;
  result.candidate_id = keyframes_[candidate].id;
  result.island_first = keyframes_[first].id;
  result.island_last = keyframes_[last].id;
  result.score = kept[best].score;
  result.normalized_score = kept[best].score / prior;

  // Temporal consistency with the previous query's island.
  const int64_t gap =
      std::max<int64_t>(0, std::max(first - last_last_, last_first_ - last));
  if (last_query_ >= 0 && index - last_query_ <= config_.max_query_gap &&
      gap <= config_.max_island_distance) {
    ++consistent_;
  } else {
    consistent_ = 1;
  }
  last_query_ = index;
  last_first_ = first;
  last_last_ = last;
  result.consistent_queries = consistent_;
  if (consistent_ < config_.min_consistent_queries) {
    result.status = LoopStatus::kNotConsistent;
    return finish(result);
  }
  result.status = Verify(keyframe, features, candidate, &result)
                      ? LoopStatus::kAccepted
                      : LoopStatus::kVerificationFailed;
  return finish(result);
}

bool LoopDetector::Verify(const LoopKeyframe& query,
                          const FeatureVector& query_features, size_t candidate,
                          LoopResult* result) const {
  if (config_.verification == Verification::kNone) return true;
  const LoopKeyframe& other = keyframes_[candidate];
  const std::vector<cv::DMatch> matches =
      MatchDescriptors(query.descriptors, other.descriptors, &query_features,
                       &database_.features(candidate), config_.matching);
  if (config_.verification == Verification::kFundamental) {
    std::vector<cv::Point2f> q, c;
    for (const cv::DMatch& m : matches) {
      if (m.queryIdx >= static_cast<int>(query.keypoints.size()) ||
          m.trainIdx >= static_cast<int>(other.keypoints.size()))
        continue;
      q.push_back(query.keypoints[m.queryIdx].pt);
      c.push_back(other.keypoints[m.trainIdx].pt);
    }
    const FundamentalVerification v =
        VerifyFundamental(q, c, config_.fundamental);
    result->matches = v.matches;
    result->inliers = v.inliers;
    return v.success;
  }
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  for (const cv::DMatch& m : matches) {
    if (m.queryIdx >= static_cast<int>(query.keypoints.size()) ||
        m.trainIdx >= static_cast<int>(other.points.size()))
      continue;
    const Eigen::Vector3d& p = other.points[m.trainIdx];
    if (!p.allFinite() || p.z() <= 0.0) continue;
    points.push_back(p);
    const cv::Point2f& px = query.keypoints[m.queryIdx].pt;
    pixels.emplace_back(px.x, px.y);
  }
  const StereoVerification v =
      VerifyStereoPnp(points, pixels, config_.camera, config_.stereo);
  result->matches = v.matches;
  result->inliers = v.inliers;
  if (!v.success) return false;
  result->has_pose = true;
  result->T_candidate_query = v.T_candidate_query;
  result->covariance = v.covariance;
  return true;
}

}  // namespace slam::bow
