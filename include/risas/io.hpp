// Files: intrinsics, RGB-D frames from PNG, features in cv::FileStorage.
// Every reader throws InputError with the path and what is wrong with it;
// every writer throws InputError when the file is not written whole.
#pragma once

#include "risas/features.hpp"
#include "risas/intrinsics.hpp"
#include "risas/rgbd_frame.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace risas {

// A rows x cols matrix as numbers in text, row by row (the dataset's
// R1-k.txt and T1-k.txt poses): InputError unless the file holds exactly
// rows x cols finite numbers and nothing else.
Eigen::MatrixXd readMatrixFile(const std::string& path, int rows, int cols);

// The rigid motion p1 = R p2 + t of a rotation file (3x3) and a translation
// file (3x1, metres), as the dataset's R1-k.txt and T1-k.txt: InputError as
// readMatrixFile, or when R is not a rotation (R^T R off I by more than
// 1e-3, or a reflection).
Eigen::Isometry3d readPoseFiles(const std::string& rotation_path, const std::string& translation_path);

// A 3x3 camera matrix as nine numbers in text, row by row (the
// ManipulatorsDataset's camera-intrinsics.txt).
Intrinsics readIntrinsicsFile(const std::string& path);

// The frames of a sequence in the ManipulatorsDataset layout: rgb_k.png and
// depth_k.png for k = 1, 2, ... up to the first gap.
struct SequenceFrame {
  int index;
  std::string rgb_path;
  std::string depth_path;
};
std::vector<SequenceFrame> listSequence(const std::string& dir);

// camera-intrinsics.txt in `dir` or the nearest folder above it (the dataset
// keeps one at its root); InputError when there is none.
Intrinsics findIntrinsics(const std::string& dir);

// Colour (8-bit, read as BGR) and 16-bit depth images, as read: InputError
// when a file is unreadable or the depth is not 16-bit. The depth's unit is
// the caller's to know: millimetres for OpenNI cameras, ROS 16UC1 and the
// ManipulatorsDataset; a fifth of a millimetre for TUM RGB-D.
struct RgbdImages {
  cv::Mat bgr;
  cv::Mat depth_mm;
  std::string color_path, depth_path;  // the files read, for errors
};
RgbdImages readRgbdImages(const std::string& color_path, const std::string& depth_path);

// 16-bit depth values per metre: millimetres, and TUM RGB-D's 5000.
constexpr double kMillimetreDepthUnits = 1000.0;

// A 16-bit depth image of `units_per_metre` values a metre as CV_32FC1
// metres, 0 where it is 0 (missing), for RgbdFrame; millimetres (1000) are
// returned as they are, which RgbdFrame takes as such. InputError unless
// units_per_metre is within [1, 1e5] (a unit between 10 µm and 1 m).
cv::Mat depthFromUnits(const cv::Mat& depth16, double units_per_metre);

// The images, validated into a frame; the depth at `depth_units_per_metre`
// (depthFromUnits). RgbdFrame's InputError comes back naming both files: a
// recording's one frame without depth is found by its name.
RgbdFrame rgbdFrameOf(const RgbdImages& images, const Intrinsics& intrinsics,
                      double depth_units_per_metre = kMillimetreDepthUnits);
RgbdFrame loadRgbdFrame(const std::string& color_path, const std::string& depth_path, const Intrinsics& intrinsics,
                        double depth_units_per_metre = kMillimetreDepthUnits);

// Nodes: descriptor_type ("RISAS"), descriptor_layout (DescriptorParams::
// layout(), written when known; files without it read as unknown),
// keypoints (cv::write of the std::vector<cv::KeyPoint>, 0-based pixels),
// descriptors (N x D CV_32F), points3d and normals (N x 3 CV_32F, metres /
// unit), support_radius (N x 1). readFeatures: InputError when a
// descriptor_layout does not give the descriptors' width, or the geometry's
// matrices do not match the keypoints or have several channels; their
// numbers of another depth (doubles, integers) are read as CV_32F.
// .yml, .yaml, .xml or .json, by the extension, as cv::FileStorage does;
// with .gz after it (f.yml.gz), compressed.
void writeFeatures(const std::string& path, const Features& features);
Features readFeatures(const std::string& path);

// Writes `text` to `path` whole (gzip-compressed when the path ends in .gz),
// or throws InputError naming `what`, the path and the system's reason.
// std::ofstream and cv::FileStorage let a failed write pass in silence: a
// full disk left a truncated file and the tool said it had written it. The
// library's and the tools' files are written through here.
void writeTextFile(const std::string& path, const std::string& text, const std::string& what);
// Writes `image` whole in the format of the path's extension (as cv::imwrite
// does), or throws InputError naming `what`, the path and the reason:
// OpenCV's missing writer for the extension, the encoder's complaint, or the
// system's ("No space left on device"). cv::imwrite returns a bare false, or
// true for a small image on a full disk.
void writeImage(const std::string& path, const cv::Mat& image, const std::string& what);
// InputError, as writeImage's, unless OpenCV has a writer for the path's
// extension: for tools that check their outputs before the work.
void requireImageWriter(const std::string& path, const std::string& what);
// A file's bytes, gunzipped when it is gzip (whatever its name), or InputError
// naming `what`, the path and the system's reason.
std::string readTextFile(const std::string& path, const std::string& what);

}  // namespace risas
