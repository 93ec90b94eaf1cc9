// The bag-of-words vocabulary and database: training on synthetic clusters,
// binary round trip, corrupt files, DBoW2 YAML reading, and tf-idf scoring
// against hand-computed values.
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <zlib.h>

#include <opencv2/core/persistence.hpp>

#include "frontends/bow/database.h"
#include "frontends/bow/vocabulary.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam::bow {
namespace {

Descriptor RandomDescriptor(std::mt19937* rng) {
  Descriptor d;
  for (auto& byte : d) byte = static_cast<uint8_t>((*rng)() & 0xff);
  return d;
}

// `base` with `flips` distinct random bits flipped.
Descriptor Perturb(const Descriptor& base, int flips, std::mt19937* rng) {
  Descriptor d = base;
  std::vector<int> bits(256);
  for (int i = 0; i < 256; ++i) bits[i] = i;
  std::shuffle(bits.begin(), bits.end(), *rng);
  for (int i = 0; i < flips; ++i) d[bits[i] / 8] ^= 1 << (bits[i] % 8);
  return d;
}

cv::Mat ToMat(const std::vector<Descriptor>& descriptors) {
  cv::Mat m(static_cast<int>(descriptors.size()), kDescriptorBytes, CV_8U);
  for (size_t i = 0; i < descriptors.size(); ++i)
    std::memcpy(m.ptr<uint8_t>(static_cast<int>(i)), descriptors[i].data(),
                kDescriptorBytes);
  return m;
}

TEST(VocabularyTest, TrainingRecoversSyntheticClusters) {
  std::mt19937 rng(7);
  constexpr int kClusters = 8;
  std::vector<Descriptor> centres;
  for (int c = 0; c < kClusters; ++c) centres.push_back(RandomDescriptor(&rng));
  // 10 images, each with 6 noisy members (12 of 256 bits flipped) of every
  // cluster.
  std::vector<cv::Mat> images;
  for (int image = 0; image < 10; ++image) {
    std::vector<Descriptor> d;
    for (int c = 0; c < kClusters; ++c)
      for (int m = 0; m < 6; ++m) d.push_back(Perturb(centres[c], 12, &rng));
    images.push_back(ToMat(d));
  }
  Vocabulary voc;
  std::string error;
  VocabularyTrainingOptions options;
  options.k = kClusters;
  options.levels = 1;
  ASSERT_TRUE(voc.Train(images, options, &error)) << error;
  ASSERT_EQ(voc.size(), static_cast<size_t>(kClusters));
  // Every cluster maps to its own word, whose centre is the true centre
  // (majority vote over 60 noisy copies).
  std::vector<int> word_of(kClusters, -1);
  for (int c = 0; c < kClusters; ++c) {
    word_of[c] = static_cast<int>(voc.Quantize(centres[c].data(), 0, nullptr));
    for (int trial = 0; trial < 20; ++trial) {
      const Descriptor noisy = Perturb(centres[c], 20, &rng);
      EXPECT_EQ(voc.Quantize(noisy.data(), 0, nullptr),
                static_cast<WordId>(word_of[c]));
    }
  }
  std::sort(word_of.begin(), word_of.end());
  EXPECT_EQ(std::unique(word_of.begin(), word_of.end()), word_of.end());
  // Every word appears in every training image: idf = log(10/10) = 0.
  for (WordId w = 0; w < voc.size(); ++w) EXPECT_EQ(voc.WordWeight(w), 0.0);
}

TEST(VocabularyTest, WordCentresAreTheMajorityVoteOfLargeClusters) {
  // Two clusters of 700 members each (more than the 255 a byte counter of
  // the majority vote holds before it is flushed), 60 of 256 bits flipped:
  // every bit is flipped in about 23 % of a cluster, so the per-bit majority
  // is the true centre. The word descriptors are read back from the binary
  // file (after its header: per node uint32 parent, float64 weight, 32
  // bytes).
  std::mt19937 rng(5);
  const std::vector<Descriptor> centres = {RandomDescriptor(&rng),
                                           RandomDescriptor(&rng)};
  std::vector<cv::Mat> images;
  for (int image = 0; image < 7; ++image) {
    std::vector<Descriptor> d;
    for (int c = 0; c < 2; ++c)
      for (int m = 0; m < 100; ++m) d.push_back(Perturb(centres[c], 60, &rng));
    images.push_back(ToMat(d));
  }
  Vocabulary voc;
  std::string error;
  VocabularyTrainingOptions options;
  options.k = 2;
  options.levels = 1;
  ASSERT_TRUE(voc.Train(images, options, &error)) << error;
  ASSERT_EQ(voc.size(), 2u);
  const std::string bytes = voc.SerializeBinary();
  constexpr size_t kHeader = 8 + 4 * 4, kNode = 4 + 8 + kDescriptorBytes;
  ASSERT_EQ(bytes.size(), kHeader + 2 * kNode);
  std::vector<Descriptor> words(2);
  for (int w = 0; w < 2; ++w)
    std::memcpy(words[w].data(), bytes.data() + kHeader + w * kNode + 12,
                kDescriptorBytes);
  if (words[0] != centres[0]) std::swap(words[0], words[1]);
  EXPECT_EQ(words[0], centres[0]);
  EXPECT_EQ(words[1], centres[1]);
}

TEST(VocabularyTest, TwoLevelTreeSplitsGroupsThenClusters) {
  // 3 groups of 3 clusters: the first level must separate the groups (their
  // members differ by ~128 bits), the second the clusters inside a group
  // (~40 bits apart: 20 bits each from the group centre).
  std::mt19937 rng(11);
  std::vector<Descriptor> centres;
  for (int g = 0; g < 3; ++g) {
    const Descriptor group = RandomDescriptor(&rng);
    for (int c = 0; c < 3; ++c) centres.push_back(Perturb(group, 20, &rng));
  }
  std::vector<cv::Mat> images;
  for (int c = 0; c < 9; ++c) {
    std::vector<Descriptor> d;
    for (int m = 0; m < 30; ++m) d.push_back(Perturb(centres[c], 4, &rng));
    images.push_back(ToMat(d));  // One image per cluster: idf = log(9).
  }
  Vocabulary voc;
  std::string error;
  VocabularyTrainingOptions options;
  options.k = 3;
  options.levels = 2;
  ASSERT_TRUE(voc.Train(images, options, &error)) << error;
  ASSERT_EQ(voc.size(), 9u);
  std::vector<WordId> words;
  for (int c = 0; c < 9; ++c) {
    NodeId parent;
    words.push_back(voc.Quantize(centres[c].data(), 1, &parent));
    NodeId parent_of_first;
    voc.Quantize(centres[c / 3 * 3].data(), 1, &parent_of_first);
    EXPECT_EQ(parent, parent_of_first) << "cluster " << c;
    EXPECT_NEAR(voc.WordWeight(words.back()), std::log(9.0), 1e-12);
  }
  std::sort(words.begin(), words.end());
  EXPECT_EQ(std::unique(words.begin(), words.end()), words.end());
}

TEST(VocabularyTest, BinaryRoundTripKeepsWordsAndWeights) {
  std::mt19937 rng(3);
  std::vector<cv::Mat> images;
  for (int image = 0; image < 12; ++image) {
    std::vector<Descriptor> d;
    for (int i = 0; i < 150; ++i) d.push_back(RandomDescriptor(&rng));
    images.push_back(ToMat(d));
  }
  Vocabulary voc;
  std::string error;
  VocabularyTrainingOptions options;
  options.k = 5;
  options.levels = 3;
  ASSERT_TRUE(voc.Train(images, options, &error)) << error;
  const std::string path = testing::TempDir() + "/voc.bin";
  ASSERT_TRUE(voc.Save(path, &error)) << error;
  Vocabulary loaded;
  ASSERT_TRUE(loaded.Load(path, &error)) << error;
  EXPECT_EQ(loaded.k(), 5);
  EXPECT_EQ(loaded.levels(), 3);
  ASSERT_EQ(loaded.size(), voc.size());
  ASSERT_EQ(loaded.num_nodes(), voc.num_nodes());
  for (WordId w = 0; w < voc.size(); ++w)
    EXPECT_EQ(loaded.WordWeight(w), voc.WordWeight(w));
  for (int i = 0; i < 500; ++i) {
    const Descriptor d = RandomDescriptor(&rng);
    NodeId a, b;
    EXPECT_EQ(loaded.Quantize(d.data(), 1, &a), voc.Quantize(d.data(), 1, &b));
    EXPECT_EQ(a, b);
  }
  EXPECT_EQ(loaded.SerializeBinary(), voc.SerializeBinary());
}

// A valid binary vocabulary with the header fields overwritten.
std::string Patched(std::string bytes, size_t offset, uint32_t value) {
  std::memcpy(bytes.data() + offset, &value, 4);
  return bytes;
}

TEST(VocabularyTest, CorruptBinaryFilesAreRejectedWithAReason) {
  std::mt19937 rng(5);
  std::vector<cv::Mat> images;
  for (int image = 0; image < 4; ++image) {
    std::vector<Descriptor> d;
    for (int i = 0; i < 60; ++i) d.push_back(RandomDescriptor(&rng));
    images.push_back(ToMat(d));
  }
  Vocabulary voc;
  std::string error;
  VocabularyTrainingOptions options;
  options.k = 4;
  options.levels = 2;
  ASSERT_TRUE(voc.Train(images, options, &error)) << error;
  const std::string good = voc.SerializeBinary();
  Vocabulary other;
  ASSERT_TRUE(other.ParseBinary(good, "good", &error)) << error;

  struct Case {
    std::string bytes;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {"", "no SLAMBOW1 header"},
      {"SLAMBOW2" + good.substr(8), "no SLAMBOW1 header"},
      {Patched(good, 8, 0), "branching factor"},
      {Patched(good, 8, 0xffffffffu), "absurd tree shape"},
      {Patched(good, 12, 0), "levels"},
      {Patched(good, 12, 4000), "absurd tree shape"},
      {Patched(good, 16, 64), "descriptors of 64 bytes"},
      {Patched(good, 20, 0xfffffff0u), "nodes, but a tree"},
      {Patched(good, 20, 20), "need exactly"},  // <= 1+4+16, not the size.
      {good.substr(0, good.size() - 1), "need exactly"},
      {good + "x", "need exactly"},
      // The first node's parent pointing forward.
      {Patched(good, 24, 5), "parents must come first"},
  };
  for (const Case& c : cases) {
    Vocabulary v;
    error.clear();
    EXPECT_FALSE(v.ParseBinary(c.bytes, "voc.bin", &error)) << c.expected;
    EXPECT_TRUE(testing::Contains(error, "voc.bin: ")) << error;
    EXPECT_TRUE(testing::Contains(error, c.expected)) << error;
    EXPECT_TRUE(v.empty());
  }
  // A missing file names the path.
  Vocabulary v;
  EXPECT_FALSE(v.Load("/nonexistent/voc.bin", &error));
  EXPECT_TRUE(testing::Contains(error, "/nonexistent/voc.bin")) << error;
}

TEST(VocabularyTest, RandomlyCorruptedBinaryFilesNeverCrash) {
  // Byte flips and truncations of a valid file: each either loads into a
  // usable vocabulary or fails with a message (run under the sanitizers,
  // this is the fuzzer's seed behaviour).
  std::mt19937 rng(13);
  std::vector<cv::Mat> images;
  for (int image = 0; image < 3; ++image) {
    std::vector<Descriptor> d;
    for (int i = 0; i < 40; ++i) d.push_back(RandomDescriptor(&rng));
    images.push_back(ToMat(d));
  }
  Vocabulary voc;
  std::string error;
  VocabularyTrainingOptions options;
  options.k = 3;
  options.levels = 2;
  ASSERT_TRUE(voc.Train(images, options, &error)) << error;
  const std::string good = voc.SerializeBinary();
  int loaded = 0, rejected = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string bytes = good;
    const int flips = 1 + static_cast<int>(rng() % 4);
    for (int f = 0; f < flips; ++f)
      bytes[rng() % bytes.size()] = static_cast<char>(rng() & 0xff);
    if (trial % 5 == 0) bytes.resize(rng() % bytes.size());
    Vocabulary v;
    error.clear();
    if (v.ParseBinary(bytes, "fuzz", &error)) {
      ++loaded;
      ASSERT_FALSE(v.empty());
      const Descriptor d = RandomDescriptor(&rng);
      EXPECT_LT(v.Quantize(d.data(), 1, nullptr), v.size());
    } else {
      ++rejected;
      EXPECT_EQ(error.rfind("fuzz: ", 0), 0u) << error;
      EXPECT_TRUE(v.empty());
    }
  }
  EXPECT_GT(loaded, 0);    // Descriptor bytes may change freely.
  EXPECT_GT(rejected, 0);  // Header, parents and sizes may not.
}

std::string DescriptorText(const Descriptor& d) {
  std::string text;
  for (int i = 0; i < kDescriptorBytes; ++i) {
    if (i > 0) text += " ";
    text += std::to_string(d[i]);
  }
  return text;
}

// A DBoW2 YAML vocabulary with k = 4, L = 1: four words with given centres
// and weights.
std::string HandmadeYaml(const std::vector<Descriptor>& centres,
                         const std::vector<double>& weights) {
  std::string yaml =
      "%YAML:1.0\n---\nvocabulary:\n   k: 4\n   L: 1\n   scoringType: 0\n"
      "   weightingType: 0\n   nodes:\n";
  for (int i = 0; i < 4; ++i) {
    yaml += "      - { nodeId:" + std::to_string(i + 1) +
            ", parentId:0, weight:" + std::to_string(weights[i]) +
            ",\n          descriptor:\"" + DescriptorText(centres[i]) +
            "\" }\n";
  }
  yaml += "   words:\n";
  for (int i = 0; i < 4; ++i) {
    yaml += "      - { wordId:" + std::to_string(i) +
            ", nodeId:" + std::to_string(i + 1) + " }\n";
  }
  return yaml;
}

TEST(VocabularyTest, ReadsDbow2YamlAndScoresTfIdfAsComputedByHand) {
  std::mt19937 rng(9);
  std::vector<Descriptor> centres;
  for (int i = 0; i < 4; ++i) centres.push_back(RandomDescriptor(&rng));
  // Weights that print exactly with std::to_string's 6 decimals.
  const std::vector<double> weights = {0.5, 1.25, 2.0, 0.0};
  const std::string path = testing::TempDir() + "/hand.yml";
  testing::WriteText(path, HandmadeYaml(centres, weights));
  Vocabulary voc;
  std::string error;
  ASSERT_TRUE(voc.Load(path, &error)) << error;
  EXPECT_EQ(voc.k(), 4);
  EXPECT_EQ(voc.levels(), 1);
  ASSERT_EQ(voc.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(voc.Quantize(centres[i].data(), 0, nullptr),
              static_cast<WordId>(i));
    EXPECT_EQ(voc.WordWeight(i), weights[i]);
  }
  // Image A: words 0, 0, 1, 3.  tf-idf: w0 = 2 * 0.5 = 1, w1 = 1.25,
  // w3 = 0 (dropped); L1-normalised by 2.25.
  // Image B: words 1, 2, 2.  w1 = 1.25, w2 = 4; normalised by 5.25.
  const cv::Mat a =
      ToMat({Perturb(centres[0], 3, &rng), centres[0], centres[1], centres[3]});
  const cv::Mat b =
      ToMat({centres[1], centres[2], Perturb(centres[2], 2, &rng)});
  BowVector va, vb;
  FeatureVector fa, fb;
  voc.Transform(a, 0, &va, &fa);
  voc.Transform(b, 0, &vb, &fb);
  ASSERT_EQ(va.size(), 2u);
  EXPECT_EQ(va[0].first, 0u);
  EXPECT_DOUBLE_EQ(va[0].second, 1.0 / 2.25);
  EXPECT_EQ(va[1].first, 1u);
  EXPECT_DOUBLE_EQ(va[1].second, 1.25 / 2.25);
  ASSERT_EQ(vb.size(), 2u);
  EXPECT_DOUBLE_EQ(vb[1].second, 4.0 / 5.25);
  // L1 score: 1 - |va - vb|_1 / 2 with |va - vb|_1 =
  // 1/2.25 + |1.25/2.25 - 1.25/5.25| + 4/5.25.
  const double l1 =
      1.0 / 2.25 + std::abs(1.25 / 2.25 - 1.25 / 5.25) + 4.0 / 5.25;
  EXPECT_NEAR(ScoreL1(va, vb), 1.0 - l1 / 2.0, 1e-15);
  EXPECT_DOUBLE_EQ(ScoreL1(va, va), 1.0);
  // Direct index at the leaves: features per word.
  ASSERT_EQ(fa.size(), 3u);
  EXPECT_EQ(fa[0].second, (std::vector<int>{0, 1}));

  // The database finds the same score through its inverted index, and
  // honours the newest entry allowed.
  Database db(&voc);
  db.Add(vb, fb);
  db.Add(va, fa);
  const std::vector<QueryResult> all = db.Query(va, 10, -1);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].entry, 1u);
  EXPECT_NEAR(all[0].score, 1.0, 1e-15);
  EXPECT_EQ(all[1].entry, 0u);
  EXPECT_NEAR(all[1].score, 1.0 - l1 / 2.0, 1e-15);
  const std::vector<QueryResult> old = db.Query(va, 10, 0);
  ASSERT_EQ(old.size(), 1u);
  EXPECT_EQ(old[0].entry, 0u);
}

TEST(VocabularyTest, BadDbow2YamlNamesTheProblem) {
  std::mt19937 rng(2);
  std::vector<Descriptor> centres;
  for (int i = 0; i < 4; ++i) centres.push_back(RandomDescriptor(&rng));
  const std::string good = HandmadeYaml(centres, {1, 1, 1, 1});
  const std::string dir = testing::TempDir();
  struct Case {
    std::string text;
    std::string expected;
  };
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::vector<Case> cases = {
      {replace("k: 4", "k: 100000"), "branching factor"},
      {replace("L: 1", "L: 99"), "levels"},
      {replace("scoringType: 0", "scoringType: 2"), "only L1"},
      {replace("nodeId:2, parentId:0", "nodeId:2, parentId:3"),
       "not an earlier node"},
      {replace("nodeId:3,", "nodeId:9,"), "out of range"},
      {replace("wordId:1, nodeId:2", "wordId:1, nodeId:3"), "does not match"},
      {"%YAML:1.0\n---\nfoo: 1\n", "no 'vocabulary'"},
      {"%YAML:1.0\n---\nvocabulary: [1, 2\n",
       ":3: 'vocabulary' must hold a block map"},
      // fuzz_visual's finding: OpenCV 4.6's parser never returns on it.
      {"%YAML:1.odes:\n      - { nodeId:1 }\n   \x90   - { nodeId:2 }\n",
       ":3: byte 0x90 is not ASCII text"},
      {replace("vocabulary:", "vocabulary:\x01"), "byte 0x01 is not ASCII"},
      // fuzz_visual's second finding: OpenCV 4.6's parser never returns on
      // two "---" lines that go on with text over an indented map.
      {"%YAML:1.0\n----vocabu1.0\n----vocabullary:\n   k: 2\n   L: 1\n",
       ":2: a line starting with '---' goes on with text"},
      {replace("---\n", "--- x\n"), ":2: a line starting with '---'"},
      // And its third: "---" after content, over a map.
      {"%YAML:1.0\n   w: e\np     - { n:1,0\n---\nv:\n k: 2\n",
       ":2: indented text 'w: e' before 'vocabulary:'"},
      {"%YAML:1.0\np: 1\n---\nvocabulary:\n k: 2\n",
       ":2: 'p: 1' where a DBoW2 vocabulary starts with 'vocabulary:'"},
      {"%YAML:1.0\n---\n---\nvocabulary:\n", ":3: '---' after content"},
      // Its fourth (CI, with OpenCV's parser): a flow map cut by a line
      // holding '}' and a sequence item opening two maps.
      {"%YAML:1.0\nvocabulary:\n   k: 2\n   nodes:\n"
       "      - { nodeId:2, parentId:0, weight:1.,\n  }\n"
       "      - { { wordId:1, nodeId:2 }\n",
       ":5: an empty entry in a flow map"},
      {"%YAML:1.0\nvocabulary:\n   k: 2\n   nodes:\n"
       "      - { { wordId:1, nodeId:2 }\n",
       ":5: a nested flow map"},
      // The strict reader's own checks, each naming its line.
      {replace("   L: 1\n", "   L: 1\n   foo: 3\n"),
       ":6: unknown key 'foo' in the vocabulary map"},
      {replace("   L: 1\n", "  L: 1\n"),
       ":5: indented by 2 where the vocabulary's keys are indented by 3"},
      {replace("k: 4", "k: four"), ":4: 'k' must be an integer, not 'four'"},
      {replace("k: 4", "k: 99999999999999999999"),
       ":4: 'k' must be an integer"},
      {replace("k: 4", "k: 4000000000"), "k = 4000000000, L = 1 outside"},
      {replace("weight:1.000000", "weight:.Inf"),
       ":9: 'weight' must be a finite number, not '.Inf'"},
      {replace("parentId:0, weight", "parent:0, weight"),
       ":9: unknown key 'parent' in a node"},
      {replace("wordId:2, nodeId:3 }", "wordId:2, nodeId:3 } x"),
       ":20: text after the flow map's '}'"},
      {replace("wordId:2, nodeId:3 }", "wordId:2, nodeId:3"),
       ":20: a nested flow map"},
      {replace("wordId:3, nodeId:4 }", "wordId:3, nodeId:4"),
       ":21: a flow map not closed with '}'"},
      {replace("   words:\n", "   words: 3\n"),
       ":17: 'words' must hold a block sequence"},
      {good.substr(0, good.find("   words:")) + "   words: []\n",
       "0 words listed but the tree has 4 leaves"},
      {"%YAML:1.0\n---\nvocabulary:\n   k: 4\n   L: 1\n",
       "needs integers k, L and sequences nodes, words (missing: nodes)"},
      {replace("vocabulary:\n", "vocabulary:\n\t k: 1\n"),
       ":4: a tab in the indentation"},
      {good + "...\nx: 1\n", ":23: text after the document end"},
      {"%TAG ! x\n---\nvocabulary:\n", ":1: directive '%TAG ! x'"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string path = dir + "/bad" + std::to_string(i) + ".yml";
    testing::WriteText(path, cases[i].text);
    Vocabulary voc;
    std::string error;
    EXPECT_FALSE(voc.Load(path, &error)) << cases[i].expected;
    EXPECT_TRUE(testing::Contains(error, path)) << error;
    EXPECT_TRUE(testing::Contains(error, cases[i].expected)) << error;
    EXPECT_TRUE(voc.empty());
  }
}

// What DBoW2's TemplatedVocabulary::save writes through cv::FileStorage
// (OpenCV wraps the long node maps over two lines and prints weights with
// 17 digits) reads back exactly.
TEST(VocabularyTest, ReadsWhatOpenCvFileStorageWritesForDbow2) {
  std::mt19937 rng(11);
  std::vector<Descriptor> centres;
  for (int i = 0; i < 4; ++i) centres.push_back(RandomDescriptor(&rng));
  const std::vector<double> weights = {1.4426950408889634, 0.1, 1.0 / 3.0, 0.0};
  cv::FileStorage fs("voc.yml", cv::FileStorage::WRITE |
                                    cv::FileStorage::MEMORY |
                                    cv::FileStorage::FORMAT_YAML);
  fs << "vocabulary"
     << "{";
  fs << "k" << 4 << "L" << 1 << "scoringType" << 0 << "weightingType" << 0;
  fs << "nodes"
     << "[";
  for (int i = 0; i < 4; ++i) {
    fs << "{:"
       << "nodeId" << i + 1 << "parentId" << 0 << "weight" << weights[i]
       << "descriptor" << DescriptorText(centres[i]) + " "
       << "}";
  }
  fs << "]"
     << "words"
     << "[";
  for (int i = 0; i < 4; ++i) {
    fs << "{:"
       << "wordId" << i << "nodeId" << i + 1 << "}";
  }
  fs << "]"
     << "}";
  const std::string text = fs.releaseAndGetString();
  ASSERT_TRUE(testing::Contains(text, "weight:")) << text;
  const std::string path = testing::TempDir() + "/opencv.yml";
  testing::WriteText(path, text);
  Vocabulary voc;
  std::string error;
  ASSERT_TRUE(voc.Load(path, &error)) << error << "\n" << text;
  ASSERT_EQ(voc.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(voc.Quantize(centres[i].data(), 0, nullptr),
              static_cast<WordId>(i));
    EXPECT_EQ(voc.WordWeight(i), weights[i]);  // Bit for bit.
  }
}

// Writes `text` gzipped.
void WriteGzip(const std::string& path, const std::string& text) {
  gzFile f = gzopen(path.c_str(), "wb9");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(gzwrite(f, text.data(), static_cast<unsigned>(text.size())),
            static_cast<int>(text.size()));
  gzclose(f);
}

// Issue 26: gzipped YAML is decompressed piece by piece with a bound (a
// 400 MiB bomb of YAML comments was inflated whole by OpenCV), and
// reads as the plain text does.
TEST(VocabularyTest, GzippedYamlIsReadWithABoundedSize) {
  std::mt19937 rng(5);
  std::vector<Descriptor> centres;
  for (int i = 0; i < 4; ++i) centres.push_back(RandomDescriptor(&rng));
  const std::string dir = testing::TempDir();
  WriteGzip(dir + "/hand.yml.gz", HandmadeYaml(centres, {0.5, 1, 2, 3}));
  Vocabulary voc;
  std::string error;
  ASSERT_TRUE(voc.Load(dir + "/hand.yml.gz", &error)) << error;
  ASSERT_EQ(voc.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(voc.Quantize(centres[i].data(), 0, nullptr),
              static_cast<WordId>(i));
  }
  EXPECT_EQ(voc.WordWeight(3), 3.0);
  // Truncated gzip data.
  const std::string gz = testing::ReadText(dir + "/hand.yml.gz");
  testing::WriteText(dir + "/cut.yml.gz", gz.substr(0, gz.size() / 2));
  EXPECT_FALSE(voc.Load(dir + "/cut.yml.gz", &error));
  EXPECT_TRUE(testing::Contains(error, "cut.yml.gz: corrupt or truncated"))
      << error;
  // 400 MiB of text in about 400 kB: 400 gzip members of 1 MiB each (as
  // `cat a.gz b.gz` makes), after one holding the YAML header.
  WriteGzip(dir + "/header.gz", "%YAML:1.0\n---\n");
  WriteGzip(dir + "/mib.gz", std::string(size_t{1} << 20, '#'));
  std::string bomb = testing::ReadText(dir + "/header.gz");
  const std::string mib = testing::ReadText(dir + "/mib.gz");
  for (int i = 0; i < 400; ++i) bomb += mib;
  testing::WriteText(dir + "/bomb.yml.gz", bomb);
  Vocabulary fresh;
  EXPECT_FALSE(fresh.Load(dir + "/bomb.yml.gz", &error));
  EXPECT_TRUE(
      testing::Contains(error, "bomb.yml.gz: decompresses to more than"))
      << error;
  EXPECT_TRUE(fresh.empty());
}

TEST(VocabularyTest, ReadsTheSharedDbow2Vocabulary) {
  const std::string path =
      testing::DatasetPath("bow_rtabmap_samples/small_voc.yml.gz");
  SLAM_REQUIRE_DATASET(path);
  Vocabulary voc;
  std::string error;
  ASSERT_TRUE(voc.Load(path, &error)) << error;
  EXPECT_EQ(voc.k(), 9);
  EXPECT_EQ(voc.levels(), 3);
  EXPECT_EQ(voc.num_nodes(), 782u);  // 781 listed + the root.
  EXPECT_EQ(voc.size(), 692u);
  // Binary round trip of a DBoW2 vocabulary.
  Vocabulary copy;
  ASSERT_TRUE(copy.ParseBinary(voc.SerializeBinary(), "copy", &error)) << error;
  std::mt19937 rng(1);
  for (int i = 0; i < 200; ++i) {
    const Descriptor d = RandomDescriptor(&rng);
    EXPECT_EQ(copy.Quantize(d.data(), 0, nullptr),
              voc.Quantize(d.data(), 0, nullptr));
  }
}

}  // namespace
}  // namespace slam::bow
