// slam vocabulary: trains a bag-of-words vocabulary of ORB descriptors
// (frontends/bow/vocabulary.h) on the images of one or more folders and
// writes it in the project's binary format:
//
//   slam vocabulary --images DIR [DIR...] -o VOC [--k 10] [--levels 5]
//                   [--orb_features 1000] [--max_descriptors 0]
//
// `--voc FILE` instead converts an existing vocabulary (a DBoW2 .yml/.yml.gz
// or a binary one) to the binary format. The output is written only when
// everything succeeded.
#include <gflags/gflags.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "apps/visual/image_features.h"
#include "apps/visual/visual_commands.h"
#include "datasets/atomic_file.h"
#include "frontends/bow/vocabulary.h"

DECLARE_string(o);

DEFINE_string(images, "",
              "vocabulary, loops: image folder (vocabulary: more folders may "
              "follow as arguments)");
DEFINE_int32(k, 10, "vocabulary: branches per node");
DEFINE_int32(levels, 5, "vocabulary: levels of the tree");
DEFINE_int64(max_descriptors, 0,
             "vocabulary: cluster at most this many descriptors, evenly "
             "subsampled (0: all; the idf weights count all)");
DEFINE_int32(orb_features, 1000, "vocabulary, loops: ORB features per image");
DEFINE_string(voc, "",
              "vocabulary: convert this vocabulary file instead of training; "
              "loops: the vocabulary to use (default: train on the images)");

namespace slam {

int RunVocabularyCommand(const std::vector<std::string>& args) {
  using Clock = std::chrono::steady_clock;
  if (FLAGS_o.empty()) {
    std::fprintf(stderr, "slam vocabulary: -o VOC is required\n");
    return 2;
  }
  std::string error;
  // Everything that can be checked is checked before the work.
  if (!CheckOutputFile(FLAGS_o, &error)) {
    std::fprintf(stderr, "slam vocabulary: -o %s\n", error.c_str());
    return 1;
  }
  bow::Vocabulary vocabulary;
  const auto start = Clock::now();
  if (!FLAGS_voc.empty()) {
    if (!FLAGS_images.empty() || !args.empty()) {
      std::fprintf(
          stderr, "slam vocabulary: give either --images or --voc, not both\n");
      return 2;
    }
    if (!vocabulary.Load(FLAGS_voc, &error)) {
      std::fprintf(stderr, "slam vocabulary: %s\n", error.c_str());
      return 1;
    }
  } else {
    std::vector<std::string> dirs;
    if (!FLAGS_images.empty()) dirs.push_back(FLAGS_images);
    dirs.insert(dirs.end(), args.begin(), args.end());
    if (dirs.empty()) {
      std::fprintf(stderr,
                   "slam vocabulary: --images DIR [DIR...] is required\n");
      return 2;
    }
    // The bound of the stereo pipeline's features.max_features and of
    // loops.orb_features.
    if (FLAGS_orb_features < 10 || FLAGS_orb_features > 100000 ||
        FLAGS_max_descriptors < 0) {
      std::fprintf(stderr,
                   "slam vocabulary: --orb_features must be in [10, 100000] "
                   "and --max_descriptors >= 0\n");
      return 2;
    }
    bow::VocabularyTrainingOptions options;
    options.k = FLAGS_k;
    options.levels = FLAGS_levels;
    options.max_descriptors = FLAGS_max_descriptors;
    if (!bow::Vocabulary::CheckOptions(options, &error)) {
      std::fprintf(stderr, "slam vocabulary: --k/--levels: %s\n",
                   error.c_str());
      return 2;
    }
    std::vector<std::string> paths;
    for (const std::string& dir : dirs) {
      std::vector<std::string> in_dir;
      if (!ListImages(dir, &in_dir, &error)) {
        std::fprintf(stderr, "slam vocabulary: %s\n", error.c_str());
        return 1;
      }
      paths.insert(paths.end(), in_dir.begin(), in_dir.end());
    }
    std::vector<ImageFeatures> features;
    if (!ExtractOrbFeatures(paths, FLAGS_orb_features, &features, &error)) {
      std::fprintf(stderr, "slam vocabulary: %s\n", error.c_str());
      return 1;
    }
    size_t count = 0;
    const std::vector<cv::Mat> descriptors = DescriptorsOf(features, &count);
    if (count == 0) {
      std::fprintf(stderr,
                   "slam vocabulary: no ORB feature in any of the %zu images "
                   "(blank, uniform or noise images?): nothing to train on\n",
                   paths.size());
      return 1;
    }
    const auto train_start = Clock::now();
    if (!vocabulary.Train(descriptors, options, &error)) {
      std::fprintf(stderr, "slam vocabulary: %s\n", error.c_str());
      return 1;
    }
    std::printf(
        "trained on %zu images, %zu descriptors in %.2f s\n", paths.size(),
        count,
        std::chrono::duration<double>(Clock::now() - train_start).count());
  }
  if (!vocabulary.Save(FLAGS_o, &error)) {
    std::fprintf(stderr, "slam vocabulary: %s\n", error.c_str());
    return 1;
  }
  std::printf(
      "vocabulary: k = %d, L = %d, %zu nodes, %zu words -> %s (%.2f s)\n",
      vocabulary.k(), vocabulary.levels(), vocabulary.num_nodes(),
      vocabulary.size(), FLAGS_o.c_str(),
      std::chrono::duration<double>(Clock::now() - start).count());
  return 0;
}

}  // namespace slam
