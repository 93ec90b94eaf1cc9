#include "frontends/bow/database.h"

#include <algorithm>

namespace slam::bow {

Database::Database(const Vocabulary* vocabulary)
    : vocabulary_(vocabulary), inverted_(vocabulary->size()) {}

EntryId Database::Add(BowVector bow, FeatureVector features) {
  const EntryId id = static_cast<EntryId>(bows_.size());
  for (const auto& [word, weight] : bow)
    inverted_[word].emplace_back(id, weight);
  bows_.push_back(std::move(bow));
  features_.push_back(std::move(features));
  return id;
}

std::vector<QueryResult> Database::Query(const BowVector& bow, int max_results,
                                         int64_t max_entry) const {
  // L1 score = sum over common words of min(q_w, e_w) (both normalised).
  const int64_t last = max_entry < 0
                           ? static_cast<int64_t>(bows_.size()) - 1
                           : std::min<int64_t>(max_entry, bows_.size() - 1);
  std::vector<QueryResult> results;
  if (last < 0 || max_results <= 0) return results;
  scratch_.assign(last + 1, 0.0);
  std::vector<EntryId> touched;
  for (const auto& [word, q] : bow) {
    for (const auto& [entry, w] : inverted_[word]) {
      // Postings are in entry order: the rest are too recent.
      if (entry > static_cast<EntryId>(last)) break;
      if (scratch_[entry] == 0.0) touched.push_back(entry);
      scratch_[entry] += std::min(q, w);
    }
  }
  results.reserve(touched.size());
  for (EntryId entry : touched) results.push_back({entry, scratch_[entry]});
  auto better = [](const QueryResult& a, const QueryResult& b) {
    return a.score > b.score || (a.score == b.score && a.entry < b.entry);
  };
  if (results.size() > static_cast<size_t>(max_results)) {
    std::partial_sort(results.begin(), results.begin() + max_results,
                      results.end(), better);
    results.resize(max_results);
  } else {
    std::sort(results.begin(), results.end(), better);
  }
  return results;
}

}  // namespace slam::bow
