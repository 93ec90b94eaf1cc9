// End-to-end tests of `slam optimize` (apps/optimize_command.cc) and its YAML
// config (apps/optimize_config.h), run as a process through the real binary:
// a known answer on simulated data with ground truth, the global optima of the
// published pose-graph benchmarks, malformed input, config handling, every
// initialization and solver, marginals, robust kernels and usage errors.
//
// Reports are read with the small JSON parser below (no JSON library is a
// dependency of the project).
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "core/graph.h"
#include "datasets/g2o_io.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using ::slam::testing::Contains;
using ::slam::testing::DatasetPath;
using ::slam::testing::Exists;
using ::slam::testing::ReadText;
using ::slam::testing::RunSlam;
using ::slam::testing::TempDir;
using ::slam::testing::WriteText;

// Names of the entries of a directory.
std::set<std::string> ListDir(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.insert(entry.path().filename().string());
  }
  return names;
}

// ---------------------------------------------------------------------------
// A minimal JSON reader: enough for the reports (objects, arrays, strings
// without unicode escapes, numbers, true/false/null). Parse errors make the
// returned value kind kInvalid.

struct Json {
  enum Kind { kInvalid, kNull, kBool, kNumber, kString, kArray, kObject };
  Kind kind = kInvalid;
  bool boolean = false;
  double number = 0.0;
  std::string string;
  std::vector<Json> array;
  std::vector<std::pair<std::string, Json>> object;

  bool Has(const std::string& key) const { return Find(key) != nullptr; }
  const Json* Find(const std::string& key) const {
    for (const auto& [k, v] : object) {
      if (k == key) return &v;
    }
    return nullptr;
  }
  // The entry `key`; an invalid value when absent.
  const Json& operator[](const std::string& key) const {
    static const Json* const kMissing = new Json();
    const Json* found = Find(key);
    return found != nullptr ? *found : *kMissing;
  }
  // The number at `key`, NaN when absent or not a number.
  double Number(const std::string& key) const {
    const Json& v = (*this)[key];
    return v.kind == kNumber ? v.number : NAN;
  }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : text_(text) {}

  Json ParseDocument() {
    Json value = ParseValue();
    SkipSpace();
    if (pos_ != text_.size()) return Json();
    return value;
  }

 private:
  void SkipSpace() {
    while (pos_ < text_.size() &&
           std::isspace(static_cast<unsigned char>(text_[pos_]))) {
      ++pos_;
    }
  }
  bool Consume(char c) {
    SkipSpace();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  bool ConsumeWord(const char* word) {
    const std::string w(word);
    if (text_.compare(pos_, w.size(), w) != 0) return false;
    pos_ += w.size();
    return true;
  }
  bool ParseString(std::string* out) {
    if (!Consume('"')) return false;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      char c = text_[pos_++];
      if (c == '\\') {
        if (pos_ >= text_.size()) return false;
        const char e = text_[pos_++];
        c = e == 'n' ? '\n' : e == 't' ? '\t' : e;
      }
      out->push_back(c);
    }
    return Consume('"');
  }
  Json ParseValue() {
    SkipSpace();
    Json v;
    if (pos_ >= text_.size()) return v;
    const char c = text_[pos_];
    if (c == '{') {
      ++pos_;
      v.kind = Json::kObject;
      if (Consume('}')) return v;
      do {
        std::string key;
        if (!ParseString(&key) || !Consume(':')) return Json();
        Json child = ParseValue();
        if (child.kind == Json::kInvalid) return Json();
        v.object.emplace_back(key, std::move(child));
      } while (Consume(','));
      if (!Consume('}')) return Json();
    } else if (c == '[') {
      ++pos_;
      v.kind = Json::kArray;
      if (Consume(']')) return v;
      do {
        Json child = ParseValue();
        if (child.kind == Json::kInvalid) return Json();
        v.array.push_back(std::move(child));
      } while (Consume(','));
      if (!Consume(']')) return Json();
    } else if (c == '"') {
      v.kind = Json::kString;
      if (!ParseString(&v.string)) return Json();
    } else if (ConsumeWord("true")) {
      v.kind = Json::kBool;
      v.boolean = true;
    } else if (ConsumeWord("false")) {
      v.kind = Json::kBool;
    } else if (ConsumeWord("null")) {
      v.kind = Json::kNull;
    } else {
      const char* begin = text_.c_str() + pos_;
      char* end = nullptr;
      v.number = std::strtod(begin, &end);
      if (end == begin) return Json();
      v.kind = Json::kNumber;
      pos_ += static_cast<size_t>(end - begin);
    }
    return v;
  }

  const std::string& text_;
  size_t pos_ = 0;
};

Json ParseJson(const std::string& text) {
  return JsonParser(text).ParseDocument();
}

TEST(JsonParserTest, ParsesWhatTheReportsHold) {
  const Json j = ParseJson(
      "{\"a\": 1.5e-3, \"b\": [1, -2, 3e2], \"c\": {\"d\": true, \"e\": "
      "\"x\\\"y\"}, \"f\": null, \"g\": false}\n");
  ASSERT_EQ(j.kind, Json::kObject);
  EXPECT_DOUBLE_EQ(j.Number("a"), 1.5e-3);
  ASSERT_EQ(j["b"].array.size(), 3u);
  EXPECT_DOUBLE_EQ(j["b"].array[2].number, 300.0);
  EXPECT_TRUE(j["c"]["d"].boolean);
  EXPECT_EQ(j["c"]["e"].string, "x\"y");
  EXPECT_EQ(j["f"].kind, Json::kNull);
  EXPECT_EQ(j["g"].kind, Json::kBool);
  EXPECT_FALSE(j["g"].boolean);
  EXPECT_TRUE(std::isnan(j.Number("missing")));
  EXPECT_EQ(ParseJson("{\"a\": 1,}").kind, Json::kInvalid);
  EXPECT_EQ(ParseJson("{\"a\": 1} x").kind, Json::kInvalid);
  EXPECT_EQ(ParseJson("").kind, Json::kInvalid);
}

// ---------------------------------------------------------------------------
// Running the binary.

struct SlamRun {
  int code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
  std::string all() const { return out + err; }
};

// Runs `slam ARGS` with stdout and stderr captured separately into files of
// `log_dir` (kept apart from the directories whose contents are checked).
SlamRun RunCaptured(const std::string& args, const std::string& log_dir) {
  std::filesystem::create_directories(log_dir);
  const std::string out = log_dir + "/stdout";
  const std::string err = log_dir + "/stderr";
  SlamRun run;
  run.code = RunSlam(args + " > '" + out + "' 2> '" + err + "'");
  run.out = ReadText(out);
  run.err = ReadText(err);
  return run;
}

// Reads a JSON report; fails the test when it is missing or malformed.
Json ReadReport(const std::string& path) {
  EXPECT_TRUE(Exists(path)) << path;
  const Json report = ParseJson(ReadText(path));
  EXPECT_EQ(report.kind, Json::kObject) << ReadText(path);
  return report;
}

// The simulated datasets of this process, by argument list -> directory.
std::map<std::string, std::string>* SimulatedDirs() {
  static auto* dirs = new std::map<std::string, std::string>();
  return dirs;
}

// Removes the simulated datasets when the test program ends.
class RemoveSimulatedDatasets : public ::testing::Environment {
 public:
  void TearDown() override {
    for (const auto& [args, dir] : *SimulatedDirs()) {
      std::filesystem::remove_all(std::filesystem::path(dir).parent_path());
    }
  }
};
::testing::Environment* const kRemoveSimulated =
    ::testing::AddGlobalTestEnvironment(new RemoveSimulatedDatasets);

// A simulated dataset (`slam simulate -o DIR EXTRA`), written once per
// distinct argument list for the whole test program (the runs are
// deterministic; the files are only read).
std::string Simulated(const std::string& extra = "") {
  auto* dirs = SimulatedDirs();
  auto it = dirs->find(extra);
  if (it != dirs->end()) return it->second;
  const std::string base =
      std::filesystem::temp_directory_path() /
      ("slam_test_optimize_sim_" + std::to_string(::getpid()) + "_" +
       std::to_string(dirs->size()));
  std::filesystem::remove_all(base);
  std::filesystem::create_directories(base);
  const std::string dir = base + "/sim";
  const std::string log = base + "/log";
  const int code = RunSlam("simulate -o " + dir + " " + extra, log);
  EXPECT_EQ(code, 0) << ReadText(log);
  (*dirs)[extra] = dir;
  return dir;
}

// Relative difference |a - b| / |b|.
double Relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

// ---------------------------------------------------------------------------
// 1. Known answer: simulated 2D grid world, evaluated against its truth.

TEST(OptimizeCommandTest, SimulatedGraphKnownAnswer) {
  const std::string sim = Simulated();
  const std::string tmp = TempDir();
  const std::string out = tmp + "/opt.g2o";
  const std::string report_path = tmp + "/r.json";
  const SlamRun run =
      RunCaptured("optimize -i " + sim + "/graph.g2o -o " + out + " --gt " +
                      sim + "/ground_truth.tum" + " --report " + report_path,
                  tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "(converged)")) << run.out;
  EXPECT_TRUE(Contains(run.out, "wrote " + out)) << run.out;

  const Json report = ReadReport(report_path);
  for (const char* key :
       {"nodes", "factors", "file_chi2", "initial_chi2", "final_chi2",
        "iterations", "init_seconds", "solve_seconds", "total_seconds"}) {
    EXPECT_EQ(report[key].kind, Json::kNumber) << key;
  }
  ASSERT_EQ(report["converged"].kind, Json::kBool);
  EXPECT_TRUE(report["converged"].boolean);
  EXPECT_EQ(report["input"].string, sim + "/graph.g2o");
  EXPECT_EQ(report["init"].string, "chordal");  // auto: the better start.
  EXPECT_EQ(report["solver"].string, "lm");
  EXPECT_EQ(report.Number("repaired_information"), 0.0);

  // The default world: 500 poses, all SE(2), node 0 fixed.
  const double nodes = report.Number("nodes");
  const double factors = report.Number("factors");
  EXPECT_EQ(nodes, 500.0);
  EXPECT_GT(factors, nodes);  // Odometry and loop closures.
  EXPECT_GE(report.Number("iterations"), 1.0);
  EXPECT_GE(report.Number("init_seconds"), 0.0);
  EXPECT_GE(report.Number("solve_seconds"), 0.0);
  EXPECT_GE(report.Number("total_seconds"),
            report.Number("init_seconds") + report.Number("solve_seconds"));
  EXPECT_LT(report.Number("total_seconds"), 10.0);

  // chi2: the optimum of a correctly weighted problem is chi2-distributed
  // with (residual dimension - free parameters) degrees of freedom.
  const double initial = report.Number("initial_chi2");
  const double final_chi2 = report.Number("final_chi2");
  EXPECT_LE(final_chi2, initial);
  EXPECT_LT(initial,
            report.Number("file_chi2"));  // Chordal beats dead reckoning.
  const double dof = 3.0 * factors - 3.0 * (nodes - 1.0);
  const double sigma = std::sqrt(2.0 * dof);
  EXPECT_NEAR(final_chi2, dof, 5.0 * sigma)
      << "dof " << dof << ", sigma " << sigma;

  // Evaluation against the ground truth, in the "evaluation" object.
  ASSERT_EQ(report["evaluation"].kind, Json::kObject) << ReadText(report_path);
  const Json& eval = report["evaluation"];
  EXPECT_EQ(eval.Number("matched_pairs"), nodes);
  ASSERT_EQ(eval["ape_translation"].kind, Json::kObject);
  ASSERT_EQ(eval["rpe_translation"].kind, Json::kObject);
  const double ape = eval["ape_translation"].Number("rmse");
  // Measured: 0.0603 m (0.05 m / 0.01 rad noise, about 320 loop closures);
  // the dead-reckoning start is metres off.
  EXPECT_GT(ape, 0.0);
  EXPECT_LT(ape, 0.12);
  EXPECT_GT(eval["rpe_translation"].Number("rmse"), 0.0);
  EXPECT_LT(eval["rpe_translation"].Number("rmse"), 0.12);
  EXPECT_EQ(eval["ape_translation"].Number("count"), nodes);

  // The output parses and holds the optimized poses: its chi2 is the final
  // chi2 of the report (the writer prints round-trip digits).
  Graph graph;
  std::string error;
  GraphReadReport read_report;
  ASSERT_TRUE(ReadG2o(out, GraphReadOptions(), &graph, &read_report, &error))
      << error;
  EXPECT_EQ(static_cast<double>(graph.NumNodes()), nodes);
  EXPECT_EQ(static_cast<double>(graph.NumFactors()), factors);
  EXPECT_EQ(read_report.fixed, 1);
  EXPECT_LT(Relative(graph.Chi2(), final_chi2), 1e-9);

  // No stray files beside the outputs.
  EXPECT_EQ(ListDir(tmp), (std::set<std::string>{"opt.g2o", "r.json", "logs"}));
}

// The same on a 3D world: SE(3) residuals are 6-dimensional.
TEST(OptimizeCommandTest, Simulated3dGraphKnownAnswer) {
  const std::string sim = Simulated("--world sphere3d --num_poses 300");
  const std::string tmp = TempDir();
  const std::string report_path = tmp + "/r.json";
  const SlamRun run =
      RunCaptured("optimize --quiet -i " + sim + "/graph.g2o" + " --gt " + sim +
                      "/ground_truth.tum" + " --report " + report_path,
                  tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  const Json report = ReadReport(report_path);
  EXPECT_TRUE(report["converged"].boolean);
  const double nodes = report.Number("nodes");
  const double factors = report.Number("factors");
  EXPECT_EQ(nodes, 300.0);
  const double dof = 6.0 * factors - 6.0 * (nodes - 1.0);
  EXPECT_NEAR(report.Number("final_chi2"), dof, 5.0 * std::sqrt(2.0 * dof));
  EXPECT_LE(report.Number("final_chi2"), report.Number("initial_chi2"));
  EXPECT_EQ(report["evaluation"].Number("matched_pairs"), nodes);
  EXPECT_LT(report["evaluation"]["ape_translation"].Number("rmse"), 0.2);
  // --quiet: no per-iteration lines.
  EXPECT_FALSE(Contains(run.out, "iter ")) << run.out;
}

// ---------------------------------------------------------------------------
// 2. Real data: the default settings reach the global optimum.

struct Benchmark {
  const char* file;
  double optimum;  // configs/benchmarks/posegraph.yaml
};

void PrintTo(const Benchmark& b, std::ostream* os) { *os << b.file; }

class OptimizeBenchmarkTest : public ::testing::TestWithParam<Benchmark> {};

TEST_P(OptimizeBenchmarkTest, DefaultSettingsReachTheOptimum) {
  const Benchmark& b = GetParam();
  const std::string path = DatasetPath(b.file);
  SLAM_REQUIRE_DATASET(path);
  const std::string tmp = TempDir();
  const std::string report_path = tmp + "/r.json";
  const SlamRun run =
      RunCaptured("optimize --quiet -i " + path + " --report " + report_path,
                  tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  const Json report = ReadReport(report_path);
  const double final_chi2 = report.Number("final_chi2");
  EXPECT_TRUE(report["converged"].boolean) << report["termination"].string;
  EXPECT_LE(final_chi2, b.optimum * (1.0 + 1e-6))
      << b.file << ": " << final_chi2 << " vs optimum " << b.optimum;
  // Below the published optimum would mean another chi2 convention.
  EXPECT_GE(final_chi2, b.optimum * (1.0 - 1e-6))
      << b.file << ": " << final_chi2 << " vs optimum " << b.optimum;
}

INSTANTIATE_TEST_SUITE_P(
    PoseGraphs, OptimizeBenchmarkTest,
    ::testing::Values(Benchmark{"posegraph_2d/MIT.g2o", 41.1632688352},
                      Benchmark{"posegraph_2d/intel.g2o", 45.0046958106},
                      Benchmark{"posegraph_2d/CSAIL.g2o", 40.5551288478},
                      Benchmark{"posegraph_2d/manhattan.g2o", 3549.03679633},
                      Benchmark{"posegraph_3d/sphere2500.g2o", 727.149667248},
                      Benchmark{"posegraph_3d/torus3D.g2o", 14574.7464388},
                      Benchmark{"posegraph_3d/parking-garage.g2o",
                                1.23869057975},
                      Benchmark{"posegraph_3d/smallGrid3D.g2o", 458.153784299}),
    [](const ::testing::TestParamInfo<Benchmark>& info) {
      std::string name = std::filesystem::path(info.param.file).stem().string();
      for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return name;
    });

// The benchmark discriminates: MIT's own guess leads elsewhere, so reaching
// the optimum above is the work of the initialization.
TEST(OptimizeCommandTest, MitFromTheFileGuessMissesTheOptimum) {
  const std::string path = DatasetPath("posegraph_2d/MIT.g2o");
  SLAM_REQUIRE_DATASET(path);
  const double optimum = 41.1632688352;
  const std::string tmp = TempDir();
  // Gauss-Newton from the file's guess: does not get near it (measured:
  // 6183.6 after the 100 allowed iterations, not converged).
  SlamRun run = RunCaptured("optimize --quiet --init none --solver gn -i " +
                                path + " --report " + tmp + "/gn.json",
                            tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  Json report = ReadReport(tmp + "/gn.json");
  EXPECT_EQ(report["init"].string, "none");
  EXPECT_EQ(report.Number("initial_chi2"), report.Number("file_chi2"));
  EXPECT_GT(report.Number("final_chi2"), 1.5 * optimum);
  // Levenberg-Marquardt from the file's guess: the local minimum at 770.66.
  run = RunCaptured("optimize --quiet --init none -i " + path + " --report " +
                        tmp + "/lm.json",
                    tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  report = ReadReport(tmp + "/lm.json");
  EXPECT_NEAR(report.Number("final_chi2"), 770.66350, 1e-3);
}

// ---------------------------------------------------------------------------
// 3. Malformed input: a message "FILE:LINE: problem", and nothing written.

constexpr char kGoodHead[] =
    "VERTEX_SE2 0 0 0 0\n"
    "VERTEX_SE2 1 1 0 0\n"
    "VERTEX_SE2 2 2 0 0\n"
    "FIX 0\n";

TEST(OptimizeCommandTest, MalformedInputFailsWithFileLineAndProblem) {
  struct Case {
    const char* name;
    std::string text;
    const char* expected;  // In stderr after "FILE:".
  };
  const Case cases[] = {
      {"bad_number",
       std::string(kGoodHead) + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
                                "EDGE_SE2 1 2 1 0 0x 1 0 0 1 0 1\n",
       ":6: bad number '0x'"},
      {"missing_field",
       std::string(kGoodHead) + "\n# a comment\n"
                                "EDGE_SE2 0 1 1 0 0 1 0 0 1 0\n",
       ":7: EDGE_SE2 needs 11 fields after the tag, found 10"},
      {"unknown_vertex",
       std::string(kGoodHead) + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
                                "EDGE_SE2 1 17 1 0 0 1 0 0 1 0 1\n",
       ":6: unknown vertex id 17"},
      {"duplicate_vertex",
       std::string(kGoodHead) + "VERTEX_SE2 1 5 5 0\n"
                                "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n",
       ":5: duplicate vertex id 1 (first defined at line 2)"},
      {"non_pd_information",
       std::string(kGoodHead) + "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"
                                "EDGE_SE2 1 2 1 0 0 1 0 0 -1 0 1\n",
       // The refusal names the option that repairs it.
       ":6: information matrix is not positive definite (the "
       "repair_information option, slam optimize --repair_information, "
       "replaces such matrices by the nearest positive definite ones)"},
      {"non_finite",
       std::string(kGoodHead) + "EDGE_SE2 0 1 nan 0 0 1 0 0 1 0 1\n",
       ":5: non-finite number 'nan'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string tmp = TempDir() + "/" + c.name;
    const std::string work = tmp + "/work";
    std::filesystem::create_directories(work);
    const std::string input = work + "/" + std::string(c.name) + ".g2o";
    WriteText(input, c.text);
    const SlamRun run = RunCaptured("optimize -i " + input + " -o " + work +
                                        "/out.g2o --report " + work + "/r.json",
                                    tmp + "/logs");
    EXPECT_NE(run.code, 0) << run.all();
    EXPECT_TRUE(Contains(run.err, input + c.expected)) << run.err;
    // Nothing written, not even a temporary file.
    EXPECT_EQ(ListDir(work),
              (std::set<std::string>{std::string(c.name) + ".g2o"}));
  }
}

TEST(OptimizeCommandTest, MissingInputFileFails) {
  const std::string tmp = TempDir();
  const std::string work = tmp + "/work";
  std::filesystem::create_directories(work);
  const SlamRun run =
      RunCaptured("optimize -i " + work + "/nothere.g2o -o " + work +
                      "/out.g2o --report " + work + "/r.json",
                  tmp + "/logs");
  EXPECT_EQ(run.code, 1) << run.all();
  EXPECT_TRUE(Contains(run.err, work + "/nothere.g2o: cannot open")) << run.err;
  EXPECT_TRUE(ListDir(work).empty());
}

// A failed run leaves an earlier output in place, untouched.
TEST(OptimizeCommandTest, FailedRunKeepsThePreviousOutput) {
  const std::string tmp = TempDir();
  const std::string work = tmp + "/work";
  std::filesystem::create_directories(work);
  WriteText(work + "/out.g2o", "previous result\n");
  WriteText(work + "/r.json", "{}\n");
  WriteText(work + "/bad.g2o", std::string(kGoodHead) + "EDGE_SE2 0 1\n");
  const SlamRun run =
      RunCaptured("optimize -i " + work + "/bad.g2o -o " + work +
                      "/out.g2o --report " + work + "/r.json",
                  tmp + "/logs");
  EXPECT_EQ(run.code, 1) << run.all();
  EXPECT_TRUE(Contains(run.err, work + "/bad.g2o:5:")) << run.err;
  EXPECT_EQ(ReadText(work + "/out.g2o"), "previous result\n");
  EXPECT_EQ(ReadText(work + "/r.json"), "{}\n");
  EXPECT_EQ(ListDir(work),
            (std::set<std::string>{"bad.g2o", "out.g2o", "r.json"}));
}

TEST(OptimizeCommandTest, RepairInformationAcceptsNonPositiveDefinite) {
  const std::string tmp = TempDir();
  const std::string input = tmp + "/non_pd.g2o";
  // Two information matrices with a negative eigenvalue, one fine.
  WriteText(input, std::string(kGoodHead) +
                       "EDGE_SE2 0 1 1 0 0 1 0 0 -1 0 1\n"
                       "EDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n"
                       "EDGE_SE2 0 2 2 0 0 1 2 0 1 0 1\n");
  const SlamRun run =
      RunCaptured("optimize --repair_information -i " + input + " -o " + tmp +
                      "/out.g2o --report " + tmp + "/r.json",
                  tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.err, "repaired 2 information matrices")) << run.err;
  const Json report = ReadReport(tmp + "/r.json");
  EXPECT_EQ(report.Number("repaired_information"), 2.0);
  EXPECT_EQ(report.Number("nodes"), 3.0);
  EXPECT_EQ(report.Number("factors"), 3.0);
  EXPECT_TRUE(Exists(tmp + "/out.g2o"));
  // The written matrices are the repaired ones: the file reads back without
  // the flag.
  Graph graph;
  std::string error;
  EXPECT_TRUE(
      ReadG2o(tmp + "/out.g2o", GraphReadOptions(), &graph, nullptr, &error))
      << error;
  // Without the flag the same file fails at the first bad matrix.
  const SlamRun strict = RunCaptured("optimize -i " + input, tmp + "/logs");
  EXPECT_EQ(strict.code, 1);
  EXPECT_TRUE(Contains(strict.err, input + ":5: information matrix"))
      << strict.err;
}

// ---------------------------------------------------------------------------
// 4. Config: --dump_config, --config, precedence, errors.

TEST(OptimizeCommandTest, DumpConfigRoundTrips) {
  const std::string tmp = TempDir();
  // Defaults.
  ASSERT_EQ(RunSlam("optimize --dump_config > " + tmp + "/a.yaml"), 0);
  const std::string defaults = ReadText(tmp + "/a.yaml");
  EXPECT_EQ(defaults.rfind("optimize:\n", 0), 0u) << defaults;
  EXPECT_TRUE(Contains(defaults, "  solver: lm\n")) << defaults;
  EXPECT_TRUE(Contains(defaults, "  init: auto\n")) << defaults;
  // The batch pose graph's LM stops for Newton steps under way.
  EXPECT_TRUE(Contains(defaults, "  newton_under_way: true\n")) << defaults;
  ASSERT_EQ(RunSlam("optimize --config " + tmp + "/a.yaml --dump_config > " +
                    tmp + "/b.yaml"),
            0);
  EXPECT_EQ(ReadText(tmp + "/b.yaml"), defaults);

  // Every flag-settable value away from its default.
  ASSERT_EQ(RunSlam("optimize --dump_config --solver dogleg --init chordal"
                    " --robust cauchy:2.5 --max_iterations 7 --ordering amd"
                    " --repair_information --quiet > " +
                    tmp + "/c.yaml"),
            0);
  const std::string custom = ReadText(tmp + "/c.yaml");
  for (const char* line :
       {"  init: chordal\n", "  solver: dogleg\n", "  max_iterations: 7\n",
        "  ordering: amd\n", "  verbose: false\n",
        "  repair_information: true\n", "    odometry: cauchy:2.5\n",
        "    loop_closure: cauchy:2.5\n", "    prior: none\n"}) {
    EXPECT_TRUE(Contains(custom, line)) << line << " in\n" << custom;
  }
  ASSERT_EQ(RunSlam("optimize --config " + tmp + "/c.yaml --dump_config > " +
                    tmp + "/d.yaml"),
            0);
  EXPECT_EQ(ReadText(tmp + "/d.yaml"), custom);

  // Values only the file can set survive the round trip too.
  WriteText(tmp + "/e.yaml",
            "optimize:\n  function_tolerance: 1e-7\n  num_threads: 1\n"
            "  newton_under_way: false\n"
            "  initial_trust_region_radius: 1000.5\n"
            "  robust:\n    prior: huber:0.25\n    loop_closure: dcs:3\n");
  ASSERT_EQ(RunSlam("optimize --config " + tmp + "/e.yaml --dump_config > " +
                    tmp + "/f.yaml"),
            0);
  const std::string file_values = ReadText(tmp + "/f.yaml");
  for (const char* line :
       {"  function_tolerance: 9.9999999999999995e-08\n", "  num_threads: 1\n",
        "  newton_under_way: false\n",
        "  initial_trust_region_radius: 1000.5\n", "    prior: huber:0.25\n",
        "    loop_closure: dcs:3\n", "    odometry: none\n"}) {
    EXPECT_TRUE(Contains(file_values, line)) << line << " in\n" << file_values;
  }
  ASSERT_EQ(RunSlam("optimize --config " + tmp + "/f.yaml --dump_config > " +
                    tmp + "/g.yaml"),
            0);
  EXPECT_EQ(ReadText(tmp + "/g.yaml"), file_values);
}

TEST(OptimizeCommandTest, FlagsOverrideTheConfigFile) {
  const std::string tmp = TempDir();
  WriteText(tmp + "/c.yaml",
            "optimize:\n  solver: dogleg\n  init: chordal\n"
            "  max_iterations: 9\n  robust:\n    odometry: huber:1\n"
            "    prior: cauchy:2\n");
  const SlamRun run = RunCaptured("optimize --config " + tmp +
                                      "/c.yaml --solver gn --robust dcs:4"
                                      " --dump_config",
                                  tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "  solver: gn\n")) << run.out;     // Flag.
  EXPECT_TRUE(Contains(run.out, "  init: chordal\n")) << run.out;  // File.
  EXPECT_TRUE(Contains(run.out, "  max_iterations: 9\n")) << run.out;
  EXPECT_TRUE(Contains(run.out, "    odometry: dcs:4\n")) << run.out;
  EXPECT_TRUE(Contains(run.out, "    loop_closure: dcs:4\n")) << run.out;
  EXPECT_TRUE(Contains(run.out, "    prior: cauchy:2\n")) << run.out;

  // And in a real run: the report names what was used.
  const std::string sim = Simulated();
  const SlamRun opt =
      RunCaptured("optimize --quiet --config " + tmp +
                      "/c.yaml --solver gn --max_iterations 50 -i " + sim +
                      "/graph.g2o --report " + tmp + "/r.json",
                  tmp + "/logs");
  ASSERT_EQ(opt.code, 0) << opt.all();
  const Json report = ReadReport(tmp + "/r.json");
  EXPECT_EQ(report["solver"].string, "gn");
  EXPECT_EQ(report["init"].string, "chordal");
}

TEST(OptimizeCommandTest, BadConfigFilesFailNamingFileAndKey) {
  const std::string tmp = TempDir();
  const std::string sim = Simulated();
  struct Case {
    const char* yaml;
    const char* expected;  // In stderr, after the file name.
  };
  const Case cases[] = {
      {"optimize:\n  solver: lm\n  solvr: gn\n", ":3: unknown key 'solvr'"},
      {"optimise:\n  solver: lm\n", ":1: unknown key 'optimise'"},
      {"optimize:\n  solver: lm\nsimulate:\n  seed: 1\nplot: {}\n",
       ":5: unknown key 'plot'"},
      {"optimize:\n  solver: foo\n", ": optimize.solver 'foo'"},
      {"optimize:\n  max_iterations: many\n",
       ": key 'max_iterations' (line 2)"},
      {"optimize:\n  robust:\n    loop_closure: tukey:1\n",
       ": robust.loop_closure: unknown robust kernel 'tukey'"},
      {"optimize:\n  robust:\n    odometry: none\n    loops: dcs:1\n",
       ":4: unknown key 'loops'"},
      {"optimize: [1, 2\n", ":2:"},
  };
  int index = 0;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.yaml);
    const std::string path = tmp + "/bad" + std::to_string(index++) + ".yaml";
    WriteText(path, c.yaml);
    // Both with --dump_config (no YAML printed) and in a real run (nothing
    // written).
    SlamRun run =
        RunCaptured("optimize --dump_config --config " + path, tmp + "/logs");
    EXPECT_EQ(run.code, 2) << run.all();
    EXPECT_TRUE(Contains(run.err, path + c.expected)) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
    run = RunCaptured("optimize --config " + path + " -i " + sim +
                          "/graph.g2o -o " + tmp + "/out.g2o --report " + tmp +
                          "/r.json",
                      tmp + "/logs");
    EXPECT_EQ(run.code, 2) << run.all();
    EXPECT_TRUE(Contains(run.err, path + c.expected)) << run.err;
    EXPECT_FALSE(Exists(tmp + "/out.g2o"));
    EXPECT_FALSE(Exists(tmp + "/r.json"));
  }
  const SlamRun missing = RunCaptured(
      "optimize --dump_config --config " + tmp + "/none.yaml", tmp + "/logs");
  EXPECT_EQ(missing.code, 2);
  EXPECT_TRUE(Contains(missing.err, tmp + "/none.yaml: no such file"))
      << missing.err;
  // Bad flag values.
  SlamRun flag =
      RunCaptured("optimize --dump_config --solver foo", tmp + "/logs");
  EXPECT_EQ(flag.code, 2);
  EXPECT_TRUE(Contains(flag.err, "--solver 'foo'")) << flag.err;
  flag = RunCaptured("optimize --dump_config --init foo", tmp + "/logs");
  EXPECT_EQ(flag.code, 2);
  EXPECT_TRUE(Contains(flag.err, "init 'foo'")) << flag.err;
  flag = RunCaptured("optimize --dump_config --robust dcs:-1", tmp + "/logs");
  EXPECT_EQ(flag.code, 2);
  EXPECT_TRUE(Contains(flag.err, "--robust")) << flag.err;
  flag = RunCaptured("optimize --dump_config --ordering foo", tmp + "/logs");
  EXPECT_EQ(flag.code, 2);
  EXPECT_TRUE(Contains(flag.err, "ordering 'foo'")) << flag.err;
}

// BUG (apps/optimize_config.cc): values checked by ValidateOptimizeConfig
// (init, ordering, num_threads, ...) are reported without the config file's
// name, and linear_solver / sparse_library are not checked at all: a config
// with `linear_solver: foo` passes --dump_config (exit 0) and a real run
// fails only after loading and initializing, with exit 1 and
// "the solver failed: unknown linear solver 'foo'" (no file named).
// Enable once fixed.
TEST(OptimizeCommandTest, EveryBadConfigValueNamesTheFile) {
  const std::string tmp = TempDir();
  const char* cases[][2] = {
      {"optimize:\n  init: foo\n", "init"},
      {"optimize:\n  ordering: foo\n", "ordering"},
      {"optimize:\n  num_threads: 0\n", "num_threads"},
      {"optimize:\n  max_iterations: -1\n", "max_iterations"},
      {"optimize:\n  linear_solver: foo\n", "linear_solver"},
      {"optimize:\n  sparse_library: foo\n", "sparse_library"},
  };
  int index = 0;
  for (const auto& c : cases) {
    SCOPED_TRACE(c[0]);
    const std::string path = tmp + "/bad" + std::to_string(index++) + ".yaml";
    WriteText(path, c[0]);
    const SlamRun run =
        RunCaptured("optimize --dump_config --config " + path, tmp + "/logs");
    EXPECT_EQ(run.code, 2) << run.all();
    EXPECT_TRUE(Contains(run.err, path)) << run.err;
    EXPECT_TRUE(Contains(run.err, c[1])) << run.err;
  }
}

TEST(OptimizeCommandTest, OneConfigFileServesEveryCommand) {
  const std::string tmp = TempDir();
  const std::string config = tmp + "/all.yaml";
  WriteText(config,
            "simulate:\n  seed: 7\n  world:\n    num_poses: 80\n"
            "optimize:\n  solver: dogleg\n  init: spanning_tree\n"
            "  verbose: false\n"
            "eval:\n  align: origin\n");
  const std::string dir = tmp + "/sim";
  SlamRun run =
      RunCaptured("simulate --config " + config + " -o " + dir, tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "80 poses")) << run.out;
  run = RunCaptured("optimize --config " + config + " -i " + dir +
                        "/graph.g2o --gt " + dir +
                        "/ground_truth.tum --report " + tmp + "/r.json",
                    tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_FALSE(Contains(run.out, "iter ")) << run.out;  // verbose: false.
  const Json report = ReadReport(tmp + "/r.json");
  EXPECT_EQ(report.Number("nodes"), 80.0);
  EXPECT_EQ(report["solver"].string, "dogleg");
  EXPECT_EQ(report["init"].string, "spanning_tree");
  // The eval: section is used for --gt.
  EXPECT_EQ(report["evaluation"]["alignment"]["method"].string, "origin");
  run = RunCaptured("optimize --config " + config + " --dump_config",
                    tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "  solver: dogleg\n")) << run.out;
  EXPECT_FALSE(Contains(run.out, "seed")) << run.out;
  run = RunCaptured("simulate --config " + config + " --dump_config",
                    tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "num_poses: 80")) << run.out;
  EXPECT_FALSE(Contains(run.out, "dogleg")) << run.out;
}

// ---------------------------------------------------------------------------
// 5. Every initialization and every solver reach the same optimum.

TEST(OptimizeCommandTest, EveryInitAndSolverReachTheSameOptimum) {
  const std::string sim = Simulated();
  const std::string tmp = TempDir();
  auto optimize = [&](const std::string& args, const std::string& name) {
    const std::string report = tmp + "/" + name + ".json";
    const SlamRun run =
        RunCaptured("optimize --quiet -i " + sim + "/graph.g2o " + args +
                        " --report " + report,
                    tmp + "/logs");
    EXPECT_EQ(run.code, 0) << args << "\n" << run.all();
    return ReadReport(report);
  };
  const Json reference = optimize("", "default");
  const double optimum = reference.Number("final_chi2");
  const double file_chi2 = reference.Number("file_chi2");
  ASSERT_TRUE(std::isfinite(optimum));
  ASSERT_TRUE(reference["converged"].boolean);

  // The initial chi2 after each initialization (measured on the default
  // world: dead reckoning 131447, chordal 952.7); each start converges to the
  // same optimum, dead reckoning (none = the file's guess = odometry here)
  // included.
  std::map<std::string, double> initial;
  for (const char* init :
       {"none", "odometry", "spanning_tree", "chordal", "auto"}) {
    for (const char* solver : {"lm", "gn", "dogleg"}) {
      SCOPED_TRACE(std::string(init) + " " + solver);
      const Json report =
          optimize(std::string("--init ") + init + " --solver " + solver,
                   std::string(init) + "_" + solver);
      EXPECT_EQ(report["solver"].string, solver);
      EXPECT_EQ(report["init"].string,
                std::string(init) == "auto" ? "chordal" : init);
      EXPECT_TRUE(report["converged"].boolean);
      EXPECT_LT(Relative(report.Number("final_chi2"), optimum), 1e-6)
          << report.Number("final_chi2") << " vs " << optimum;
      initial[init] = report.Number("initial_chi2");
    }
  }
  // The initializations really differ: none keeps the file's guess, which
  // the simulator writes as dead reckoning, i.e. what odometry computes.
  EXPECT_EQ(initial["none"], file_chi2);
  EXPECT_LT(Relative(initial["odometry"], file_chi2), 1e-9);
  EXPECT_LT(initial["chordal"], 0.1 * file_chi2);
  EXPECT_NE(initial["spanning_tree"], initial["chordal"]);
  EXPECT_EQ(initial["auto"], initial["chordal"]);

  // --max_iterations is honoured: one step from dead reckoning does not
  // converge (and still exits 0, with the result written).
  const Json one = optimize("--init none --max_iterations 1", "one");
  EXPECT_EQ(one.Number("iterations"), 1.0);
  EXPECT_FALSE(one["converged"].boolean);
  EXPECT_GT(one.Number("final_chi2"), optimum * (1.0 + 1e-6));
}

// ---------------------------------------------------------------------------
// 6. Marginals.

TEST(OptimizeCommandTest, MarginalsPrintedAndReported) {
  const std::string sim = Simulated();
  const std::string tmp = TempDir();
  const SlamRun run =
      RunCaptured("optimize --quiet -i " + sim +
                      "/graph.g2o --marginals 0,5 --report " + tmp + "/r.json",
                  tmp + "/logs");
  ASSERT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "marginal covariances")) << run.out;
  EXPECT_TRUE(Contains(run.out, "  node 0:\n")) << run.out;
  EXPECT_TRUE(Contains(run.out, "  node 5:\n")) << run.out;
  const Json report = ReadReport(tmp + "/r.json");
  ASSERT_EQ(report["marginals"].kind, Json::kObject)
      << ReadText(tmp + "/r.json");
  const Json& marginals = report["marginals"];
  EXPECT_EQ(marginals.object.size(), 2u);

  // Node 0 is fixed (the gauge): zero covariance.
  ASSERT_EQ(marginals["0"].array.size(), 9u);
  for (const Json& v : marginals["0"].array) EXPECT_EQ(v.number, 0.0);

  // Node 5: symmetric positive definite 3x3, no larger than dead reckoning
  // over the 5 odometry steps from the fixed node allows (0.05 m and
  // 0.01 rad per step and axis: 0.0125 m^2 without the lever arm of the
  // heading errors, 5e-4 rad^2). Measured: 2.6e-3 m^2, 9.6e-5 rad^2.
  ASSERT_EQ(marginals["5"].array.size(), 9u);
  Eigen::Matrix3d cov;
  for (int k = 0; k < 9; ++k)
    cov(k / 3, k % 3) = marginals["5"].array[k].number;
  EXPECT_LT((cov - cov.transpose()).norm(), 1e-12 * cov.norm()) << cov;
  Eigen::LLT<Eigen::Matrix3d> llt(cov);
  EXPECT_EQ(llt.info(), Eigen::Success) << cov;
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov)
                .eigenvalues()
                .minCoeff(),
            0.0)
      << cov;
  EXPECT_GT(cov(0, 0), 0.0);
  EXPECT_LT(cov(0, 0), 2 * 5 * 0.05 * 0.05);
  EXPECT_LT(cov(1, 1), 2 * 5 * 0.05 * 0.05);
  EXPECT_LT(cov(2, 2), 5 * 0.01 * 0.01);

  // The printed block is the reported one (printed with %.6e).
  const size_t at = run.out.find("  node 5:\n");
  ASSERT_NE(at, std::string::npos);
  std::istringstream printed(run.out.substr(at + 10));
  for (int k = 0; k < 9; ++k) {
    double v = NAN;
    printed >> v;
    EXPECT_NEAR(v, cov(k / 3, k % 3), 1e-6 * std::abs(cov(k / 3, k % 3))) << k;
  }
}

TEST(OptimizeCommandTest, MarginalsOfUnknownNodeFail) {
  const std::string sim = Simulated();
  const std::string tmp = TempDir();
  const std::string work = tmp + "/work";
  std::filesystem::create_directories(work);
  SlamRun run = RunCaptured("optimize --quiet -i " + sim +
                                "/graph.g2o --marginals 0,99999 -o " + work +
                                "/out.g2o --report " + work + "/r.json",
                            tmp + "/logs");
  EXPECT_EQ(run.code, 1) << run.all();
  EXPECT_TRUE(Contains(run.err, "marginals")) << run.err;
  EXPECT_TRUE(Contains(run.err, "99999")) << run.err;
  EXPECT_TRUE(Contains(run.err, "no node")) << run.err;
  EXPECT_TRUE(ListDir(work).empty());

  run = RunCaptured("optimize -i " + sim + "/graph.g2o --marginals 0,x -o " +
                        work + "/out.g2o",
                    tmp + "/logs");
  EXPECT_EQ(run.code, 2) << run.all();
  EXPECT_TRUE(Contains(run.err, "--marginals: 'x' is not a node id"))
      << run.err;
  EXPECT_TRUE(ListDir(work).empty());
}

// BUG (apps/optimize_command.cc, marginals): an id that is in neither key
// space is looked up as Pose3Key last, so on a 2D graph the message is
// "marginals: no node pose3(99999) in the graph" -- it names an SE(3) node
// the graph could never hold. The check also runs only after the whole
// optimization (ids could be checked right after loading). Enable once fixed.
TEST(OptimizeCommandTest, MarginalsOfUnknownNodeNameTheRightKind) {
  const std::string sim = Simulated();
  const std::string tmp = TempDir();
  const SlamRun run = RunCaptured(
      "optimize -i " + sim + "/graph.g2o --marginals 99999", tmp + "/logs");
  EXPECT_NE(run.code, 0);
  EXPECT_TRUE(Contains(run.err, "99999")) << run.err;
  EXPECT_FALSE(Contains(run.err, "pose3")) << run.err;
  EXPECT_FALSE(Contains(run.out, "iter ")) << run.out;  // Before solving.
}

// ---------------------------------------------------------------------------
// 7. Robust kernels against outlier loop closures.

TEST(OptimizeCommandTest, RobustKernelDefeatsOutliers) {
  const std::string sim = Simulated("--outlier_fraction 0.1");
  ASSERT_TRUE(Exists(sim + "/outliers.txt"));
  const std::string tmp = TempDir();
  auto ape = [&](const std::string& args, const std::string& name) {
    const std::string report = tmp + "/" + name + ".json";
    const SlamRun run =
        RunCaptured("optimize --quiet -i " + sim + "/graph.g2o --gt " + sim +
                        "/ground_truth.tum --report " + report + " " + args,
                    tmp + "/logs");
    EXPECT_EQ(run.code, 0) << run.all();
    return ReadReport(report)["evaluation"]["ape_translation"].Number("rmse");
  };
  // Measured: 2.64 m without a kernel, 0.176 m with dcs:1.
  const double plain = ape("", "plain");
  const double robust = ape("--robust dcs:1", "dcs");
  EXPECT_LT(robust, 0.3);
  EXPECT_GT(plain, 1.0);
  EXPECT_GT(plain, 5.0 * robust);
  // The same through the config file, on the loop closures only.
  WriteText(tmp + "/c.yaml", "optimize:\n  robust:\n    loop_closure: dcs:1\n");
  const double from_config = ape("--config " + tmp + "/c.yaml", "config");
  EXPECT_LT(from_config, 0.3);
}

// ---------------------------------------------------------------------------
// 9. Usage errors.

TEST(OptimizeCommandTest, UsageErrors) {
  const std::string tmp = TempDir();
  SlamRun run = RunCaptured("optimize", tmp + "/logs");
  EXPECT_EQ(run.code, 2);
  EXPECT_TRUE(Contains(run.err, "no input")) << run.err;
  EXPECT_TRUE(Contains(run.err, "usage: slam optimize -i IN")) << run.err;
  run =
      RunCaptured("optimize -o " + tmp + "/out.g2o --report " + tmp + "/r.json",
                  tmp + "/logs");
  EXPECT_EQ(run.code, 2);
  EXPECT_FALSE(Exists(tmp + "/out.g2o"));
  EXPECT_FALSE(Exists(tmp + "/r.json"));
  run = RunCaptured("frobnicate -i x", tmp + "/logs");
  EXPECT_EQ(run.code, 2);
  EXPECT_TRUE(Contains(run.err, "unknown command 'frobnicate'")) << run.err;
  EXPECT_TRUE(Contains(run.err, "optimize")) << run.err;  // The list.
  run = RunCaptured("", tmp + "/logs");
  EXPECT_EQ(run.code, 2);
  EXPECT_TRUE(Contains(run.err, "usage: slam <command>")) << run.err;
  // An unknown flag is refused by gflags.
  run = RunCaptured("optimize --solverr gn -i x", tmp + "/logs");
  EXPECT_NE(run.code, 0);
  EXPECT_TRUE(Contains(run.err, "solverr")) << run.err;
  // The input may also be given as the only argument.
  const std::string sim = Simulated();
  run = RunCaptured("optimize --quiet " + sim + "/graph.g2o", tmp + "/logs");
  EXPECT_EQ(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.out, "loaded " + sim + "/graph.g2o")) << run.out;
}

// BUG (apps/optimize_command.cc): arguments beyond the input are ignored:
// `slam optimize -i A.g2o B.g2o` optimizes A and exits 0 (slam simulate
// refuses extra arguments with exit 2). Enable once fixed.
TEST(OptimizeCommandTest, ExtraArgumentsAreRefused) {
  const std::string sim = Simulated();
  const std::string tmp = TempDir();
  const SlamRun run = RunCaptured(
      "optimize --quiet -i " + sim + "/graph.g2o extra.g2o", tmp + "/logs");
  EXPECT_EQ(run.code, 2) << run.all();
  EXPECT_TRUE(Contains(run.err, "extra.g2o")) << run.err;
}

// BUG (apps/optimize_command.cc): the output graph (-o) is written before
// --gt is read and before the report is written, so a missing ground-truth
// file ("--gt: FILE: cannot open") or an unwritable --report path ("cannot
// create a temporary file") makes the command fail with exit 1 only after
// the whole optimization, and the -o file of the failed run is left behind.
// Enable once fixed.
TEST(OptimizeCommandTest, LateFailuresLeaveNoOutput) {
  const std::string sim = Simulated();
  const std::string tmp = TempDir();
  const std::string work = tmp + "/work";
  std::filesystem::create_directories(work);
  SlamRun run = RunCaptured("optimize --quiet -i " + sim + "/graph.g2o -o " +
                                work + "/out.g2o --report " + work +
                                "/r.json --gt " + work + "/nothere.tum",
                            tmp + "/logs");
  EXPECT_NE(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.err, work + "/nothere.tum")) << run.err;
  EXPECT_TRUE(ListDir(work).empty());

  run = RunCaptured("optimize --quiet -i " + sim + "/graph.g2o -o " + work +
                        "/out.g2o --report " + work + "/no_dir/r.json",
                    tmp + "/logs");
  EXPECT_NE(run.code, 0) << run.all();
  EXPECT_TRUE(Contains(run.err, work + "/no_dir/r.json")) << run.err;
  EXPECT_TRUE(ListDir(work).empty());
}

}  // namespace
}  // namespace slam
