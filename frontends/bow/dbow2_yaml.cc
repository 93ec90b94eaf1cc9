#include "frontends/bow/dbow2_yaml.h"

#include <cstdio>
#include <string>
#include <utility>

#include "datasets/text_util.h"

namespace slam::bow {
namespace {

// The longest flow map read (a node is about 150 bytes: ids, a weight and
// 32 byte values); a map not closed within it is an error, not a buffer
// that grows with the file.
constexpr size_t kMaxItemBytes = 4096;

std::string_view Trim(std::string_view s) {
  const size_t first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const size_t last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

// `s` quoted for a message: at most 40 printable characters.
std::string Quote(std::string_view s) { return "'" + text::Printable(s) + "'"; }

// The position of the first '}' outside double quotes in `s`, or npos;
// *quoted says whether `s` starts inside quotes and, on npos, whether it
// ends inside them (so a map read over lines is scanned once).
size_t FindClose(std::string_view s, bool* quoted) {
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '"') {
      *quoted = !*quoted;
    } else if (s[i] == '}' && !*quoted) {
      return i;
    }
  }
  return std::string_view::npos;
}

size_t FindClose(std::string_view s) {
  bool quoted = false;
  return FindClose(s, &quoted);
}

enum class Sequence { kNone, kNodes, kWords };

class Parser {
 public:
  Parser(std::string_view text, const std::string& path, Dbow2Yaml* out,
         std::string* error)
      : text_(text), path_(path), out_(out), error_(error) {}

  bool Run();

 private:
  bool Fail(size_t line, const std::string& problem) {
    *error_ = path_ + ":" + std::to_string(line) + ": " + problem;
    return false;
  }
  // Reads the integer `value` of `key` into *target, once (*has).
  bool Integer(size_t line, std::string_view key, std::string_view value,
               bool* has, int64_t* target) {
    if (*has) return Fail(line, "a second '" + std::string(key) + "'");
    *has = true;
    if (!text::ParseInt64(value, target)) {
      return Fail(line, "'" + std::string(key) + "' must be an integer, not " +
                            Quote(value));
    }
    return true;
  }
  bool CheckBytes();
  bool TopLevelLine(size_t line, std::string_view body);
  bool KeyLine(size_t line, size_t indent, std::string_view body);
  bool Item(size_t line, std::string_view item);

  std::string_view text_;
  const std::string& path_;
  Dbow2Yaml* out_;
  std::string* error_;

  bool marker_seen_ = false;   // "---".
  bool content_seen_ = false;  // Anything but directives, markers, comments.
  bool vocabulary_seen_ = false;
  bool ended_ = false;     // "..." seen.
  size_t key_indent_ = 0;  // 0: not set yet (keys are indented).
  Sequence sequence_ = Sequence::kNone;
  // Keys seen in the vocabulary map.
  bool has_k_ = false, has_levels_ = false, has_scoring_ = false,
       has_weighting_ = false, has_nodes_ = false, has_words_ = false;
};

bool Parser::CheckBytes() {
  size_t line = 1;
  for (const char c : text_) {
    const auto b = static_cast<unsigned char>(c);
    if (b == '\n') {
      ++line;
    } else if ((b < 0x20 && b != '\t' && b != '\r') || b > 0x7e) {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "0x%02x", b);
      return Fail(line, std::string("byte ") + hex +
                            " is not ASCII text (a DBoW2 YAML vocabulary "
                            "is ASCII)");
    }
  }
  return true;
}

bool Parser::TopLevelLine(size_t line, std::string_view body) {
  if (body[0] == '%') {
    if (marker_seen_ || content_seen_) {
      return Fail(line, "a directive after the document start");
    }
    if (body.substr(0, 5) != "%YAML") {
      return Fail(line, "directive " + Quote(body) +
                            " (a DBoW2 YAML vocabulary has only %YAML)");
    }
    return true;
  }
  if (body.substr(0, 3) == "---") {
    if (body.size() > 3) {
      return Fail(line,
                  "a line starting with '---' goes on with text (a DBoW2 "
                  "YAML vocabulary's document marker is '---' alone)");
    }
    if (marker_seen_ || content_seen_) {
      return Fail(line,
                  "'---' after content (a DBoW2 YAML vocabulary is one "
                  "document, its marker before the content)");
    }
    marker_seen_ = true;
    return true;
  }
  if (body == "...") {
    ended_ = true;
    sequence_ = Sequence::kNone;
    return true;
  }
  content_seen_ = true;
  sequence_ = Sequence::kNone;
  const size_t colon = body.find(':');
  if (colon != std::string_view::npos &&
      Trim(body.substr(0, colon)) == "vocabulary") {
    if (vocabulary_seen_) return Fail(line, "a second 'vocabulary' key");
    if (!Trim(body.substr(colon + 1)).empty()) {
      return Fail(line,
                  "'vocabulary' must hold a block map ('vocabulary:' alone "
                  "on its line, its keys indented below), not " +
                      Quote(Trim(body.substr(colon + 1))));
    }
    vocabulary_seen_ = true;
    return true;
  }
  if (!vocabulary_seen_) {
    return Fail(line, Quote(body) +
                          " where a DBoW2 vocabulary starts with "
                          "'vocabulary:' (no 'vocabulary' map: not a DBoW2 "
                          "vocabulary)");
  }
  return Fail(line, Quote(body) +
                        " after the vocabulary map (a DBoW2 YAML vocabulary "
                        "holds only 'vocabulary')");
}

bool Parser::KeyLine(size_t line, size_t indent, std::string_view body) {
  if (key_indent_ == 0) key_indent_ = indent;
  if (indent != key_indent_) {
    return Fail(line, "indented by " + std::to_string(indent) +
                          " where the vocabulary's keys are indented by " +
                          std::to_string(key_indent_));
  }
  const size_t colon = body.find(':');
  if (colon == std::string_view::npos ||
      (colon + 1 < body.size() && body[colon + 1] != ' ' &&
       body[colon + 1] != '\t')) {
    return Fail(line, Quote(body) + " is not 'key: value'");
  }
  const std::string_view key = Trim(body.substr(0, colon));
  const std::string_view value = Trim(body.substr(colon + 1));
  sequence_ = Sequence::kNone;
  auto integer = [&](bool* has, int64_t* target) {
    return Integer(line, key, value, has, target);
  };
  auto sequence = [&](bool* has, Sequence kind) {
    if (*has) return Fail(line, "a second '" + std::string(key) + "'");
    *has = true;
    if (value == "[]") return true;  // Empty.
    if (!value.empty()) {
      return Fail(line, "'" + std::string(key) +
                            "' must hold a block sequence of '- { ... }' "
                            "items, not " +
                            Quote(value));
    }
    sequence_ = kind;
    return true;
  };
  if (key == "k") return integer(&has_k_, &out_->k);
  if (key == "L") return integer(&has_levels_, &out_->levels);
  if (key == "scoringType") return integer(&has_scoring_, &out_->scoring_type);
  if (key == "weightingType") {
    return integer(&has_weighting_, &out_->weighting_type);
  }
  if (key == "nodes") return sequence(&has_nodes_, Sequence::kNodes);
  if (key == "words") return sequence(&has_words_, Sequence::kWords);
  return Fail(line, "unknown key " + Quote(key) +
                        " in the vocabulary map (a DBoW2 vocabulary has k, "
                        "L, scoringType, weightingType, nodes, words)");
}

bool Parser::Item(size_t line, std::string_view item) {
  // item: "{ ... }" with its '}' the first outside quotes.
  const size_t close = FindClose(item);
  if (close + 1 != item.size()) {
    return Fail(line, "text after the flow map's '}': " +
                          Quote(item.substr(close + 1)));
  }
  std::string_view inner = item.substr(1, close - 1);
  const bool is_node = sequence_ == Sequence::kNodes;
  Dbow2YamlNode node;
  Dbow2YamlWord word;
  node.line = word.line = line;
  bool has_id = false, has_parent = false, has_weight = false,
       has_descriptor = false, has_word = false;
  while (!inner.empty()) {
    // The next entry ends at a comma outside quotes.
    size_t end = 0;
    bool quoted = false;
    for (; end < inner.size(); ++end) {
      if (inner[end] == '"') quoted = !quoted;
      if (inner[end] == ',' && !quoted) break;
      if (inner[end] == '{' && !quoted) {
        return Fail(line, "a nested flow map (DBoW2's items hold scalars)");
      }
    }
    if (quoted) return Fail(line, "a quoted string not closed");
    const std::string_view entry = Trim(inner.substr(0, end));
    inner = end < inner.size() ? inner.substr(end + 1) : std::string_view();
    if (entry.empty()) return Fail(line, "an empty entry in a flow map");
    const size_t colon = entry.find(':');
    if (colon == std::string_view::npos) {
      return Fail(line, "entry " + Quote(entry) + " is not key:value");
    }
    const std::string_view key = Trim(entry.substr(0, colon));
    const std::string_view value = Trim(entry.substr(colon + 1));
    auto integer = [&](bool* has, int64_t* target) {
      return Integer(line, key, value, has, target);
    };
    bool ok = true;
    if (key == "nodeId") {
      ok = integer(&has_id, is_node ? &node.node_id : &word.node_id);
    } else if (is_node && key == "parentId") {
      ok = integer(&has_parent, &node.parent_id);
    } else if (is_node && key == "weight") {
      if (has_weight) return Fail(line, "a second 'weight'");
      has_weight = true;
      if (!text::ParseDouble(value, &node.weight)) {
        return Fail(line,
                    "'weight' must be a finite number, not " + Quote(value));
      }
    } else if (is_node && key == "descriptor") {
      if (has_descriptor) return Fail(line, "a second 'descriptor'");
      has_descriptor = true;
      if (value.size() < 2 || value.front() != '"' || value.back() != '"') {
        return Fail(
            line, "'descriptor' must be a quoted string, not " + Quote(value));
      }
      node.descriptor = std::string(value.substr(1, value.size() - 2));
    } else if (!is_node && key == "wordId") {
      ok = integer(&has_word, &word.word_id);
    } else {
      return Fail(line, "unknown key " + Quote(key) + " in a " +
                            (is_node ? "node" : "word") +
                            (is_node ? " (nodeId, parentId, weight, descriptor)"
                                     : " (wordId, nodeId)"));
    }
    if (!ok) return false;
  }
  if (is_node) {
    if (!has_id || !has_parent || !has_weight || !has_descriptor) {
      return Fail(line, "a node needs nodeId, parentId, weight, descriptor");
    }
    out_->nodes.push_back(std::move(node));
  } else {
    if (!has_word || !has_id) {
      return Fail(line, "a word needs wordId, nodeId");
    }
    out_->words.push_back(word);
  }
  return true;
}

bool Parser::Run() {
  *out_ = Dbow2Yaml();
  if (!CheckBytes()) return false;
  std::string item;  // A flow map being read over several lines.
  size_t item_line = 0;
  bool item_quoted = false;  // Its text so far ends inside quotes.
  size_t line = 0;
  size_t start = 0;
  while (start < text_.size()) {
    size_t end = text_.find('\n', start);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view raw = text_.substr(start, end - start);
    start = end + 1;
    ++line;
    if (!item.empty()) {
      const std::string_view more = Trim(raw);
      if (item.size() + 1 + more.size() > kMaxItemBytes) {
        return Fail(item_line, "a flow map not closed within " +
                                   std::to_string(kMaxItemBytes) + " bytes");
      }
      item += ' ';
      item += more;
      if (FindClose(more, &item_quoted) != std::string_view::npos) {
        if (!Item(item_line, item)) return false;
        item.clear();
      }
      continue;
    }
    const size_t indent = raw.find_first_not_of(' ');
    if (indent == std::string_view::npos) continue;  // Blank.
    if (raw[indent] == '\t') {
      return Fail(line, "a tab in the indentation (YAML indents with spaces)");
    }
    const std::string_view body = Trim(raw.substr(indent));
    if (body.empty() || body[0] == '#') continue;
    if (ended_) return Fail(line, "text after the document end '...'");
    if (indent == 0) {
      if (!TopLevelLine(line, body)) return false;
      continue;
    }
    if (!vocabulary_seen_) {
      return Fail(line, "indented text " + Quote(body) +
                            " before 'vocabulary:' (not a DBoW2 vocabulary)");
    }
    if (body[0] == '-' && (body.size() == 1 || body[1] == ' ')) {
      if (sequence_ == Sequence::kNone) {
        return Fail(line, "a sequence item outside 'nodes' and 'words'");
      }
      if (indent < key_indent_) {
        return Fail(line, "a sequence item indented less than its key");
      }
      const std::string_view rest = Trim(body.substr(1));
      if (rest.empty() || rest[0] != '{') {
        return Fail(line, "a sequence item that is not a flow map '{ ... }'");
      }
      item_quoted = false;
      if (FindClose(rest, &item_quoted) != std::string_view::npos) {
        if (!Item(line, rest)) return false;
      } else {
        if (rest.size() > kMaxItemBytes) {
          return Fail(line, "a flow map longer than " +
                                std::to_string(kMaxItemBytes) + " bytes");
        }
        item = std::string(rest);
        item_line = line;
      }
      continue;
    }
    if (!KeyLine(line, indent, body)) return false;
  }
  if (!item.empty()) {
    return Fail(item_line, "a flow map not closed with '}'");
  }
  if (!vocabulary_seen_) {
    *error_ = path_ + ": no 'vocabulary' map (not a DBoW2 vocabulary)";
    return false;
  }
  if (!has_k_ || !has_levels_ || !has_nodes_ || !has_words_) {
    *error_ = path_ +
              ": DBoW2 vocabulary needs integers k, L and sequences nodes, "
              "words (missing: " +
              (!has_k_        ? "k"
               : !has_levels_ ? "L"
               : !has_nodes_  ? "nodes"
                              : "words") +
              ")";
    return false;
  }
  return true;
}

}  // namespace

bool ParseDbow2Yaml(std::string_view text, const std::string& path,
                    Dbow2Yaml* out, std::string* error) {
  Parser parser(text, path, out, error);
  if (parser.Run()) return true;
  *out = Dbow2Yaml();
  return false;
}

}  // namespace slam::bow
