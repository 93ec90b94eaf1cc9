// The visual pipelines' text and vocabulary readers: a KITTI sequence's
// calib.txt and times.txt (datasets/kitti_sequence_io.h), KITTI poses
// (the ground truth of slam run), and bag-of-words vocabularies in the
// binary format and DBoW2 YAML, plain and gzipped
// (frontends/bow/vocabulary.h). The first byte picks the reader.
#include <string>

#include "datasets/kitti_sequence_io.h"
#include "datasets/trajectory_io.h"
#include "frontends/bow/vocabulary.h"
#include "fuzz/fuzz_util.h"

namespace {

constexpr char kCalibration[] =
    "P0: 300 0 160 0 0 300 60 0 0 0 1 0\n"
    "P1: 300 0 160 -150 0 300 60 0 0 0 1 0\n";

// A two-frame sequence folder (images are listed, never decoded here).
std::string SequenceDir() {
  static const std::string* dir = [] {
    for (const char* name :
         {"seq/image_0/000000.png", "seq/image_0/000001.png",
          "seq/image_1/000000.png", "seq/image_1/000001.png"}) {
      slam::fuzz::WriteScratch(name, "");
    }
    slam::fuzz::WriteScratch("seq/calib.txt", kCalibration);
    return new std::string(slam::fuzz::ScratchDir() + "/seq");
  }();
  return *dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int which = data[0] % 6;
  ++data;
  --size;
  std::string error;
  bool ok = false;
  switch (which) {
    case 0: {  // calib.txt.
      slam::StereoCalibration calibration;
      ok = slam::ReadKittiStereoCalibration(
          slam::fuzz::WriteScratch("calib.txt", data, size), &calibration,
          &error);
      break;
    }
    case 1: {  // times.txt of a two-frame sequence.
      slam::KittiSequenceOptions options;
      const std::string dir = SequenceDir();
      options.times_path = slam::fuzz::WriteScratch("times.txt", data, size);
      slam::KittiSequence sequence;
      ok = slam::ReadKittiSequence(dir, options, &sequence, &error);
      break;
    }
    case 2: {  // poses.txt (KITTI poses).
      slam::TrajectoryReadOptions options;
      options.format = slam::TrajectoryFormat::kKitti;
      slam::TrajectoryData trajectory;
      ok = slam::ReadTrajectory(
          slam::fuzz::WriteScratch("poses.txt", data, size), options,
          &trajectory, &error);
      break;
    }
    default: {  // Vocabularies: binary, DBoW2 YAML, gzipped YAML.
      const char* names[] = {"voc.bin", "voc.yml", "voc.yml.gz"};
      slam::bow::Vocabulary vocabulary;
      ok = vocabulary.Load(
          slam::fuzz::WriteScratch(names[which - 3], data, size), &error);
      break;
    }
  }
  slam::fuzz::CheckResult(ok, error);
  return 0;
}
