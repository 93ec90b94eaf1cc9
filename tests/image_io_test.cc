// Reading images for the visual pipelines (frontends/image_io.h): the size
// in the header of every parsed format, files that must not be decoded
// (a header declaring 60000 x 60000 pixels), files that are not images
// (FIFO, folder, broken or looping links) and images too small for ORB.
#include "frontends/image_io.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "gtest/gtest.h"
#include "tests/test_util.h"

namespace slam {
namespace {

using testing::Contains;
using testing::TempDir;
using testing::WriteText;

std::string Encode(const cv::Mat& image, const std::string& ext) {
  std::vector<uchar> bytes;
  EXPECT_TRUE(cv::imencode(ext, image, bytes)) << ext;
  return std::string(bytes.begin(), bytes.end());
}

TEST(ImageIoTest, HeaderSizeOfEveryParsedFormatIsTheDecodedSize) {
  cv::Mat grey(23, 37, CV_8U);
  cv::randu(grey, 0, 255);
  cv::Mat colour(23, 37, CV_8UC3);
  cv::randu(colour, 0, 255);
  const std::vector<std::pair<std::string, cv::Mat>> cases = {
      {".png", grey},   {".png", colour}, {".jpg", grey},
      {".jpg", colour}, {".bmp", grey},   {".bmp", colour},
      {".pgm", grey},   {".ppm", colour}, {".webp", colour}};
  for (const auto& [ext, image] : cases) {
    const std::string bytes = Encode(image, ext);
    int64_t width = 0, height = 0;
    ASSERT_TRUE(ImageHeaderSize(bytes, &width, &height)) << ext;
    EXPECT_EQ(width, 37) << ext;
    EXPECT_EQ(height, 23) << ext;
  }
  // Lossless WebP (VP8L) and a PGM header with a comment.
  const std::string lossless = [&] {
    std::vector<uchar> bytes;
    cv::imencode(".webp", colour, bytes, {cv::IMWRITE_WEBP_QUALITY, 101});
    return std::string(bytes.begin(), bytes.end());
  }();
  int64_t width = 0, height = 0;
  ASSERT_TRUE(ImageHeaderSize(lossless, &width, &height));
  EXPECT_EQ(width * 1000 + height, 37023);
  ASSERT_TRUE(
      ImageHeaderSize("P5\n# made by hand\n12 7\n255\n", &width, &height));
  EXPECT_EQ(width * 1000 + height, 12007);
  // Cut short or not an image: no size.
  EXPECT_FALSE(
      ImageHeaderSize(Encode(grey, ".png").substr(0, 20), &width, &height));
  EXPECT_FALSE(
      ImageHeaderSize(Encode(grey, ".jpg").substr(0, 30), &width, &height));
  EXPECT_FALSE(ImageHeaderSize("hello", &width, &height));
}

TEST(ImageIoTest, AHugeDeclaredSizeIsRefusedBeforeDecoding) {
  const std::string dir = TempDir();
  cv::Mat image;
  std::string error;
  // 100 bytes declaring 60000 x 60000: OpenCV throws (or allocates) when
  // asked to decode it.
  WriteText(dir + "/huge.png", testing::PngDeclaring(60000, 60000));
  EXPECT_FALSE(ReadGrayImage(dir + "/huge.png", 1, &image, &error));
  EXPECT_TRUE(Contains(error, dir + "/huge.png: the header declares "
                                    "60000x60000 pixels"))
      << error;
  // A real JPEG whose frame header is patched to the same size.
  std::string jpeg = Encode(cv::Mat(16, 16, CV_8U, cv::Scalar(90)), ".jpg");
  const size_t sof = jpeg.find("\xFF\xC0");
  ASSERT_NE(sof, std::string::npos);
  jpeg[sof + 5] = jpeg[sof + 7] = '\xEA';  // 0xEA60 = 60000.
  jpeg[sof + 6] = jpeg[sof + 8] = '\x60';
  WriteText(dir + "/huge.jpg", jpeg);
  EXPECT_FALSE(ReadGrayImage(dir + "/huge.jpg", 1, &image, &error));
  EXPECT_TRUE(Contains(error, "60000x60000")) << error;
  // The caller's own bound (a loop matrix of N x N pixels).
  cv::imwrite(dir + "/small.png", cv::Mat(20, 30, CV_8U, cv::Scalar(1)));
  EXPECT_FALSE(ReadGrayImage(dir + "/small.png", 1, &image, &error, 500));
  EXPECT_TRUE(ReadGrayImage(dir + "/small.png", 1, &image, &error, 600))
      << error;
  EXPECT_EQ(image.cols, 30);
  // Corrupt data after a plausible header: an error, no exception.
  std::string corrupt = Encode(cv::Mat(64, 64, CV_8U, cv::Scalar(7)), ".png");
  corrupt.resize(60);
  WriteText(dir + "/cut.png", corrupt);
  EXPECT_FALSE(ReadGrayImage(dir + "/cut.png", 1, &image, &error));
  EXPECT_TRUE(Contains(error, dir + "/cut.png")) << error;
}

TEST(ImageIoTest, FilesThatAreNotImagesAndTinyImagesAreNamedErrors) {
  const std::string dir = TempDir();
  namespace fs = std::filesystem;
  ASSERT_EQ(::mkfifo((dir + "/fifo.png").c_str(), 0600), 0);
  fs::create_directories(dir + "/folder.png");
  fs::create_symlink(dir + "/missing.png", dir + "/dangling.png");
  fs::create_symlink(dir + "/loop_b.png", dir + "/loop_a.png");
  fs::create_symlink(dir + "/loop_a.png", dir + "/loop_b.png");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"fifo.png", "cannot read the image: not a regular file (a FIFO)"},
      {"folder.png", "cannot read the image: not a regular file (a directory)"},
      {"dangling.png", "cannot read the image: No such file"},
      {"loop_a.png", "cannot read the image: Too many levels"},
      {"missing.png", "cannot read the image: No such file"}};
  cv::Mat image;
  for (const auto& [name, expected] : cases) {
    std::string error;
    EXPECT_FALSE(ReadGrayImage(dir + "/" + name, 1, &image, &error)) << name;
    EXPECT_TRUE(Contains(error, dir + "/" + name + ": " + expected)) << error;
  }
  // Sides below the ORB pyramid's minimum (cv::resize asserts on them).
  const int min_side = OrbMinImageSide(8, 1.2, 31);
  EXPECT_EQ(min_side, 63);
  EXPECT_EQ(OrbMinImageSide(16, 2.0, 19), 32768);  // 2^15 on the top level.
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(613, 1),
                              cv::Size(1, 400), cv::Size(62, 100)}) {
    cv::imwrite(dir + "/tiny.png", cv::Mat(size, CV_8U, cv::Scalar(3)));
    std::string error;
    EXPECT_FALSE(ReadGrayImage(dir + "/tiny.png", min_side, &image, &error));
    EXPECT_TRUE(Contains(error, "too small for the feature pyramid")) << error;
  }
  cv::imwrite(dir + "/ok.png", cv::Mat(63, 63, CV_8U, cv::Scalar(3)));
  std::string error;
  EXPECT_TRUE(ReadGrayImage(dir + "/ok.png", min_side, &image, &error))
      << error;
}

}  // namespace
}  // namespace slam
