// A strict reader for the YAML text of a DBoW2 vocabulary, the layout that
// DBoW2's TemplatedVocabulary::save writes through cv::FileStorage:
//
//   %YAML:1.0
//   ---
//   vocabulary:
//      k: 9
//      L: 3
//      scoringType: 0
//      weightingType: 0
//      nodes:
//         - { nodeId:1, parentId:0, weight:0.,
//             descriptor:"212 176 ... 34 " }
//      words:
//         - { wordId:0, nodeId:21 }
//
// and nothing else: one document, one top-level key `vocabulary`, its
// scalar keys, and two block sequences of one flow map each (a map may wrap
// over lines, as OpenCV wraps long ones). Blank lines and whole-line '#'
// comments are skipped; `nodes: []` is an empty sequence.
//
// Why not cv::FileStorage: OpenCV 4.6's YAML parser never returns on some
// malformed inputs (fuzz_visual found three shapes in minutes: a non-ASCII
// byte where it expects indentation, "---" lines that go on with text, a
// "---" after content, a flow map cut off by a line and reopened). Untrusted
// files must not hang the reader, so this one reads the layout above in one
// pass over the lines, every loop bounded by the text's length.
#ifndef SLAM_FRONTENDS_BOW_DBOW2_YAML_H_
#define SLAM_FRONTENDS_BOW_DBOW2_YAML_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace slam::bow {

struct Dbow2YamlNode {
  size_t line = 0;  // 1-based line of the item's '-'.
  int64_t node_id = 0;
  int64_t parent_id = 0;
  double weight = 0.0;
  std::string descriptor;  // The quoted text: byte values and spaces.
};

struct Dbow2YamlWord {
  size_t line = 0;
  int64_t word_id = 0;
  int64_t node_id = 0;
};

struct Dbow2Yaml {
  int64_t k = 0;
  int64_t levels = 0;          // "L".
  int64_t scoring_type = 0;    // Absent: 0 (L1).
  int64_t weighting_type = 0;  // Absent: 0 (TF-IDF).
  std::vector<Dbow2YamlNode> nodes;
  std::vector<Dbow2YamlWord> words;
};

// Parses `text` (the file's whole content). On a problem returns false with
// "<path>:<line>: <problem>" (or "<path>: <problem>" for a missing part) in
// *error. Checks the layout and the types of the values; the tree's shape
// (ranges of ids, counts) is for the caller. Time and memory are linear in
// the text's size.
bool ParseDbow2Yaml(std::string_view text, const std::string& path,
                    Dbow2Yaml* out, std::string* error);

}  // namespace slam::bow

#endif  // SLAM_FRONTENDS_BOW_DBOW2_YAML_H_
