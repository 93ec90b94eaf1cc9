// Place recognition settings of the visual pipelines (frontends/bow/): the
// vocabulary (a file, or one trained on the sequence's own descriptors) and
// the loop detector. `slam loops` and the visual SLAM pipeline
// (visual_slam.h) share them; apps/visual/loops_config.h reads them from
// the `loops:` section of a YAML file.
#ifndef SLAM_FRONTENDS_VISUAL_PLACE_RECOGNITION_H_
#define SLAM_FRONTENDS_VISUAL_PLACE_RECOGNITION_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "frontends/bow/loop_detector.h"
#include "frontends/bow/vocabulary.h"

namespace slam {

struct LoopsConfig {
  std::string vocabulary;  // Empty: self-trained.
  int vocabulary_k = 10;
  int vocabulary_levels = 0;  // 0: automatic (see VocabularyLevelsFor).
  int descriptors_per_word = 20;
  int64_t vocabulary_max_descriptors = 200000;
  int orb_features = 1000;
  bow::LoopDetectorConfig detector;
};

// The levels of a self-trained vocabulary for `num_descriptors`: the largest
// L <= 5 with k^L * descriptors_per_word <= num_descriptors (at least 1).
int VocabularyLevelsFor(const LoopsConfig& config, size_t num_descriptors);

// Trains the self-trained vocabulary of `config` (k = vocabulary_k, levels
// by VocabularyLevelsFor of the descriptors clustered, at most
// vocabulary_max_descriptors evenly subsampled) on `descriptors` (ORB rows;
// `count` rows in all).
bool TrainVocabulary(const LoopsConfig& config,
                     const std::vector<cv::Mat>& descriptors, size_t count,
                     bow::Vocabulary* vocabulary, std::string* error);

}  // namespace slam

#endif  // SLAM_FRONTENDS_VISUAL_PLACE_RECOGNITION_H_
