#include "apps/visual/loops_config.h"

#include <cmath>
#include <sstream>

#include "apps/yaml_config.h"

namespace slam {
namespace {

const char* VerificationName(bow::Verification v) {
  switch (v) {
    case bow::Verification::kNone:
      return "none";
    case bow::Verification::kFundamental:
      return "fundamental";
    case bow::Verification::kStereoPnp:
      return "stereo_pnp";
  }
  return "none";
}

}  // namespace

bool ReadLoopsConfig(const YAML::Node& node, const std::string& where,
                     LoopsConfig* config, std::string* error) {
  if (!CheckKnownKeys(node,
                      {"vocabulary",
                       "vocabulary_k",
                       "vocabulary_levels",
                       "descriptors_per_word",
                       "vocabulary_max_descriptors",
                       "orb_features",
                       "exclude_recent",
                       "max_query_results",
                       "direct_index_levels_up",
                       "min_prior_score",
                       "prior_keyframes",
                       "min_normalized_score",
                       "max_island_gap",
                       "min_consistent_queries",
                       "max_island_distance",
                       "max_query_gap",
                       "verification",
                       "match_max_hamming",
                       "match_ratio",
                       "fundamental_min_inliers",
                       "fundamental_error_px",
                       "pnp_min_inliers",
                       "pnp_error_px",
                       "pnp_min_pixel_sigma"},
                      where, error)) {
    return false;
  }
  bow::LoopDetectorConfig& d = config->detector;
  std::string verification = VerificationName(d.verification);
  if (!ReadOptional(node, "vocabulary", where, &config->vocabulary, error) ||
      !ReadOptional(node, "vocabulary_k", where, &config->vocabulary_k,
                    error) ||
      !ReadOptional(node, "vocabulary_levels", where,
                    &config->vocabulary_levels, error) ||
      !ReadOptional(node, "descriptors_per_word", where,
                    &config->descriptors_per_word, error) ||
      !ReadOptional(node, "vocabulary_max_descriptors", where,
                    &config->vocabulary_max_descriptors, error) ||
      !ReadOptional(node, "orb_features", where, &config->orb_features,
                    error) ||
      !ReadOptional(node, "exclude_recent", where, &d.exclude_recent, error) ||
      !ReadOptional(node, "max_query_results", where, &d.max_query_results,
                    error) ||
      !ReadOptional(node, "direct_index_levels_up", where,
                    &d.direct_index_levels_up, error) ||
      !ReadOptional(node, "min_prior_score", where, &d.min_prior_score,
                    error) ||
      !ReadOptional(node, "prior_keyframes", where, &d.prior_keyframes,
                    error) ||
      !ReadOptional(node, "min_normalized_score", where,
                    &d.min_normalized_score, error) ||
      !ReadOptional(node, "max_island_gap", where, &d.max_island_gap, error) ||
      !ReadOptional(node, "min_consistent_queries", where,
                    &d.min_consistent_queries, error) ||
      !ReadOptional(node, "max_island_distance", where, &d.max_island_distance,
                    error) ||
      !ReadOptional(node, "max_query_gap", where, &d.max_query_gap, error) ||
      !ReadOptional(node, "verification", where, &verification, error) ||
      !ReadOptional(node, "match_max_hamming", where, &d.matching.max_hamming,
                    error) ||
      !ReadOptional(node, "match_ratio", where, &d.matching.ratio, error) ||
      !ReadOptional(node, "fundamental_min_inliers", where,
                    &d.fundamental.min_inliers, error) ||
      !ReadOptional(node, "fundamental_error_px", where,
                    &d.fundamental.epipolar_error_px, error) ||
      !ReadOptional(node, "pnp_min_inliers", where, &d.stereo.min_inliers,
                    error) ||
      !ReadOptional(node, "pnp_error_px", where,
                    &d.stereo.reprojection_error_px, error) ||
      !ReadOptional(node, "pnp_min_pixel_sigma", where,
                    &d.stereo.min_pixel_sigma, error)) {
    return false;
  }
  if (verification == "none") {
    d.verification = bow::Verification::kNone;
  } else if (verification == "fundamental") {
    d.verification = bow::Verification::kFundamental;
  } else if (verification == "stereo_pnp") {
    d.verification = bow::Verification::kStereoPnp;
  } else {
    *error = where + ": loops.verification '" + verification +
             "' is not one of none, fundamental, stereo_pnp";
    return false;
  }
  if (!ValidateLoopsConfig(*config, error)) {
    *error = where + ": loops." + *error;
    return false;
  }
  return true;
}

bool LoadLoopsConfig(const std::string& path, LoopsConfig* config,
                     std::string* error) {
  YAML::Node root;
  if (!LoadYamlFile(path, &root, error)) return false;
  if (!root || root.IsNull()) return true;
  if (!CheckTopLevelSections(root, path, error)) return false;
  const YAML::Node node = root["loops"];
  if (!node) return true;
  return ReadLoopsConfig(node, path, config, error);
}

bool ValidateLoopsConfig(const LoopsConfig& config, std::string* error) {
  const bow::LoopDetectorConfig& d = config.detector;
  auto fail = [&](const std::string& message) {
    *error = message;
    return false;
  };
  if (config.vocabulary_k < 2 || config.vocabulary_k > 64)
    return fail("vocabulary_k must be in [2, 64]");
  if (config.vocabulary_levels < 0 || config.vocabulary_levels > 8)
    return fail("vocabulary_levels must be in [0, 8] (0: automatic)");
  if (config.descriptors_per_word < 1)
    return fail("descriptors_per_word must be >= 1");
  if (config.vocabulary_max_descriptors < 0)
    return fail("vocabulary_max_descriptors must be >= 0 (0: all)");
  if (config.orb_features < 10 || config.orb_features > 100000)
    return fail("orb_features must be in [10, 100000]");
  if (d.exclude_recent < 0) return fail("exclude_recent must be >= 0");
  if (d.max_query_results < 1) return fail("max_query_results must be >= 1");
  if (d.direct_index_levels_up < 0)
    return fail("direct_index_levels_up must be >= 0");
  if (!(d.min_prior_score >= 0.0 && d.min_prior_score <= 1.0))
    return fail("min_prior_score must be in [0, 1]");
  if (d.prior_keyframes < 1) return fail("prior_keyframes must be >= 1");
  if (!(d.min_normalized_score >= 0.0) ||
      !std::isfinite(d.min_normalized_score))
    return fail("min_normalized_score must be >= 0");
  if (d.max_island_gap < 1) return fail("max_island_gap must be >= 1");
  if (d.min_consistent_queries < 1)
    return fail("min_consistent_queries must be >= 1");
  if (d.max_island_distance < 0)
    return fail("max_island_distance must be >= 0");
  if (d.max_query_gap < 1) return fail("max_query_gap must be >= 1");
  if (d.matching.max_hamming < 0 || d.matching.max_hamming > 256)
    return fail("match_max_hamming must be in [0, 256]");
  if (!(d.matching.ratio > 0.0 && d.matching.ratio <= 1.0))
    return fail("match_ratio must be in (0, 1]");
  if (d.fundamental.min_inliers < 8)
    return fail("fundamental_min_inliers must be >= 8");
  if (!(d.fundamental.epipolar_error_px > 0.0))
    return fail("fundamental_error_px must be > 0");
  if (d.stereo.min_inliers < 6) return fail("pnp_min_inliers must be >= 6");
  if (!(d.stereo.reprojection_error_px > 0.0))
    return fail("pnp_error_px must be > 0");
  if (!(d.stereo.min_pixel_sigma > 0.0))
    return fail("pnp_min_pixel_sigma must be > 0");
  return true;
}

std::string LoopsConfigToYaml(const LoopsConfig& config) {
  const bow::LoopDetectorConfig& d = config.detector;
  std::ostringstream out;
  out.precision(17);
  out << "loops:\n"
      << "  vocabulary: \"" << config.vocabulary << "\"\n"
      << "  vocabulary_k: " << config.vocabulary_k << "\n"
      << "  vocabulary_levels: " << config.vocabulary_levels << "\n"
      << "  descriptors_per_word: " << config.descriptors_per_word << "\n"
      << "  vocabulary_max_descriptors: " << config.vocabulary_max_descriptors
      << "\n"
      << "  orb_features: " << config.orb_features << "\n"
      << "  exclude_recent: " << d.exclude_recent << "\n"
      << "  max_query_results: " << d.max_query_results << "\n"
      << "  direct_index_levels_up: " << d.direct_index_levels_up << "\n"
      << "  min_prior_score: " << d.min_prior_score << "\n"
      << "  prior_keyframes: " << d.prior_keyframes << "\n"
      << "  min_normalized_score: " << d.min_normalized_score << "\n"
      << "  max_island_gap: " << d.max_island_gap << "\n"
      << "  min_consistent_queries: " << d.min_consistent_queries << "\n"
      << "  max_island_distance: " << d.max_island_distance << "\n"
      << "  max_query_gap: " << d.max_query_gap << "\n"
      << "  verification: " << VerificationName(d.verification) << "\n"
      << "  match_max_hamming: " << d.matching.max_hamming << "\n"
      << "  match_ratio: " << d.matching.ratio << "\n"
      << "  fundamental_min_inliers: " << d.fundamental.min_inliers << "\n"
      << "  fundamental_error_px: " << d.fundamental.epipolar_error_px << "\n"
      << "  pnp_min_inliers: " << d.stereo.min_inliers << "\n"
      << "  pnp_error_px: " << d.stereo.reprojection_error_px << "\n"
      << "  pnp_min_pixel_sigma: " << d.stereo.min_pixel_sigma << "\n";
  return out.str();
}

}  // namespace slam
