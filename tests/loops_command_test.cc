// `slam vocabulary` and `slam loops`: bad input gives a clear error and no
// output; the rtabmap samples meet the target with the defaults.
#include <sys/stat.h>

#include <filesystem>
#include <regex>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/visual/image_features.h"
#include "apps/visual/loops_config.h"
#include "frontends/bow/vocabulary.h"
#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::Contains;
using testing::Exists;
using testing::ReadText;
using testing::RunSlam;

// A folder with `n` textured images 1.png ... n.png.
std::string MakeImages(const std::string& dir, int n) {
  std::filesystem::create_directories(dir);
  cv::RNG rng(12345);
  for (int i = 1; i <= n; ++i) {
    cv::Mat image(240, 320, CV_8U);
    rng.fill(image, cv::RNG::UNIFORM, 0, 255);
    cv::GaussianBlur(image, image, cv::Size(5, 5), 1.5);
    cv::imwrite(dir + "/" + std::to_string(i) + ".png", image);
  }
  return dir;
}

// The number after "key": in a JSON report (NaN when absent).
double JsonNumber(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([-0-9.e+]+)")))
    return std::nan("");
  return std::stod(m[1]);
}

TEST(LoopsCommandTest, NaturalOrderSortsNumbersByValue) {
  EXPECT_TRUE(NaturalLess("2.jpg", "10.jpg"));
  EXPECT_FALSE(NaturalLess("10.jpg", "2.jpg"));
  EXPECT_TRUE(NaturalLess("img9_b", "img10_a"));
  EXPECT_TRUE(NaturalLess("a1", "a01"));  // Same value: shorter first.
  EXPECT_FALSE(NaturalLess("x", "x"));
  EXPECT_TRUE(NaturalLess("abc", "abd"));
}

TEST(LoopsCommandTest, ConfigRoundTripsThroughItsYamlDump) {
  // Every printed key must be accepted back (a key missing from the known
  // list would make --dump_config output unusable as a config).
  LoopsConfig config;
  config.vocabulary = "voc.bin";
  config.vocabulary_max_descriptors = 1234;
  config.detector.prior_keyframes = 3;
  config.detector.min_normalized_score = 0.45;
  config.detector.max_query_gap = 4;
  config.detector.verification = bow::Verification::kStereoPnp;
  config.detector.stereo.min_pixel_sigma = 0.75;
  const std::string path = testing::TempDir() + "/loops.yaml";
  testing::WriteText(path, LoopsConfigToYaml(config));
  LoopsConfig loaded;
  std::string error;
  ASSERT_TRUE(LoadLoopsConfig(path, &loaded, &error)) << error;
  EXPECT_EQ(LoopsConfigToYaml(loaded), LoopsConfigToYaml(config));
  EXPECT_EQ(loaded.detector.prior_keyframes, 3);
  EXPECT_EQ(loaded.vocabulary_max_descriptors, 1234);
}

TEST(LoopsCommandTest, BadInputFailsNamingTheFileWithoutOutput) {
  const std::string dir = testing::TempDir();
  const std::string log = dir + "/log.txt";
  const std::string report = dir + "/report.json";

  // Missing folder.
  EXPECT_NE(
      RunSlam("loops --images " + dir + "/nowhere --report " + report, log), 0);
  EXPECT_TRUE(Contains(ReadText(log), dir + "/nowhere")) << ReadText(log);
  EXPECT_FALSE(Exists(report));

  // Unreadable image.
  const std::string images = MakeImages(dir + "/images", 3);
  testing::WriteText(images + "/4.png", "not a png");
  EXPECT_NE(RunSlam("loops --images " + images + " --report " + report, log),
            0);
  EXPECT_TRUE(Contains(ReadText(log), images + "/4.png")) << ReadText(log);
  EXPECT_FALSE(Exists(report));
  std::filesystem::remove(images + "/4.png");

  // Ground truth of the wrong size.
  const std::string gt = dir + "/gt.png";
  cv::imwrite(gt, cv::Mat::zeros(4, 4, CV_8U));
  EXPECT_NE(RunSlam("loops --images " + images + " --gt " + gt + " --report " +
                        report,
                    log),
            0);
  EXPECT_TRUE(Contains(ReadText(log), gt)) << ReadText(log);
  EXPECT_TRUE(Contains(ReadText(log), "4 x 4 pixels but there are 3 images"))
      << ReadText(log);
  EXPECT_FALSE(Exists(report));

  // Unreadable ground truth.
  testing::WriteText(dir + "/gt.bmp", "BM garbage");
  EXPECT_NE(RunSlam("loops --images " + images + " --gt " + dir +
                        "/gt.bmp --report " + report,
                    log),
            0);
  EXPECT_TRUE(Contains(ReadText(log), dir + "/gt.bmp")) << ReadText(log);

  // Corrupt vocabulary (absurd k).
  std::string bytes = "SLAMBOW1";
  for (uint32_t v : {1000000u, 5u, 32u, 100u})
    bytes.append(reinterpret_cast<const char*>(&v), 4);
  testing::WriteText(dir + "/bad.voc", bytes);
  EXPECT_NE(RunSlam("loops --images " + images + " --voc " + dir +
                        "/bad.voc --report " + report,
                    log),
            0);
  EXPECT_TRUE(Contains(ReadText(log), dir + "/bad.voc")) << ReadText(log);
  EXPECT_FALSE(Exists(report));

  // Unknown config key.
  testing::WriteText(dir + "/c.yaml", "loops:\n  min_normalised_score: 0.2\n");
  EXPECT_NE(
      RunSlam("loops --images " + images + " --config " + dir + "/c.yaml", log),
      0);
  EXPECT_TRUE(Contains(ReadText(log), "min_normalised_score")) << ReadText(log);

  // slam vocabulary: missing folder among several, no output.
  const std::string voc = dir + "/out.voc";
  EXPECT_NE(RunSlam("vocabulary --images " + images + " " + dir +
                        "/missing -o " + voc,
                    log),
            0);
  EXPECT_TRUE(Contains(ReadText(log), dir + "/missing")) << ReadText(log);
  EXPECT_FALSE(Exists(voc));
}

// Issue 26: the image commands check their flags, outputs and inputs
// before the work, refuse images ORB cannot take and endless inputs, and a
// failure leaves no folder behind.
TEST(LoopsCommandTest, ChecksComeBeforeTheWorkAndFailuresLeaveNothing) {
  const std::string dir = testing::TempDir();
  const std::string log = dir + "/log.txt";
  const std::string images = MakeImages(dir + "/images", 3);
  const std::string voc = dir + "/out.voc";
  // Feature extraction prints "features: N / N images" on stderr: a check
  // that fails before the work fails before that line.
  struct Case {
    std::string args;
    int code;
    std::string expected;
  };
  std::filesystem::create_directories(dir + "/a_folder");
  const std::vector<Case> cases = {
      {"vocabulary --images " + images + " -o " + voc +
           " --orb_features 2000000000",
       2, "--orb_features must be in [10, 100000]"},
      {"vocabulary --images " + images + " -o " + voc + " --k 1", 2,
       "branching factor k = 1"},
      {"vocabulary --images " + images + " -o " + voc + " --k 100000", 2,
       "branching factor k = 100000"},
      {"vocabulary --images " + images + " -o " + voc + " --levels 0", 2,
       "levels L = 0"},
      {"vocabulary --images " + images + " -o " + voc + " --levels 20", 2,
       "levels L = 20"},
      {"vocabulary --images " + images + " -o " + dir + "/a_folder", 1,
       dir + "/a_folder: is a directory"},
      {"vocabulary --images " + images + " -o " + dir + "/no/such.voc", 1,
       "the folder " + dir + "/no does not exist"},
      {"vocabulary --images " + images + " -o /proc/no_such_file.voc", 1,
       "cannot write in /proc"},
      {"vocabulary --voc /dev/zero -o " + voc, 1, "/dev/zero: larger than"},
      {"loops --images " + images + " --report " + dir + "/a_folder", 1,
       dir + "/a_folder: is a directory"},
      {"loops --images " + images + " --report " + dir + "/no/r.json", 1,
       "the folder " + dir + "/no does not exist"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(RunSlam(c.args, log), c.code) << c.args << "\n" << ReadText(log);
    EXPECT_TRUE(Contains(ReadText(log), c.expected)) << c.args << "\n"
                                                     << ReadText(log);
    EXPECT_FALSE(Contains(ReadText(log), "features:")) << c.args << "\n"
                                                       << ReadText(log);
    EXPECT_FALSE(Exists(voc));
  }

  // Images too small for ORB's pyramid (cv::resize asserted on them), one
  // among real ones: named.
  cv::imwrite(images + "/2.png", cv::Mat(1, 1, CV_8U, cv::Scalar(128)));
  for (const std::string& args :
       {"vocabulary --images " + images + " -o " + voc,
        "loops --images " + images}) {
    EXPECT_EQ(RunSlam(args, log), 1) << args << "\n" << ReadText(log);
    EXPECT_TRUE(Contains(ReadText(log), images +
                                            "/2.png: 1x1 pixels: too small "
                                            "for the feature pyramid"))
        << ReadText(log);
  }

  // Featureless images fail training after the folder of the plots was
  // made: the folder goes with the failure; the vocabulary command says why.
  const std::string blank = dir + "/blank";
  std::filesystem::create_directories(blank);
  for (int i = 1; i <= 3; ++i) {
    cv::imwrite(blank + "/" + std::to_string(i) + ".png",
                cv::Mat(120, 160, CV_8U, cv::Scalar(0)));
  }
  EXPECT_EQ(RunSlam("loops --images " + blank + " --plot " + dir +
                        "/new/plots --report " + dir + "/r.json",
                    log),
            1)
      << ReadText(log);
  EXPECT_FALSE(Exists(dir + "/new")) << ReadText(log);
  EXPECT_EQ(RunSlam("vocabulary --images " + blank + " -o " + voc, log), 1);
  EXPECT_TRUE(Contains(ReadText(log), "no ORB feature in any of the 3 images"))
      << ReadText(log);

  // A FIFO without a writer as a text input: an error, not a hang.
  ASSERT_EQ(::mkfifo((dir + "/fifo.yaml").c_str(), 0600), 0);
  EXPECT_EQ(
      RunSlam("loops --images " + images + " --config " + dir + "/fifo.yaml",
              log),
      1);
  EXPECT_TRUE(Contains(ReadText(log), "fifo.yaml: a FIFO with no writer"))
      << ReadText(log);
  ASSERT_EQ(::mkfifo((dir + "/fifo.bmp").c_str(), 0600), 0);
  EXPECT_EQ(
      RunSlam("loops --images " + images + " --gt " + dir + "/fifo.bmp", log),
      1);
  EXPECT_TRUE(Contains(ReadText(log),
                       "fifo.bmp: cannot read the image: not "
                       "a regular file (a FIFO)"))
      << ReadText(log);
}

// Standard output closed by its reader: the command is not killed by
// SIGPIPE (exit 141) but fails on the write error.
TEST(LoopsCommandTest, AClosedStdoutIsAnErrorNotASignal) {
  const std::string dir = testing::TempDir();
  const std::string script = dir + "/pipe.sh";
  testing::WriteText(script, "set -o pipefail\n" + std::string(SLAM_BINARY) +
                                 " loops --dump_config 2> " + dir +
                                 "/err.txt | (exec 0<&-; sleep 0.5)\n");
  const int status = std::system(("bash " + script).c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_TRUE(
      Contains(ReadText(dir + "/err.txt"), "cannot write to standard output"))
      << ReadText(dir + "/err.txt");
}

TEST(LoopsCommandTest, VocabularyCommandTrainsAndConverts) {
  const std::string dir = testing::TempDir();
  const std::string images = MakeImages(dir + "/a", 4);
  const std::string more = MakeImages(dir + "/b", 2);
  const std::string voc = dir + "/out.voc";
  ASSERT_EQ(RunSlam("vocabulary --images " + images + " " + more + " -o " +
                        voc + " --k 6 --levels 3",
                    dir + "/log.txt"),
            0)
      << ReadText(dir + "/log.txt");
  bow::Vocabulary loaded;
  std::string error;
  ASSERT_TRUE(loaded.Load(voc, &error)) << error;
  EXPECT_EQ(loaded.k(), 6);
  EXPECT_EQ(loaded.levels(), 3);
  EXPECT_GT(loaded.size(), 100u);

  const std::string yml =
      testing::DatasetPath("bow_rtabmap_samples/small_voc.yml.gz");
  SLAM_REQUIRE_DATASET(yml);
  ASSERT_EQ(RunSlam("vocabulary --voc " + yml + " -o " + voc), 0);
  ASSERT_TRUE(loaded.Load(voc, &error)) << error;
  EXPECT_EQ(loaded.size(), 692u);
}

TEST(LoopsCommandTest, RtabmapSamplesMeetTheTargetWithTheDefaults) {
  const std::string data = testing::DatasetPath("bow_rtabmap_samples");
  SLAM_REQUIRE_DATASET(data + "/samples_GT.bmp");
  const std::string dir = testing::TempDir();
  const std::string report = dir + "/report.json";
  ASSERT_EQ(RunSlam("loops --images " + data + "/samples --gt " + data +
                        "/samples_GT.bmp --report " + report + " --plot " +
                        dir + "/plots",
                    dir + "/log.txt"),
            0)
      << ReadText(dir + "/log.txt");
  const std::string json = ReadText(report);
  EXPECT_EQ(JsonNumber(json, "queries"), 84);
  EXPECT_EQ(JsonNumber(json, "images_with_loop"), 44);
  // The target: 100 % precision at >= 80 % recall.
  EXPECT_EQ(JsonNumber(json, "precision"), 1.0);
  EXPECT_GE(JsonNumber(json, "recall"), 0.8);
  EXPECT_GE(JsonNumber(json, "recall_at_100_precision"), 0.8);
  EXPECT_GE(JsonNumber(json, "auc"), 0.8);
  EXPECT_GT(JsonNumber(json, "query_ms_median"), 0.0);
  EXPECT_TRUE(Exists(dir + "/plots/pr_curve.png"));
  EXPECT_TRUE(Exists(dir + "/plots/loop_matrix.png"));
}

}  // namespace
}  // namespace slam
