#include "frontends/visual/place_recognition.h"

#include <algorithm>

namespace slam {

int VocabularyLevelsFor(const LoopsConfig& config, size_t num_descriptors) {
  if (config.vocabulary_levels > 0) return config.vocabulary_levels;
  int levels = 1;
  double words = config.vocabulary_k;
  while (levels < 5 &&
         words * config.vocabulary_k * config.descriptors_per_word <=
             static_cast<double>(num_descriptors)) {
    words *= config.vocabulary_k;
    ++levels;
  }
  return levels;
}

bool TrainVocabulary(const LoopsConfig& config,
                     const std::vector<cv::Mat>& descriptors, size_t count,
                     bow::Vocabulary* vocabulary, std::string* error) {
  bow::VocabularyTrainingOptions options;
  options.k = config.vocabulary_k;
  options.max_descriptors = config.vocabulary_max_descriptors;
  options.levels = VocabularyLevelsFor(
      config, options.max_descriptors > 0
                  ? std::min<size_t>(count, options.max_descriptors)
                  : count);
  return vocabulary->Train(descriptors, options, error);
}

}  // namespace slam
