// A hierarchical vocabulary of binary (ORB, 32-byte) descriptors for
// bag-of-words place recognition, in the way DBoW2 (Galvez-Lopez and Tardos,
// "Bags of Binary Words for Fast Place Recognition in Image Sequences", 2012)
// describes it:
//   - a tree with k branches and L levels built by hierarchical k-means
//     (k-means++ seeding, Hamming distance, centres by per-bit majority vote);
//     the leaves are the words;
//   - tf-idf weights: idf(w) = log(N / n_w), N training images, n_w the images
//     with at least one descriptor in w;
//   - an image becomes an L1-normalised bag-of-words vector (BowVector) and a
//     direct index (FeatureVector: the features below each node a few levels
//     up from the leaves, which restricts descriptor matching to features
//     that fell in the same branch);
//   - the L1 score s(v, w) = 1 - |v - w|_1 / 2 in [0, 1], which for
//     normalised non-negative vectors is the sum over common words of
//     min(v_i, w_i).
//
// Files: a compact binary format of this project (see Save) and DBoW2's
// OpenCV YAML (`.yml`, `.yml.gz`) with ORB descriptors, L1 scoring; every
// size read is checked before anything is allocated.
#ifndef SLAM_FRONTENDS_BOW_VOCABULARY_H_
#define SLAM_FRONTENDS_BOW_VOCABULARY_H_

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace slam::bow {

constexpr int kDescriptorBytes = 32;  // ORB.
using Descriptor = std::array<uint8_t, kDescriptorBytes>;
using WordId = uint32_t;
using NodeId = uint32_t;

// Sparse word -> weight, sorted by word id, L1-normalised.
using BowVector = std::vector<std::pair<WordId, double>>;
// Node (levels_up above the leaves) -> indices of the features below it,
// sorted by node id.
using FeatureVector = std::vector<std::pair<NodeId, std::vector<int>>>;

int HammingDistance(const uint8_t* a, const uint8_t* b);

// The L1 score of two normalised vectors, in [0, 1] (1: identical).
double ScoreL1(const BowVector& a, const BowVector& b);

struct VocabularyTrainingOptions {
  int k = 10;      // Branches per node.
  int levels = 5;  // Depth of the tree (the words are at most this deep).
  int max_iterations = 20;  // Of each k-means (stops earlier when stable).
  int restarts = 3;         // k-means++ seedings per node; the best is kept.
  uint64_t seed = 42;       // k-means++ seeding.
  // Cluster at most this many descriptors (evenly spread; 0: all); the idf
  // weights always count every descriptor.
  int64_t max_descriptors = 0;
};

class Vocabulary {
 public:
  // Trains on the descriptors of a set of images: one CV_8U matrix with
  // 32-byte rows per image. Fails (with a message) on an empty set, a wrong
  // descriptor type or invalid options.
  bool Train(const std::vector<cv::Mat>& image_descriptors,
             const VocabularyTrainingOptions& options, std::string* error);
  // The checks Train makes of its options (k in [2, 256], levels in
  // [1, 16], iterations and restarts >= 1), for callers that validate
  // before the work.
  static bool CheckOptions(const VocabularyTrainingOptions& options,
                           std::string* error);

  // Loads a binary vocabulary of this project or a DBoW2 YAML one (chosen by
  // the file's first bytes / name). Errors name the file and the problem.
  bool Load(const std::string& path, std::string* error);
  bool LoadDbow2Yaml(const std::string& path, std::string* error);
  // `where` names the source in error messages.
  bool ParseBinary(std::string_view bytes, const std::string& where,
                   std::string* error);

  // Binary file: "SLAMBOW1", uint32 k, levels, descriptor bytes (32),
  // node count, then per node but the root: uint32 parent, float64 weight,
  // 32 descriptor bytes (little endian). Written atomically.
  std::string SerializeBinary() const;
  bool Save(const std::string& path, std::string* error) const;

  bool empty() const { return words_.empty(); }
  int k() const { return k_; }
  int levels() const { return levels_; }
  size_t size() const { return words_.size(); }  // Number of words.
  size_t num_nodes() const { return nodes_.size(); }
  double WordWeight(WordId word) const { return nodes_[words_[word]].weight; }
  NodeId WordNode(WordId word) const { return words_[word]; }

  // The word of one descriptor; *node receives the node `levels_up` levels
  // above the leaf it reached (the root at most; the leaf itself when 0).
  WordId Quantize(const uint8_t* descriptor, int levels_up, NodeId* node) const;

  // Bag of words (tf-idf, L1-normalised; zero-weight words are dropped) and
  // direct index (levels_up above the leaves) of one image's descriptors.
  void Transform(const cv::Mat& descriptors, int levels_up, BowVector* bow,
                 FeatureVector* features) const;

 private:
  struct Node {
    NodeId parent = 0;
    std::vector<NodeId> children;
    Descriptor descriptor{};
    double weight = 0.0;  // Words only.
    int32_t word = -1;    // Leaves: the word id.
  };

  // Numbers the leaves (words_ and Node::word) and checks the tree shape.
  bool Finish(const std::string& where, std::string* error);

  int k_ = 0;
  int levels_ = 0;
  std::vector<Node> nodes_;  // nodes_[0] is the root.
  std::vector<NodeId> words_;
};

}  // namespace slam::bow

#endif  // SLAM_FRONTENDS_BOW_VOCABULARY_H_
