#include "risas/io.hpp"

#include "risas/errors.hpp"

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <fstream>
#include <sstream>

namespace risas {
namespace {

bool endsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

// What a call writes to the process's stderr (file descriptor 2) while it
// runs, captured instead of shown, with OpenCV's log silenced: libpng
// reports a corrupt file or a failed write there itself, before OpenCV
// returns. One call at a time (stderr is one).
template <class F>
std::string capturingStderr(F&& call) {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto level = cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  std::fflush(stderr);
  std::FILE* sink = std::tmpfile();
  const int saved = sink ? ::dup(2) : -1;
  if (saved >= 0) ::dup2(::fileno(sink), 2);  // else it cannot capture: let it through
  const auto restore = [&] {
    std::fflush(stderr);
    if (saved >= 0) {
      ::dup2(saved, 2);
      ::close(saved);
    }
    cv::utils::logging::setLogLevel(level);
  };
  try {
    call();
  } catch (...) {
    restore();
    if (sink) std::fclose(sink);
    throw;
  }
  restore();
  std::string text;
  if (saved >= 0) {
    text.resize(4096);
    std::rewind(sink);
    text.resize(std::fread(text.data(), 1, text.size(), sink));
  }
  if (sink) std::fclose(sink);
  return text;
}

// libjpeg's warning, when `said` holds one, that the image it still
// returned lacks data: the file ends early (a copy cut short), or its data
// are corrupt, and libjpeg filled the rest with grey or with what it could
// resynchronise on. Bytes skipped before a marker ("extraneous bytes")
// pass: a writer's padding loses nothing, and libjpeg's words do not tell
// it from corrupt data it decoded through and then had left over. libjpeg
// prints only a file's first warning, so a file with extraneous bytes and
// truncated later passes too.
std::string jpegDataLost(const std::string& said) {
  for (size_t start = 0; start < said.size();) {
    const size_t end = std::min(said.find('\n', start), said.size());
    const std::string line = said.substr(start, end - start);
    const bool lost = line.rfind("Premature end of JPEG file", 0) == 0 ||
                      (line.rfind("Corrupt JPEG data", 0) == 0 && line.find("extraneous bytes") == std::string::npos);
    if (lost) return line;
    start = end + 1;
  }
  return {};
}

// cv::imread, its complaints (OpenCV's log, libpng's and libjpeg's own
// lines) folded into the one InputError: the first of them says what is
// wrong with the file. An image libjpeg decoded only in part is refused
// too: OpenCV returns it, grey where the data ran out.
cv::Mat readImage(const std::string& path, int flags, const char* what) {
  const std::string prefix = std::string("cannot read ") + what + " image " + path + ": ";
  if (!std::filesystem::is_regular_file(path)) throw InputError(prefix + "no such file");
  cv::Mat image;
  std::string said = capturingStderr([&] {
    try {
      image = cv::imread(path, flags);
    } catch (const cv::Exception&) {
      image.release();
    }
  });
  if (!image.empty()) {
    const std::string lost = jpegDataLost(said);
    if (lost.empty()) return image;
    throw InputError(prefix + lost + " (part of the image is missing)");
  }
  said = said.substr(0, said.find('\n'));
  throw InputError(prefix + (said.empty() ? "not an image OpenCV can decode" : said));
}

// The dimension a DescriptorParams::layout() string gives, or -1 when the
// string is not one. At most four digits a number: no field of a valid
// layout has more, and the reads and the product cannot overflow.
int64_t layoutDimension(const std::string& layout) {
  int ring = 0, pie = 0, bin = 0, vec = 0, end = 0;
  const int read =
      std::sscanf(layout.c_str(), "n_ring=%4d n_pie=%4d n_bin=%4d n_vec=%4d%n", &ring, &pie, &bin, &vec, &end);
  if (read != 4 || ring < 1 || pie < 1 || bin < 1 || vec < 0) return -1;
  if (end == static_cast<int>(layout.size())) return int64_t{ring} * pie * bin * (vec + 1);
  // The shape labels' own histogram (DescriptorParams::shape_weight); the
  // weight read whatever the C locale's decimal point.
  const std::string weighted = " shape_weight=";
  if (layout.compare(static_cast<size_t>(end), weighted.size(), weighted) != 0) return -1;
  const char* last = layout.data() + layout.size();
  double weight = 0.0;
  const auto [stop, error] = std::from_chars(layout.data() + end + weighted.size(), last, weight);
  if (error != std::errc() || stop != last || !(weight > 0.0) || !std::isfinite(weight) || vec < 1) return -1;
  return int64_t{ring} * pie * (bin + vec + 1);
}

// How many numbers an element of a FileStorage dt holds: "f" 1, "3f" 3,
// "2if" 3; -1 when it is no dt.
int64_t numbersPerElement(const std::string& dt) {
  int64_t total = 0;
  for (size_t i = 0; i < dt.size();) {
    int64_t count = 1;
    if (std::isdigit(static_cast<unsigned char>(dt[i]))) {
      count = 0;
      for (; i < dt.size() && std::isdigit(static_cast<unsigned char>(dt[i])) && count < 1000; ++i) {
        count = count * 10 + (dt[i] - '0');
      }
    }
    if (i == dt.size() || !std::strchr("ucwsifdhr", dt[i])) return -1;
    total += count, ++i;
  }
  return dt.empty() ? -1 : total;
}

// A features file's matrix node (empty when absent), read only when it has
// whole-number rows and cols, a dt and data, and they agree with the
// numbers its data holds: OpenCV allocates what rows and cols say before it
// reads the data (a rows of "u1" reads as 2^31 - 1), and a corrupt count
// would ask for gigabytes. An empty matrix's data is no sequence in XML.
cv::Mat matrixNode(const cv::FileNode& node, const std::string& path, const char* name) {
  cv::Mat m;
  if (node.empty()) return m;
  const cv::FileNode rows = node["rows"], cols = node["cols"], dt = node["dt"], data = node["data"];
  if (!node.isMap() || !rows.isInt() || !cols.isInt() || !dt.isString() || !(data.isSeq() || data.isNone())) {
    throw InputError("features file " + path + ": " + name + " is not a matrix of rows, cols, dt and data");
  }
  const int64_t r = static_cast<int>(rows), c = static_cast<int>(cols), per = numbersPerElement(dt.string());
  const int64_t held = data.isSeq() ? static_cast<int64_t>(data.size()) : 0;
  if (r < 0 || c < 0 || per < 0 || r * c * per != held) {
    throw InputError("features file " + path + ": " + name + " says " + std::to_string(r) + " x " + std::to_string(c) +
                     " of '" + dt.string() + "' but holds " + std::to_string(held) + " numbers");
  }
  node >> m;
  return m;
}

// A features file's matrix node as CV_32F, read element by element after:
// a file's numbers of another depth (doubles, integers) are converted, as
// written; several channels are not this file's layout. Empty when absent.
cv::Mat floatMatrix(const cv::FileNode& node, const std::string& path, const char* name) {
  cv::Mat m = matrixNode(node, path, name);
  if (m.empty()) return m;
  if (m.channels() != 1) {
    throw InputError("features file " + path + ": " + name + " has " + std::to_string(m.channels()) +
                     " channels, not 1");
  }
  m.convertTo(m, CV_32F);
  return m;
}

// Every whitespace-separated token of a text file as a finite number:
// InputError naming the file (as `what`) and the first token that is not one.
std::vector<double> numbersInFile(const std::string& path, const char* what) {
  std::ifstream in(path);
  if (!in) throw InputError(std::string("cannot open ") + what + " " + path);
  std::vector<double> values;
  std::string token;
  while (in >> token) {
    std::istringstream number(token);
    double v = 0.0;
    if (!(number >> v) || !number.eof() || !std::isfinite(v)) {
      throw InputError(std::string(what) + " " + path + ": '" + token + "' is not a finite number");
    }
    values.push_back(v);
  }
  return values;
}

}  // namespace

Eigen::MatrixXd readMatrixFile(const std::string& path, int rows, int cols) {
  const std::vector<double> values = numbersInFile(path, "matrix file");
  if (values.size() != static_cast<size_t>(rows) * static_cast<size_t>(cols)) {
    throw InputError("matrix file " + path + " must hold a " + std::to_string(rows) + "x" + std::to_string(cols) +
                     " matrix (" + std::to_string(rows * cols) + " numbers), found " + std::to_string(values.size()));
  }
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows * cols; ++i) m(i / cols, i % cols) = values[static_cast<size_t>(i)];
  return m;
}

Eigen::Isometry3d readPoseFiles(const std::string& rotation_path, const std::string& translation_path) {
  const Eigen::Matrix3d R = readMatrixFile(rotation_path, 3, 3);
  // The dataset writes five to nine digits: R^T R is I within 1e-5 there.
  constexpr double kTolerance = 1e-3;
  const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(off <= kTolerance) || !(R.determinant() > 0.0)) {
    char detail[96];
    std::snprintf(detail, sizeof detail, "R^T R differs from I by %.3g, det R = %.3g", off, R.determinant());
    throw InputError("rotation file " + rotation_path + " does not hold a rotation (" + detail + ")");
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = readMatrixFile(translation_path, 3, 1);
  return T;
}

Intrinsics readIntrinsicsFile(const std::string& path) {
  const std::vector<double> values = numbersInFile(path, "intrinsics file");
  if (values.size() != 9) {
    throw InputError("intrinsics file " + path + " must hold a 3x3 matrix (9 numbers), found " +
                     std::to_string(values.size()));
  }
  try {
    return Intrinsics::fromMatrix(cv::Matx33d(values.data()));
  } catch (const InputError& e) {
    throw InputError("intrinsics file " + path + ": " + e.what());
  }
}

std::vector<SequenceFrame> listSequence(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<SequenceFrame> frames;
  for (int k = 1;; ++k) {
    const fs::path rgb = fs::path(dir) / ("rgb_" + std::to_string(k) + ".png");
    const fs::path depth = fs::path(dir) / ("depth_" + std::to_string(k) + ".png");
    if (!fs::exists(rgb) || !fs::exists(depth)) break;
    frames.push_back({k, rgb.string(), depth.string()});
  }
  return frames;
}

Intrinsics findIntrinsics(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (fs::path p = fs::absolute(dir, ec); !p.empty(); p = p.parent_path()) {
    if (fs::exists(p / "camera-intrinsics.txt")) return readIntrinsicsFile((p / "camera-intrinsics.txt").string());
    if (p == p.parent_path()) break;
  }
  throw InputError("no camera-intrinsics.txt in " + dir + " or any folder above it");
}

RgbdImages readRgbdImages(const std::string& color_path, const std::string& depth_path) {
  // Depth as stored: IMREAD_ANYDEPTH alone would turn a 16-bit colour image
  // into grey and accept it.
  RgbdImages images{readImage(color_path, cv::IMREAD_COLOR, "colour"),
                    readImage(depth_path, cv::IMREAD_UNCHANGED, "depth"), color_path, depth_path};
  if (images.depth_mm.type() != CV_16UC1) {
    throw InputError("depth image " + depth_path + " must be single-channel 16-bit millimetres, got " +
                     describeType(images.depth_mm));
  }
  return images;
}

cv::Mat depthFromUnits(const cv::Mat& depth16, double units_per_metre) {
  // A unit between 10 µm (a 16-bit image's range 0.65 m) and 1 m: beyond
  // them a typo ("--depth-units 5e9") would give every pixel a depth, none a
  // sensor's.
  if (!(units_per_metre >= 1.0 && units_per_metre <= 1e5)) {
    std::ostringstream given;
    given << units_per_metre;
    throw InputError("depth units per metre must be within [1, 100000] (1000: millimetres; TUM RGB-D: 5000), got " +
                     given.str());
  }
  if (units_per_metre == kMillimetreDepthUnits) return depth16;
  cv::Mat metres;
  depth16.convertTo(metres, CV_32F, 1.0 / units_per_metre);
  return metres;
}

RgbdFrame rgbdFrameOf(const RgbdImages& images, const Intrinsics& intrinsics, double depth_units_per_metre) {
  try {
    return RgbdFrame(images.bgr, depthFromUnits(images.depth_mm, depth_units_per_metre), intrinsics);
  } catch (const InputError& e) {
    throw InputError(images.color_path + " + " + images.depth_path + ": " + e.what());
  }
}

RgbdFrame loadRgbdFrame(const std::string& color_path, const std::string& depth_path, const Intrinsics& intrinsics,
                        double depth_units_per_metre) {
  return rgbdFrameOf(readRgbdImages(color_path, depth_path), intrinsics, depth_units_per_metre);
}

void writeFeatures(const std::string& path, const Features& features) {
  const int n = static_cast<int>(features.keypoints.size());
  if (features.descriptors.rows != n || (!features.geometry.empty() && static_cast<int>(features.geometry.size()) != n)) {
    throw InputError("features to write are inconsistent: keypoints, descriptors and geometry differ in count");
  }
  // FileStorage writes into memory (its format from the name's extension),
  // writeTextFile to the file: FileStorage's own file writes ignore errors.
  const std::string name = endsWith(path, ".gz") ? path.substr(0, path.size() - 3) : path;
  cv::FileStorage fs;
  try {
    fs.open(name, cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    throw InputError("cannot write features file " + path + ": " + e.msg);
  }
  if (!fs.isOpened()) throw InputError("cannot write features file " + path);
  cv::Mat points(n, 3, CV_32F), normals(n, 3, CV_32F), radius(n, 1, CV_32F);
  for (int i = 0; i < static_cast<int>(features.geometry.size()); ++i) {
    const KeypointGeometry& g = features.geometry[static_cast<size_t>(i)];
    points.at<float>(i, 0) = g.point.x;
    points.at<float>(i, 1) = g.point.y;
    points.at<float>(i, 2) = g.point.z;
    for (int c = 0; c < 3; ++c) normals.at<float>(i, c) = g.normal[c];
    radius.at<float>(i, 0) = g.support_radius;
  }
  fs << "descriptor_type" << "RISAS";
  if (!features.descriptor_layout.empty()) fs << "descriptor_layout" << features.descriptor_layout;
  cv::write(fs, "keypoints", features.keypoints);
  fs << "descriptors" << features.descriptors;
  if (!features.geometry.empty()) {
    fs << "points3d" << points << "normals" << normals << "support_radius" << radius;
  }
  writeTextFile(path, fs.releaseAndGetString(), "features file");
}

Features readFeatures(const std::string& path) {
  Features features;
  try {
    cv::FileStorage fs(path, cv::FileStorage::READ);
    if (!fs.isOpened()) throw InputError("cannot open features file " + path);
    if (fs["keypoints"].empty() || fs["descriptors"].empty()) {
      throw InputError("features file " + path + " has no keypoints or descriptors node");
    }
    cv::read(fs["keypoints"], features.keypoints);
    features.descriptors = matrixNode(fs["descriptors"], path, "descriptors");
    const cv::Mat points = floatMatrix(fs["points3d"], path, "points3d");
    const cv::Mat normals = floatMatrix(fs["normals"], path, "normals");
    const cv::Mat radius = floatMatrix(fs["support_radius"], path, "support_radius");
    const int n = static_cast<int>(features.keypoints.size());
    if (features.descriptors.rows != n || (n > 0 && features.descriptors.type() != CV_32F)) {
      throw InputError("features file " + path + ": descriptors are not " + std::to_string(n) + " CV_32F rows");
    }
    if (!fs["descriptor_layout"].empty()) {
      fs["descriptor_layout"] >> features.descriptor_layout;
      const int64_t dimension = layoutDimension(features.descriptor_layout);
      if (dimension < 0 || (n > 0 && dimension != features.descriptors.cols)) {
        throw InputError("features file " + path + ": descriptor_layout '" + features.descriptor_layout +
                         "' does not describe its " + std::to_string(features.descriptors.cols) + "-column descriptors");
      }
    }
    if (!points.empty()) {
      if (points.rows != n || points.cols != 3 || normals.rows != n || normals.cols != 3 || radius.rows != n ||
          radius.cols != 1) {
        throw InputError("features file " + path + ": points3d/normals/support_radius do not match the keypoints");
      }
      for (int i = 0; i < n; ++i) {
        features.geometry.push_back({cv::Point3f(points.at<float>(i, 0), points.at<float>(i, 1), points.at<float>(i, 2)),
                                     cv::Vec3f(normals.at<float>(i, 0), normals.at<float>(i, 1), normals.at<float>(i, 2)),
                                     radius.at<float>(i, 0)});
      }
    }
  } catch (const InputError&) {
    throw;
  } catch (const cv::Exception& e) {
    throw InputError("cannot parse features file " + path + ": " + e.msg);
  } catch (const std::exception& e) {
    // OpenCV's parser lets a standard exception out on some corrupt nodes
    // (std::length_error on a matrix node with a key that begins with ':').
    throw InputError("cannot parse features file " + path + ": OpenCV's parser failed (" + e.what() + ")");
  }
  return features;
}

void writeTextFile(const std::string& path, const std::string& text, const std::string& what) {
  // The reason is errno as the failing call left it, read straight after it.
  const auto failed = [&](int error) {
    return InputError("cannot write " + what + " " + path + ": " +
                      (error != 0 ? std::strerror(error) : "the write failed"));
  };
  bool written = true, closed = true;
  int write_error = 0, close_error = 0;
  if (endsWith(path, ".gz")) {
    gzFile file = gzopen(path.c_str(), "wb");
    if (file == nullptr) throw failed(errno);
    // gzwrite takes an unsigned count: the text in pieces of at most 1 GiB.
    for (size_t at = 0; written && at < text.size();) {
      const unsigned piece = static_cast<unsigned>(std::min<size_t>(text.size() - at, size_t{1} << 30));
      errno = 0;
      written = gzwrite(file, text.data() + at, piece) == static_cast<int>(piece);
      write_error = written ? 0 : errno;
      at += piece;
    }
    errno = 0;
    closed = gzclose(file) == Z_OK;  // compresses and writes what is left
    close_error = errno;
  } else {
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (file == nullptr) throw failed(errno);
    errno = 0;
    written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
    write_error = written ? 0 : errno;
    errno = 0;
    closed = std::fclose(file) == 0;  // flushes what fwrite buffered: a full disk often shows only here
    close_error = errno;
  }
  if (!written) throw failed(write_error);
  if (!closed) throw failed(close_error);
}

void requireImageWriter(const std::string& path, const std::string& what) {
  if (!cv::haveImageWriter(path)) {
    const std::string extension = std::filesystem::path(path).extension().string();
    throw InputError("cannot write " + what + " " + path + ": OpenCV has no image writer for " +
                     (extension.empty() ? "a name without an extension" : "'" + extension + "'") +
                     " (.png, .jpg, .tif, ...)");
  }
}

void writeImage(const std::string& path, const cv::Mat& image, const std::string& what) {
  requireImageWriter(path, what);
  // Encoded in memory, then written with writeTextFile's checked writes:
  // cv::imwrite does not check its fclose, so a small image on a full disk
  // came out a success.
  std::vector<uchar> bytes;
  bool encoded = false;
  std::string reason;
  std::string said = capturingStderr([&] {
    try {
      encoded = cv::imencode(std::filesystem::path(path).extension().string(), image, bytes);
    } catch (const cv::Exception& e) {
      reason = e.err;
    }
  });
  if (!encoded) {
    said = said.substr(0, said.find('\n'));
    if (reason.empty()) reason = said.empty() ? "the encoder failed" : said;
    throw InputError("cannot write " + what + " " + path + ": " + reason);
  }
  writeTextFile(path, std::string(bytes.begin(), bytes.end()), what);
}

std::string readTextFile(const std::string& path, const std::string& what) {
  const auto failed = [&](int error) {
    return InputError("cannot read " + what + " " + path + ": " +
                      (error != 0 ? std::strerror(error) : "the read failed"));
  };
  errno = 0;
  gzFile file = gzopen(path.c_str(), "rb");  // reads a file that is not gzip as it is
  if (file == nullptr) throw failed(errno);
  std::string text;
  char buffer[1 << 16];
  int got = 0;
  while ((got = gzread(file, buffer, sizeof buffer)) > 0) text.append(buffer, static_cast<size_t>(got));
  const int error = errno;
  if (got < 0) {
    // The system's reason, or zlib's for a corrupt gzip stream.
    int zlib_error = Z_OK;
    std::string zlib_reason = gzerror(file, &zlib_error);
    gzclose(file);
    if (zlib_reason.rfind(path + ": ", 0) == 0) zlib_reason.erase(0, path.size() + 2);  // zlib names the file too
    if (zlib_error == Z_ERRNO) throw failed(error);
    throw InputError("cannot read " + what + " " + path + ": corrupt gzip data (" + zlib_reason + ")");
  }
  gzclose(file);
  return text;
}

}  // namespace risas
