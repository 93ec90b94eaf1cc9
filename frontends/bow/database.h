// A place-recognition database over a bag-of-words vocabulary: an inverted
// index (word -> entries that contain it, with their weight) answers "which
// stored images look like this one" by touching only the entries that share
// a word with the query; the direct index of every entry (features per
// vocabulary node) is kept for descriptor matching in the verification.
#ifndef SLAM_FRONTENDS_BOW_DATABASE_H_
#define SLAM_FRONTENDS_BOW_DATABASE_H_

#include <cstdint>
#include <vector>

#include "frontends/bow/vocabulary.h"

namespace slam::bow {

using EntryId = uint32_t;

struct QueryResult {
  EntryId entry = 0;
  double score = 0.0;  // L1 score in [0, 1].
};

class Database {
 public:
  // The vocabulary must outlive the database.
  explicit Database(const Vocabulary* vocabulary);

  // Adds an image; entries are numbered 0, 1, ... in the order added.
  EntryId Add(BowVector bow, FeatureVector features);

  // The best `max_results` entries with id <= max_entry (all when negative)
  // and score > 0, best first (ties: older entry first).
  std::vector<QueryResult> Query(const BowVector& bow, int max_results,
                                 int64_t max_entry) const;

  size_t size() const { return bows_.size(); }
  const BowVector& bow(EntryId entry) const { return bows_[entry]; }
  const FeatureVector& features(EntryId entry) const {
    return features_[entry];
  }
  const Vocabulary& vocabulary() const { return *vocabulary_; }

 private:
  const Vocabulary* vocabulary_;
  std::vector<std::vector<std::pair<EntryId, double>>> inverted_;  // By word.
  std::vector<BowVector> bows_;
  std::vector<FeatureVector> features_;
  mutable std::vector<double> scratch_;  // Accumulated scores by entry.
};

}  // namespace slam::bow

#endif  // SLAM_FRONTENDS_BOW_DATABASE_H_
