#include "frontends/bow/vocabulary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <string_view>

#include <zlib.h>

#include <opencv2/core/hal/hal.hpp>

#include "datasets/atomic_file.h"
#include "datasets/text_util.h"
#include "frontends/bow/dbow2_yaml.h"

namespace slam::bow {
namespace {

constexpr char kMagic[8] = {'S', 'L', 'A', 'M', 'B', 'O', 'W', '1'};
constexpr size_t kHeaderBytes = 8 + 4 * 4;
constexpr size_t kNodeBytes = 4 + 8 + kDescriptorBytes;
constexpr int kMaxK = 256;
constexpr int kMaxLevels = 16;
// No vocabulary this project reads or writes has more nodes (DBoW2's
// largest published ORB vocabulary, k=10 L=6, has about 1.1 million).
constexpr uint64_t kMaxNodes = uint64_t{1} << 26;
// The largest binary file: kMaxNodes nodes.
constexpr size_t kMaxBinaryBytes = kHeaderBytes + kMaxNodes * kNodeBytes;
// The largest DBoW2 YAML text read (after decompression): about 220 bytes a
// node (32 descriptor bytes as decimals, ids, weight) plus the word list,
// so room for DBoW2's k = 10, L = 6 ORB vocabulary of 1.1 million nodes;
// a gzip bomb stops here, while it is decompressed.
constexpr size_t kMaxYamlBytes = size_t{384} << 20;

// The text of a DBoW2 YAML file, gunzipped piece by piece when it starts
// with the gzip magic (one or more members), at most kMaxYamlBytes.
bool ReadYamlText(const std::string& path, std::string* text,
                  std::string* error) {
  std::string data;
  if (!text::ReadWholeFile(path, &data, error, kMaxYamlBytes)) return false;
  if (data.size() < 2 || static_cast<uint8_t>(data[0]) != 0x1f ||
      static_cast<uint8_t>(data[1]) != 0x8b) {
    *text = std::move(data);
    return true;
  }
  text->clear();
  z_stream z{};
  if (inflateInit2(&z, 15 + 16) != Z_OK) {
    *error = path + ": cannot start gzip decompression";
    return false;
  }
  z.next_in = reinterpret_cast<Bytef*>(data.data());
  z.avail_in = static_cast<uInt>(data.size());  // <= kMaxYamlBytes.
  std::vector<char> out(size_t{1} << 20);
  int status = Z_OK;
  while (true) {
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = static_cast<uInt>(out.size());
    status = inflate(&z, Z_NO_FLUSH);
    const size_t got = out.size() - z.avail_out;
    if (got > kMaxYamlBytes - text->size()) {
      inflateEnd(&z);
      text->clear();
      *error = path + ": decompresses to more than " +
               std::to_string(kMaxYamlBytes) +
               " bytes (no vocabulary is that large: a gzip bomb?)";
      return false;
    }
    text->append(out.data(), got);
    if (status == Z_STREAM_END) {
      // Another gzip member may follow (as `cat a.gz b.gz` makes).
      if (z.avail_in >= 2 && z.next_in[0] == 0x1f && z.next_in[1] == 0x8b) {
        inflateReset(&z);
        continue;
      }
      break;
    }
    if (status != Z_OK) break;  // Z_BUF_ERROR: truncated.
  }
  inflateEnd(&z);
  if (status != Z_STREAM_END) {
    text->clear();
    *error = path + ": corrupt or truncated gzip data";
    return false;
  }
  return true;
}

// The most nodes a tree with k branches and L levels can have (saturating).
uint64_t MaxNodes(int k, int levels) {
  uint64_t total = 1, level = 1;
  for (int d = 1; d <= levels; ++d) {
    level *= static_cast<uint64_t>(k);
    total += level;
    if (total > kMaxNodes) return kMaxNodes + 1;
  }
  return total;
}

bool CheckShape(int k, int levels, uint64_t num_nodes, const std::string& where,
                std::string* error) {
  if (k < 2 || k > kMaxK) {
    *error = where + ": branching factor k = " + std::to_string(k) +
             " outside [2, " + std::to_string(kMaxK) + "]";
    return false;
  }
  if (levels < 1 || levels > kMaxLevels) {
    *error = where + ": levels L = " + std::to_string(levels) +
             " outside [1, " + std::to_string(kMaxLevels) + "]";
    return false;
  }
  const uint64_t max_nodes = std::min(MaxNodes(k, levels), kMaxNodes);
  if (num_nodes < 2 || num_nodes > max_nodes) {
    *error = where + ": " + std::to_string(num_nodes) +
             " nodes, but a tree with k = " + std::to_string(k) +
             " and L = " + std::to_string(levels) + " has 2 to " +
             std::to_string(max_nodes);
    return false;
  }
  return true;
}

// The majority-vote centre of a set of binary descriptors: each bit is set
// when more than half of the descriptors have it set. The bits are counted
// eight at a time: kSpreadBits[v] holds bit b of v in byte b, so adding it
// to a 64-bit word counts the 8 bits of one descriptor byte at once (a byte
// counter holds 255: flushed every 255 descriptors). Counting bit by bit
// made the vocabulary training the largest cost of a short run after the
// frames (0.5 of 1 s on the KITTI 06 excerpt's keyframes).
constexpr std::array<uint64_t, 256> SpreadBits() {
  std::array<uint64_t, 256> table{};
  for (int v = 0; v < 256; ++v) {
    for (int bit = 0; bit < 8; ++bit) {
      if ((v >> bit) & 1) table[v] |= uint64_t{1} << (8 * bit);
    }
  }
  return table;
}
constexpr std::array<uint64_t, 256> kSpreadBits = SpreadBits();

Descriptor MajorityCentre(const std::vector<const uint8_t*>& members) {
  std::array<int, kDescriptorBytes * 8> ones{};
  std::array<uint64_t, kDescriptorBytes> packed{};
  auto flush = [&]() {
    for (int byte = 0; byte < kDescriptorBytes; ++byte) {
      for (int bit = 0; bit < 8; ++bit)
        ones[byte * 8 + bit] += (packed[byte] >> (8 * bit)) & 0xff;
      packed[byte] = 0;
    }
  };
  int pending = 0;
  for (const uint8_t* d : members) {
    for (int byte = 0; byte < kDescriptorBytes; ++byte)
      packed[byte] += kSpreadBits[d[byte]];
    if (++pending == 255) {
      flush();
      pending = 0;
    }
  }
  flush();
  Descriptor centre{};
  const size_t half = members.size() / 2;
  for (int byte = 0; byte < kDescriptorBytes; ++byte) {
    uint8_t value = 0;
    for (int bit = 0; bit < 8; ++bit) {
      if (static_cast<size_t>(ones[byte * 8 + bit]) > half) value |= 1 << bit;
    }
    centre[byte] = value;
  }
  return centre;
}

// One k-means run on all[members] with k-means++ seeding (probability
// proportional to the squared Hamming distance); returns the summed distance
// of the members to their centres.
double KMeans(const std::vector<const uint8_t*>& all,
              const std::vector<int>& members, int k, int max_iterations,
              std::mt19937_64* rng, std::vector<Descriptor>* centres,
              std::vector<int>* assignment) {
  const size_t n = members.size();
  centres->clear();
  std::vector<double> min_sq(n, std::numeric_limits<double>::max());
  std::uniform_int_distribution<size_t> pick(0, n - 1);
  size_t next = pick(*rng);
  while (centres->size() < static_cast<size_t>(k)) {
    Descriptor c;
    std::memcpy(c.data(), all[members[next]], kDescriptorBytes);
    centres->push_back(c);
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) {
      const double dist = HammingDistance(all[members[i]], c.data());
      min_sq[i] = std::min(min_sq[i], dist * dist);
      total += min_sq[i];
    }
    if (total <= 0.0) break;  // Every member equals a centre already.
    std::uniform_real_distribution<double> u(0.0, total);
    double target = u(*rng);
    next = n - 1;
    for (size_t i = 0; i < n; ++i) {
      target -= min_sq[i];
      if (target <= 0.0 && min_sq[i] > 0.0) {
        next = i;
        break;
      }
    }
  }
  assignment->assign(n, -1);
  std::vector<int> distance(n, 0);
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    bool changed = false;
    for (size_t i = 0; i < n; ++i) {
      int best = 0, best_distance = std::numeric_limits<int>::max();
      for (size_t c = 0; c < centres->size(); ++c) {
        const int dist = HammingDistance(all[members[i]], (*centres)[c].data());
        if (dist < best_distance) {
          best_distance = dist;
          best = static_cast<int>(c);
        }
      }
      distance[i] = best_distance;
      if ((*assignment)[i] != best) {
        (*assignment)[i] = best;
        changed = true;
      }
    }
    if (!changed || iteration + 1 == max_iterations) break;
    std::vector<std::vector<const uint8_t*>> groups(centres->size());
    for (size_t i = 0; i < n; ++i)
      groups[(*assignment)[i]].push_back(all[members[i]]);
    for (size_t c = 0; c < centres->size(); ++c) {
      if (!groups[c].empty()) (*centres)[c] = MajorityCentre(groups[c]);
    }
  }
  double cost = 0.0;
  for (int d : distance) cost += d;
  return cost;
}

template <typename T>
bool ReadScalar(std::string_view bytes, size_t* pos, T* value) {
  if (bytes.size() - *pos < sizeof(T)) return false;
  std::memcpy(value, bytes.data() + *pos, sizeof(T));
  *pos += sizeof(T);
  return true;
}

template <typename T>
void AppendScalar(std::string* out, T value) {
  out->append(reinterpret_cast<const char*>(&value), sizeof(T));
}

}  // namespace

int HammingDistance(const uint8_t* a, const uint8_t* b) {
  // OpenCV's SIMD count (__builtin_popcountll is a libgcc call without
  // -mpopcnt, which the build cannot assume).
  return cv::hal::normHamming(a, b, kDescriptorBytes);
}

double ScoreL1(const BowVector& a, const BowVector& b) {
  // 1 - |a - b|_1 / 2 = sum over common words of min(a_i, b_i) when both
  // are L1-normalised and non-negative.
  double score = 0.0;
  auto i = a.begin();
  auto j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (i->first < j->first) {
      ++i;
    } else if (j->first < i->first) {
      ++j;
    } else {
      score += std::min(i->second, j->second);
      ++i;
      ++j;
    }
  }
  return score;
}

bool Vocabulary::CheckOptions(const VocabularyTrainingOptions& options,
                              std::string* error) {
  if (!CheckShape(options.k, options.levels, 2, "vocabulary training", error))
    return false;
  if (options.max_iterations < 1 || options.restarts < 1) {
    *error = "vocabulary training: max_iterations and restarts must be >= 1";
    return false;
  }
  return true;
}

bool Vocabulary::Train(const std::vector<cv::Mat>& image_descriptors,
                       const VocabularyTrainingOptions& options,
                       std::string* error) {
  if (!CheckOptions(options, error)) return false;
  std::vector<const uint8_t*> all;
  std::vector<int> image_of;
  for (size_t i = 0; i < image_descriptors.size(); ++i) {
    const cv::Mat& d = image_descriptors[i];
    if (d.empty()) continue;
    if (d.type() != CV_8U || d.cols != kDescriptorBytes) {
      *error = "vocabulary training: image " + std::to_string(i) +
               " has descriptors that are not 32-byte binary (ORB) rows";
      return false;
    }
    for (int r = 0; r < d.rows; ++r) {
      all.push_back(d.ptr<uint8_t>(r));
      image_of.push_back(static_cast<int>(i));
    }
  }
  if (all.empty()) {
    *error = "vocabulary training: no descriptors";
    return false;
  }
  k_ = options.k;
  levels_ = options.levels;
  nodes_.assign(1, Node());
  words_.clear();
  std::mt19937_64 rng(options.seed);

  // Depth-first: (node, depth, member indices into `all`).
  struct Task {
    NodeId node;
    int depth;
    std::vector<int> members;
  };
  std::vector<Task> stack;
  {
    // Clustering on at most max_descriptors, evenly spread over the images.
    const size_t used =
        options.max_descriptors > 0
            ? std::min(all.size(), static_cast<size_t>(options.max_descriptors))
            : all.size();
    std::vector<int> members(used);
    for (size_t i = 0; i < used; ++i)
      members[i] = static_cast<int>(i * all.size() / used);
    stack.push_back({0, 0, std::move(members)});
  }
  while (!stack.empty()) {
    Task task = std::move(stack.back());
    stack.pop_back();
    if (task.depth == levels_ || task.members.size() <= 1) {
      continue;
    }
    std::vector<Descriptor> centres;
    std::vector<int> assignment(task.members.size(), 0);
    if (task.members.size() <= static_cast<size_t>(k_)) {
      // As many clusters as distinct descriptors.
      for (size_t i = 0; i < task.members.size(); ++i) {
        const uint8_t* d = all[task.members[i]];
        int found = -1;
        for (size_t c = 0; c < centres.size(); ++c) {
          if (std::memcmp(centres[c].data(), d, kDescriptorBytes) == 0)
            found = static_cast<int>(c);
        }
        if (found < 0) {
          Descriptor copy;
          std::memcpy(copy.data(), d, kDescriptorBytes);
          centres.push_back(copy);
          found = static_cast<int>(centres.size()) - 1;
        }
        assignment[i] = found;
      }
    } else {
      // k-means, keeping the best of a few k-means++ restarts (one seeding
      // can land two centres in one cluster and Lloyd's iterations do not
      // recover from that).
      double best_cost = std::numeric_limits<double>::max();
      for (int attempt = 0; attempt < options.restarts; ++attempt) {
        std::vector<Descriptor> c;
        std::vector<int> a;
        const double cost =
            KMeans(all, task.members, k_, options.max_iterations, &rng, &c, &a);
        if (cost < best_cost) {
          best_cost = cost;
          centres = std::move(c);
          assignment = std::move(a);
        }
      }
    }
    // Children for the non-empty clusters, created together (contiguous).
    std::vector<std::vector<int>> groups(centres.size());
    for (size_t i = 0; i < task.members.size(); ++i)
      groups[assignment[i]].push_back(task.members[i]);
    for (size_t c = 0; c < centres.size(); ++c) {
      if (groups[c].empty()) continue;
      Node child;
      child.parent = task.node;
      child.descriptor = centres[c];
      const NodeId id = static_cast<NodeId>(nodes_.size());
      nodes_.push_back(child);
      nodes_[task.node].children.push_back(id);
      stack.push_back({id, task.depth + 1, std::move(groups[c])});
    }
  }
  if (!Finish("vocabulary training", error)) return false;
  // idf = log(N / n_w) over the training images (every descriptor).
  std::vector<int> images_with(words_.size(), 0);
  std::vector<int> last_image(words_.size(), -1);
  int num_images = 0;
  for (size_t i = 0; i < image_descriptors.size(); ++i)
    if (!image_descriptors[i].empty()) ++num_images;
  for (size_t m = 0; m < all.size(); ++m) {
    const WordId word = Quantize(all[m], 0, nullptr);
    if (last_image[word] != image_of[m]) {
      last_image[word] = image_of[m];
      ++images_with[word];
    }
  }
  for (size_t w = 0; w < words_.size(); ++w) {
    nodes_[words_[w]].weight =
        images_with[w] > 0
            ? std::log(static_cast<double>(num_images) / images_with[w])
            : 0.0;
  }
  return true;
}

bool Vocabulary::Finish(const std::string& where, std::string* error) {
  words_.clear();
  std::vector<int> depth(nodes_.size(), 0);
  for (size_t i = 1; i < nodes_.size(); ++i) {
    const NodeId parent = nodes_[i].parent;
    if (parent >= i) {
      *error = where + ": node " + std::to_string(i) + " has parent " +
               std::to_string(parent) + " (parents must come first)";
      return false;
    }
    depth[i] = depth[parent] + 1;
    if (depth[i] > levels_) {
      *error = where + ": node " + std::to_string(i) + " is at depth " +
               std::to_string(depth[i]) + " > L = " + std::to_string(levels_);
      return false;
    }
    if (nodes_[parent].children.size() > static_cast<size_t>(k_)) {
      *error = where + ": node " + std::to_string(parent) +
               " has more than k = " + std::to_string(k_) + " children";
      return false;
    }
  }
  for (size_t i = 1; i < nodes_.size(); ++i) {
    if (!nodes_[i].children.empty()) {
      nodes_[i].word = -1;
      continue;
    }
    if (!std::isfinite(nodes_[i].weight) || nodes_[i].weight < 0.0) {
      *error =
          where + ": word node " + std::to_string(i) + " has an invalid weight";
      return false;
    }
    nodes_[i].word = static_cast<int32_t>(words_.size());
    words_.push_back(static_cast<NodeId>(i));
  }
  if (words_.empty()) {
    *error = where + ": vocabulary without words";
    return false;
  }
  return true;
}

WordId Vocabulary::Quantize(const uint8_t* descriptor, int levels_up,
                            NodeId* node) const {
  const int node_depth = std::max(0, levels_ - levels_up);
  NodeId current = 0;
  NodeId at_depth = 0;
  int depth = 0;
  while (!nodes_[current].children.empty()) {
    NodeId best = nodes_[current].children[0];
    int best_distance = std::numeric_limits<int>::max();
    for (NodeId child : nodes_[current].children) {
      const int dist =
          HammingDistance(descriptor, nodes_[child].descriptor.data());
      if (dist < best_distance) {
        best_distance = dist;
        best = child;
      }
    }
    current = best;
    ++depth;
    if (depth <= node_depth) at_depth = current;
  }
  if (node != nullptr) *node = at_depth;
  return static_cast<WordId>(nodes_[current].word);
}

void Vocabulary::Transform(const cv::Mat& descriptors, int levels_up,
                           BowVector* bow, FeatureVector* features) const {
  bow->clear();
  if (features != nullptr) features->clear();
  if (descriptors.empty() || empty()) return;
  CV_Assert(descriptors.type() == CV_8U &&
            descriptors.cols == kDescriptorBytes);
  std::vector<std::pair<WordId, double>> weights;
  std::vector<std::pair<NodeId, int>> node_features;
  weights.reserve(descriptors.rows);
  for (int r = 0; r < descriptors.rows; ++r) {
    NodeId node;
    const WordId word = Quantize(descriptors.ptr<uint8_t>(r), levels_up, &node);
    const double weight = WordWeight(word);
    if (weight > 0.0) weights.emplace_back(word, weight);
    node_features.emplace_back(node, r);
  }
  std::sort(weights.begin(), weights.end());
  double total = 0.0;
  for (const auto& [word, weight] : weights) {
    if (!bow->empty() && bow->back().first == word) {
      bow->back().second += weight;
    } else {
      bow->emplace_back(word, weight);
    }
    total += weight;
  }
  if (total > 0.0) {
    for (auto& entry : *bow) entry.second /= total;
  }
  if (features != nullptr) {
    std::sort(node_features.begin(), node_features.end());
    for (const auto& [node, index] : node_features) {
      if (features->empty() || features->back().first != node)
        features->emplace_back(node, std::vector<int>());
      features->back().second.push_back(index);
    }
  }
}

std::string Vocabulary::SerializeBinary() const {
  std::string out(kMagic, sizeof(kMagic));
  out.reserve(kHeaderBytes + nodes_.size() * kNodeBytes);
  AppendScalar<uint32_t>(&out, static_cast<uint32_t>(k_));
  AppendScalar<uint32_t>(&out, static_cast<uint32_t>(levels_));
  AppendScalar<uint32_t>(&out, kDescriptorBytes);
  AppendScalar<uint32_t>(&out, static_cast<uint32_t>(nodes_.size()));
  for (size_t i = 1; i < nodes_.size(); ++i) {
    AppendScalar<uint32_t>(&out, nodes_[i].parent);
    AppendScalar<double>(&out, nodes_[i].word >= 0 ? nodes_[i].weight : 0.0);
    out.append(reinterpret_cast<const char*>(nodes_[i].descriptor.data()),
               kDescriptorBytes);
  }
  return out;
}

bool Vocabulary::Save(const std::string& path, std::string* error) const {
  return WriteFileAtomically(path, SerializeBinary(), error);
}

bool Vocabulary::ParseBinary(std::string_view bytes, const std::string& where,
                             std::string* error) {
  if (bytes.size() < kHeaderBytes ||
      std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    *error = where + ": not a binary vocabulary (no SLAMBOW1 header)";
    return false;
  }
  size_t pos = sizeof(kMagic);
  uint32_t k, levels, descriptor_bytes, num_nodes;
  ReadScalar(bytes, &pos, &k);
  ReadScalar(bytes, &pos, &levels);
  ReadScalar(bytes, &pos, &descriptor_bytes);
  ReadScalar(bytes, &pos, &num_nodes);
  if (descriptor_bytes != kDescriptorBytes) {
    *error = where + ": descriptors of " + std::to_string(descriptor_bytes) +
             " bytes (only 32-byte ORB descriptors are supported)";
    return false;
  }
  if (k > kMaxK || levels > kMaxLevels) {
    *error = where + ": absurd tree shape k = " + std::to_string(k) +
             ", L = " + std::to_string(levels);
    return false;
  }
  if (!CheckShape(static_cast<int>(k), static_cast<int>(levels), num_nodes,
                  where, error))
    return false;
  const uint64_t expected = kHeaderBytes + uint64_t{num_nodes - 1} * kNodeBytes;
  if (bytes.size() != expected) {
    *error = where + ": " + std::to_string(bytes.size()) + " bytes, but " +
             std::to_string(num_nodes) + " nodes need exactly " +
             std::to_string(expected) + " (truncated or corrupt file)";
    return false;
  }
  std::vector<Node> nodes(num_nodes);
  for (uint32_t i = 1; i < num_nodes; ++i) {
    Node& node = nodes[i];
    ReadScalar(bytes, &pos, &node.parent);
    ReadScalar(bytes, &pos, &node.weight);
    std::memcpy(node.descriptor.data(), bytes.data() + pos, kDescriptorBytes);
    pos += kDescriptorBytes;
    if (node.parent >= i) {
      *error = where + ": node " + std::to_string(i) + " has parent " +
               std::to_string(node.parent) + " (parents must come first)";
      return false;
    }
    if (nodes[node.parent].children.size() >= k) {
      *error = where + ": node " + std::to_string(node.parent) +
               " has more than k = " + std::to_string(k) + " children";
      return false;
    }
    nodes[node.parent].children.push_back(i);
  }
  k_ = static_cast<int>(k);
  levels_ = static_cast<int>(levels);
  nodes_ = std::move(nodes);
  if (!Finish(where, error)) {
    nodes_.clear();
    words_.clear();
    return false;
  }
  return true;
}

bool Vocabulary::LoadDbow2Yaml(const std::string& path, std::string* error) {
  Dbow2Yaml yaml;
  {
    std::string text;
    if (!ReadYamlText(path, &text, error)) return false;
    if (!ParseDbow2Yaml(text, path, &yaml, error)) return false;
  }
  if (yaml.scoring_type != 0 || yaml.weighting_type != 0) {
    *error = path + ": scoringType " + std::to_string(yaml.scoring_type) +
             ", weightingType " + std::to_string(yaml.weighting_type) +
             " (only L1 scoring, 0, with TF-IDF weights, 0, is supported)";
    return false;
  }
  // k and L as ints only once they are known to be in CheckShape's ranges.
  const int64_t k64 = std::clamp<int64_t>(yaml.k, -1, kMaxK + 1);
  const int64_t levels64 = std::clamp<int64_t>(yaml.levels, -1, kMaxLevels + 1);
  const int k = static_cast<int>(k64);
  const int levels = static_cast<int>(levels64);
  const uint64_t num_nodes = static_cast<uint64_t>(yaml.nodes.size()) + 1;
  if (k64 != yaml.k || levels64 != yaml.levels) {
    *error = path + ": k = " + std::to_string(yaml.k) +
             ", L = " + std::to_string(yaml.levels) + " outside [2, " +
             std::to_string(kMaxK) + "] and [1, " + std::to_string(kMaxLevels) +
             "] (branching factor k, levels L)";
    return false;
  }
  if (!CheckShape(k, levels, num_nodes, path, error)) return false;
  std::vector<Node> tree(num_nodes);
  std::vector<bool> seen(num_nodes, false);
  for (const Dbow2YamlNode& n : yaml.nodes) {
    const std::string item = path + ":" + std::to_string(n.line);
    if (n.node_id < 1 || static_cast<uint64_t>(n.node_id) >= num_nodes ||
        seen[n.node_id]) {
      *error = item + ": nodeId " + std::to_string(n.node_id) +
               " out of range or repeated (" + std::to_string(num_nodes - 1) +
               " nodes listed)";
      return false;
    }
    if (n.parent_id < 0 || n.parent_id >= n.node_id) {
      *error = item + ": parentId " + std::to_string(n.parent_id) +
               " is not an earlier node";
      return false;
    }
    seen[n.node_id] = true;
    Node& node = tree[n.node_id];
    node.parent = static_cast<NodeId>(n.parent_id);
    node.weight = n.weight;
    std::istringstream values(n.descriptor);
    for (int b = 0; b < kDescriptorBytes; ++b) {
      int value = -1;
      if (!(values >> value) || value < 0 || value > 255) {
        *error = item + ": descriptor must be 32 byte values (0-255)";
        return false;
      }
      node.descriptor[b] = static_cast<uint8_t>(value);
    }
    std::string extra;
    if (values >> extra) {
      *error = item + ": descriptor has more than 32 values (not ORB)";
      return false;
    }
  }
  // Children in id order, as DBoW2 keeps them.
  for (size_t i = 1; i < num_nodes; ++i) {
    tree[tree[i].parent].children.push_back(static_cast<NodeId>(i));
  }
  k_ = k;
  levels_ = levels;
  nodes_ = std::move(tree);
  if (!Finish(path, error)) {
    nodes_.clear();
    words_.clear();
    return false;
  }
  // DBoW2 numbers the words as the leaves in node order, like Finish.
  if (yaml.words.size() != words_.size()) {
    *error = path + ": " + std::to_string(yaml.words.size()) +
             " words listed but the tree has " + std::to_string(words_.size()) +
             " leaves";
    nodes_.clear();
    words_.clear();
    return false;
  }
  for (const Dbow2YamlWord& w : yaml.words) {
    if (w.word_id < 0 || static_cast<uint64_t>(w.word_id) >= words_.size() ||
        static_cast<int64_t>(words_[w.word_id]) != w.node_id) {
      *error = path + ":" + std::to_string(w.line) + ": word " +
               std::to_string(w.word_id) + " -> node " +
               std::to_string(w.node_id) +
               " does not match the leaves in node order";
      nodes_.clear();
      words_.clear();
      return false;
    }
  }
  return true;
}

bool Vocabulary::Load(const std::string& path, std::string* error) {
  auto ends_with = [&](const std::string& suffix) {
    return path.size() >= suffix.size() &&
           path.compare(path.size() - suffix.size(), suffix.size(), suffix) ==
               0;
  };
  if (ends_with(".yml") || ends_with(".yml.gz") || ends_with(".yaml") ||
      ends_with(".yaml.gz")) {
    return LoadDbow2Yaml(path, error);
  }
  std::string bytes;
  if (!text::ReadWholeFile(path, &bytes, error, kMaxBinaryBytes)) return false;
  return ParseBinary(bytes, path, error);
}

}  // namespace slam::bow
