// Files: parameters, intrinsics, frames and features round-trip; corrupt or
// wrong files give InputError (or runtime_error for unreadable parameter files).
#include "input_error.hpp"
#include "synthetic_fixtures.hpp"
#include "tool_run.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"
#include "risas/tum_sequence.hpp"

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace risas {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path;
  TempDir() : path(fs::temp_directory_path() / ("risas_test_io_" + std::to_string(::getpid()))) {
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name)) << text;
    return file(name);
  }
};

TEST(ParamsFile, RoundTripsEveryField) {
  const TempDir dir;
  RisasParams params;
  params.detector.tau = 0.65;
  params.detector.max_keypoints = 321;
  params.descriptor.n_pie = 12;
  params.descriptor.gamma = 0.7;
  params.match.cross_check = true;
  params.motion.seed = 77;
  for (const char* name : {"p.yml", "p.json", "p.yml.gz", "p.xml.gz"}) {  // FileStorage's formats, gzip too
    params.save(dir.file(name));
    const RisasParams loaded = RisasParams::load(dir.file(name));
    EXPECT_DOUBLE_EQ(loaded.detector.tau, 0.65) << name;
    EXPECT_EQ(loaded.detector.max_keypoints, 321) << name;
    EXPECT_EQ(loaded.descriptor.n_pie, 12) << name;
    EXPECT_DOUBLE_EQ(loaded.descriptor.gamma, 0.7) << name;
    EXPECT_TRUE(loaded.match.cross_check) << name;
    EXPECT_EQ(loaded.motion.seed, 77u) << name;
    EXPECT_EQ(loaded.descriptor.n_bin, RisasParams().descriptor.n_bin) << name;
  }
}

TEST(ParamsFile, PartialFileKeepsDefaultsAndBadFilesAreErrors) {
  const TempDir dir;
  const RisasParams partial = RisasParams::load(dir.write("partial.yml", "%YAML:1.0\ndescriptor:\n  n_bin: 16\n"));
  EXPECT_EQ(partial.descriptor.n_bin, 16);
  EXPECT_DOUBLE_EQ(partial.detector.tau, 0.8);
  EXPECT_THROW(RisasParams::load(dir.write("range.yml", "%YAML:1.0\ndetector:\n  tau: 2.0\n")), std::invalid_argument);
  EXPECT_THROW(RisasParams::load(dir.write("text.yml", "%YAML:1.0\ndetector:\n  tau: high\n")), std::invalid_argument);
  EXPECT_THROW(RisasParams::load(dir.write("corrupt.yml", "%YAML:1.0\ndetector: [1, {\n")), std::runtime_error);
  // A key that begins with ':' makes OpenCV's parser throw std::length_error.
  try {
    RisasParams::load(dir.write("colon.yml", "%YAML:1.0\ndetector:\n   data: [ 0.5 ]\n   :ata: [ X ]\n"));
    ADD_FAILURE() << "a parameter file with a ':' key was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot parse parameter file"), std::string::npos) << e.what();
  }
  EXPECT_THROW(RisasParams::load(dir.file("missing.yml")), std::runtime_error);
}

// A YAML parameter file needs no "%YAML" line (OpenCV 4.6 needs one; rosparam,
// PyYAML and later OpenCV do not); a parse error names the file's own line.
TEST(ParamsFile, YamlWithoutItsDirectiveIsRead) {
  const TempDir dir;
  EXPECT_EQ(RisasParams::load(dir.write("plain.yml", "descriptor:\n  n_bin: 16\n")).descriptor.n_bin, 16);
  EXPECT_DOUBLE_EQ(RisasParams::load(dir.write("comment.yaml", "# mine\nmatch: {ratio: 0.9}\n")).match.ratio, 0.9);
  EXPECT_DOUBLE_EQ(RisasParams::load(dir.write("bom.yml", "\xEF\xBB\xBFmatch:\n  ratio: 0.7\n")).match.ratio, 0.7);
  EXPECT_DOUBLE_EQ(RisasParams::load(dir.write("p.json", "{\"match\": {\"ratio\": 0.6}}")).match.ratio, 0.6);
  EXPECT_DOUBLE_EQ(RisasParams::load(dir.write("empty.yml", "")).match.ratio, RisasParams().match.ratio);
  const auto error = [](const std::string& path) {
    try {
      RisasParams::load(path);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string broken = "match:\n   ratio 0.9\n  bad: [\n";  // line 3 is out of line
  const std::string plain = dir.write("broken.yml", broken), headed = dir.write("broken_headed.yml", "%YAML:1.0\n" + broken);
  EXPECT_NE(error(plain).find(plain + "(3): Incorrect indentation"), std::string::npos) << error(plain);
  EXPECT_NE(error(headed).find(headed + "(4): Incorrect indentation"), std::string::npos) << error(headed);
  EXPECT_EQ(error(dir.path.string()), "cannot read parameter file " + dir.path.string() + ": Is a directory");
  EXPECT_EQ(error(dir.file("missing.yml")),
            "cannot read parameter file " + dir.file("missing.yml") + ": No such file or directory");
  const std::string corrupt = dir.write("corrupt.yml.gz", std::string("\x1f\x8b\x08\x00 not deflate at all", 24));
  const std::string corrupt_error = error(corrupt);  // zlib's words in the brackets: "invalid code lengths set"
  EXPECT_EQ(corrupt_error.rfind("cannot read parameter file " + corrupt + ": corrupt gzip data (", 0), 0u)
      << corrupt_error;
  EXPECT_EQ(corrupt_error.find(corrupt, corrupt_error.find(corrupt) + 1), std::string::npos)
      << "the file named twice: " << corrupt_error;
  // Fields that contradict each other are named with the file too.
  const std::string crossed = dir.write("crossed.yml", "descriptor:\n  min_radius_px: 30\n  max_radius_px: 20\n");
  EXPECT_EQ(error(crossed), "parameter file " + crossed + ": descriptor.min_radius_px exceeds descriptor.max_radius_px");
}

// Every field of the parameters, as a parameter file writes them.
std::string paramsText(const RisasParams& p) {
  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  p.write(fs);
  return fs.releaseAndGetString();
}

// config/paper.yaml loads and selects the paper's choices where the
// defaults depart from them (docs/method.md), nothing else.
TEST(Params, PaperYamlSelectsThePapersChoices) {
  const RisasParams paper = RisasParams::load(RISAS_SOURCE_DIR "/config/paper.yaml");
  EXPECT_EQ(paper.descriptor.support_radius, 0.0);  // eq. 3-4
  EXPECT_TRUE(paper.descriptor.shape_orientation);  // eq. 7
  EXPECT_EQ(paper.descriptor.patch_radius, 20);
  EXPECT_EQ(paper.geometry.normal_stride, 1);
  EXPECT_FALSE(paper.descriptor.soft_binning);  // one vote per sample
  EXPECT_EQ(paper.descriptor.sample_blur, 0.0);  // the frame's grey image
  EXPECT_EQ(paper.descriptor.grey_noise, 0.0);  // exact ranks
  EXPECT_EQ(paper.descriptor.n_vec, 2);  // the shape labels
  EXPECT_EQ(paper.descriptor.n_bin, 8);  // eight rank groups
  EXPECT_EQ(paper.descriptor.n_ring, 1);  // sectors only
  EXPECT_EQ(paper.descriptor.dimension(), 192);
  RisasParams expected;  // the defaults with those fields changed, and no other
  expected.geometry.normal_stride = 1;
  expected.detector.gray_sigma = 0.7, expected.detector.window_sigma = 1.0;
  expected.detector.min_keypoints = 0;
  expected.descriptor.support_radius = 0.0, expected.descriptor.shape_orientation = true;
  expected.descriptor.patch_radius = 20, expected.descriptor.min_valid_fraction = 0.7;
  expected.descriptor.soft_binning = false, expected.descriptor.sample_blur = 0.0, expected.descriptor.n_vec = 2;
  expected.descriptor.grey_noise = 0.0;
  expected.descriptor.n_bin = 8, expected.descriptor.n_ring = 1;
  expected.descriptor.gradient_orientation = false;
  EXPECT_EQ(paramsText(paper), paramsText(expected));
}

// config/odometry.yaml changes the detector's budget rule, scales and suppression, nothing else.
TEST(Params, OdometryYamlKeepsTheBestThousandAnywhere) {
  RisasParams expected;
  expected.detector.max_keypoints = 1000;
  expected.detector.response_threshold = 0.0;
  expected.detector.grid_cols = 1, expected.detector.grid_rows = 1;
  expected.detector.gray_sigma = 0.7, expected.detector.window_sigma = 1.0;
  expected.detector.nms_radius = 2;
  EXPECT_EQ(paramsText(RisasParams::load(RISAS_SOURCE_DIR "/config/odometry.yaml")), paramsText(expected));
}

// The shipped config/risas.yaml is the library's defaults, field for field.
TEST(ParamsFile, ShippedConfigEqualsTheDefaults) {
  EXPECT_EQ(paramsText(RisasParams::load(RISAS_SOURCE_DIR "/config/risas.yaml")), paramsText(RisasParams()));
}

TEST(IntrinsicsFile, ReadsTheDatasetFormatAndRejectsOthers) {
  const TempDir dir;
  const Intrinsics K = readIntrinsicsFile(
      dir.write("K.txt", "585.67  0       382.76\n0       606.56  223.09\n0       0       1\n"));
  EXPECT_DOUBLE_EQ(K.fx, 585.67);
  EXPECT_DOUBLE_EQ(K.fy, 606.56);
  EXPECT_DOUBLE_EQ(K.cx, 382.76);
  EXPECT_DOUBLE_EQ(K.cy, 223.09);
  EXPECT_THROW(readIntrinsicsFile(dir.write("short.txt", "585 0 382 0 606 223 0 0")), InputError);
  EXPECT_THROW(readIntrinsicsFile(dir.write("word.txt", "585 0 382 0 606 223 0 0 one")), InputError);
  EXPECT_THROW(readIntrinsicsFile(dir.write("zero.txt", "0 0 382 0 606 223 0 0 1")), InputError);
  EXPECT_THROW(readIntrinsicsFile(dir.file("missing.txt")), InputError);
}

// The dataset's R1-k.txt and T1-k.txt: a rigid motion, or a one-line error
// naming the file; never a matrix that is not a rotation, nor numbers taken
// from a file that holds more or other text.
TEST(PoseFiles, ReadTheDatasetsRigidMotionAndRefuseWhatIsNot) {
  const TempDir dir;
  // geometry/rotate's corrected R1-5.txt and T1-5.txt.
  const std::string R = dir.write("R.txt",
                                  "-0.710281445 0.703483841 -0.023955241\n"
                                  "-0.661060636 -0.678474334 -0.320514093\n"
                                  "-0.241727270 -0.211737680 0.946955779\n");
  const std::string t = dir.write("T.txt", "-0.229027258\n0.191907103\n0.013232292");
  const Eigen::Isometry3d T = readPoseFiles(R, t);
  EXPECT_NEAR(T.linear()(1, 2), -0.320514093, 1e-12);
  EXPECT_NEAR(T.translation().y(), 0.191907103, 1e-12);
  // The raw files' five digits are a rotation within the tolerance.
  EXPECT_NO_THROW(readPoseFiles(dir.write("R5.txt", "-0.72086 0.67907 0.13856 -0.67987 -0.65421 -0.33143 "
                                                    "-0.13442 -0.33304 0.93327"),
                                t));
  const auto message = [&](const std::string& rotation, const std::string& translation) {
    try {
      readPoseFiles(rotation, translation);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto refused = [&](const std::string& rotation_text, const std::string& wanted) {
    const std::string path = dir.write("bad_R.txt", rotation_text);
    const std::string what = message(path, t);
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(wanted), std::string::npos) << rotation_text << ": " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  };
  refused("2 0 0 0 2 0 0 0 2", "does not hold a rotation");   // a scale
  refused("1 0 0 0 1 0 0 0 -1", "does not hold a rotation");  // a reflection
  refused("1 0 0 0 1 0 0 0 1 0", "found 10");                 // a number too many
  refused("1 0 0 0 1 0 0 0", "found 8");
  refused("1 0 0 0 1 0 0 0 1x", "'1x' is not a finite number");
  refused("1 0 0 0 nan 0 0 0 1", "'nan' is not a finite number");
  refused("1 0 0 0 1e999 0 0 0 1", "'1e999' is not a finite number");
  EXPECT_NE(message(R, dir.write("bad_T.txt", "0.1 0.2")).find("found 2"), std::string::npos);
  EXPECT_NE(message(dir.file("missing.txt"), t).find("cannot open"), std::string::npos);
}

TEST(SequenceFiles, ListsFramesUpToTheFirstGapAndFindsIntrinsicsAbove) {
  const TempDir dir;
  fs::create_directories(dir.path / "seq");
  for (int k : {1, 2, 3, 5}) {
    dir.write("seq/rgb_" + std::to_string(k) + ".png", "x");
    dir.write("seq/depth_" + std::to_string(k) + ".png", "x");
  }
  dir.write("seq/rgb_4.png", "x");  // no depth_4: the sequence ends at 3
  const auto frames = listSequence(dir.file("seq"));
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[2].index, 3);
  EXPECT_EQ(frames[2].depth_path, dir.file("seq/depth_3.png"));
  EXPECT_TRUE(listSequence(dir.file("nothing-here")).empty());
  EXPECT_THROW(findIntrinsics(dir.file("seq")), InputError);
  dir.write("camera-intrinsics.txt", "500 0 320 0 510 240 0 0 1");
  EXPECT_DOUBLE_EQ(findIntrinsics(dir.file("seq")).fy, 510.0);
}

TEST(FrameFiles, LoadsPngPairsAndRejectsWrongDepthFiles) {
  const TempDir dir;
  const SyntheticRender r = SyntheticScene::demo().render(syntheticIntrinsics(), test::kVga, test::demoCamera());
  cv::imwrite(dir.file("rgb.png"), r.bgr);
  cv::imwrite(dir.file("depth.png"), r.depth_mm);
  cv::imwrite(dir.file("depth8.png"), r.bgr);
  dir.write("broken.png", "not a png");
  const RgbdFrame frame = loadRgbdFrame(dir.file("rgb.png"), dir.file("depth.png"), syntheticIntrinsics());
  EXPECT_EQ(frame.size(), test::kVga);
  EXPECT_THROW(loadRgbdFrame(dir.file("rgb.png"), dir.file("depth8.png"), syntheticIntrinsics()), InputError);
  EXPECT_THROW(loadRgbdFrame(dir.file("broken.png"), dir.file("depth.png"), syntheticIntrinsics()), InputError);
  EXPECT_THROW(loadRgbdFrame(dir.file("none.png"), dir.file("depth.png"), syntheticIntrinsics()), InputError);
}

TEST(FrameFiles, ReadsDepthInTheUnitsGiven) {
  const TempDir dir;
  const SyntheticRender r = SyntheticScene::demo().render(syntheticIntrinsics(), test::kVga, test::demoCamera());
  cv::imwrite(dir.file("rgb.png"), r.bgr);
  cv::imwrite(dir.file("depth_mm.png"), r.depth_mm);
  cv::Mat tum_units;
  r.depth_mm.convertTo(tum_units, CV_16U, 5.0);  // TUM RGB-D: 5000 a metre
  cv::imwrite(dir.file("depth_tum.png"), tum_units);
  const RgbdFrame mm = loadRgbdFrame(dir.file("rgb.png"), dir.file("depth_mm.png"), syntheticIntrinsics());
  const RgbdFrame tum = loadRgbdFrame(dir.file("rgb.png"), dir.file("depth_tum.png"), syntheticIntrinsics(), 5000.0);
  // The same metres, and the same holes (NaN compares unequal: count both).
  EXPECT_EQ(cv::countNonZero(mm.depth() == mm.depth()), cv::countNonZero(tum.depth() == tum.depth()));
  cv::Mat difference;
  cv::absdiff(mm.depth(), tum.depth(), difference);
  double largest = 0.0;
  cv::minMaxLoc(difference, nullptr, &largest, nullptr, nullptr, mm.depth() == mm.depth());
  EXPECT_LT(largest, 1e-6);
  // Read as millimetres, the TUM file is five times too deep: why the unit is asked for.
  const RgbdFrame misread = loadRgbdFrame(dir.file("rgb.png"), dir.file("depth_tum.png"), syntheticIntrinsics());
  const cv::Point centre(test::kVga.width / 2, test::kVga.height / 2);
  EXPECT_NEAR(misread.depth().at<float>(centre), 5.0f * mm.depth().at<float>(centre), 1e-3);

  const cv::Mat values(2, 2, CV_16UC1, cv::Scalar(2500));
  EXPECT_FLOAT_EQ(depthFromUnits(values, 5000.0).at<float>(1, 1), 0.5f);
  EXPECT_EQ(depthFromUnits(values, kMillimetreDepthUnits).type(), CV_16UC1);  // RgbdFrame's millimetres as they are
  for (double bad : {0.0, -1000.0, std::nan(""), double(INFINITY)}) {
    EXPECT_THROW(depthFromUnits(values, bad), InputError) << bad;
    EXPECT_THROW(loadRgbdFrame(dir.file("rgb.png"), dir.file("depth_mm.png"), syntheticIntrinsics(), bad), InputError);
  }
}

TEST(FeaturesFile, RoundTripsInYamlAndJson) {
  const TempDir dir;
  const Features f = Risas().extract(test::renderFrame(SyntheticScene::demo(), test::demoCamera()));
  ASSERT_GT(f.keypoints.size(), 50u);
  for (const char* name : {"f.yml", "f.json", "f.xml.gz"}) {
    writeFeatures(dir.file(name), f);
    const Features g = readFeatures(dir.file(name));
    ASSERT_EQ(g.keypoints.size(), f.keypoints.size()) << name;
    EXPECT_EQ(cv::norm(g.descriptors, f.descriptors, cv::NORM_INF), 0.0) << name;
    EXPECT_EQ(g.descriptor_layout, "n_ring=2 n_pie=8 n_bin=4 n_vec=0") << name;
    ASSERT_EQ(g.geometry.size(), f.geometry.size());
    for (size_t i = 0; i < f.keypoints.size(); ++i) {
      EXPECT_EQ(g.keypoints[i].pt, f.keypoints[i].pt);
      EXPECT_FLOAT_EQ(g.keypoints[i].angle, f.keypoints[i].angle);
      EXPECT_FLOAT_EQ(g.keypoints[i].size, f.keypoints[i].size);
      EXPECT_EQ(g.geometry[i].point, f.geometry[i].point);
      EXPECT_EQ(g.geometry[i].normal, f.geometry[i].normal);
      EXPECT_FLOAT_EQ(g.geometry[i].support_radius, f.geometry[i].support_radius);
    }
    writeFeatures(dir.file(name), Features{});  // a frame without keypoints
    EXPECT_TRUE(readFeatures(dir.file(name)).keypoints.empty()) << name;
  }
}

// Every file the library writes is written whole or refused in an
// InputError naming it and the system's reason: std::ofstream and
// cv::FileStorage, which wrote them before, said nothing on a full disk.
TEST(WrittenFiles, AreWholeOrAnErrorNamingTheFileAndTheReason) {
  const TempDir dir;
  writeTextFile(dir.file("plain.txt"), "one\ntwo\n", "test file");
  EXPECT_EQ(test::fileText(dir.file("plain.txt")), "one\ntwo\n");
  writeTextFile(dir.file("packed.yml.gz"), "%YAML:1.0\n---\nvalue: 3\n", "test file");  // gzip: FileStorage reads it
  EXPECT_EQ(static_cast<int>(cv::FileStorage(dir.file("packed.yml.gz"), cv::FileStorage::READ)["value"]), 3);
  std::ifstream packed(dir.file("packed.yml.gz"), std::ios::binary);
  EXPECT_EQ(packed.get(), 0x1f);  // gzip's magic number, not the text
  EXPECT_EQ(packed.get(), 0x8b);
  EXPECT_EQ(test::inputErrorOf([&] { writeTextFile(dir.file("no/such/folder.txt"), "x", "test file"); }),
            "cannot write test file " + dir.file("no/such/folder.txt") + ": No such file or directory");

  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  // /dev/full opens and then fails every write, as a full disk does.
  fs::create_symlink("/dev/full", dir.file("full.gz"));
  const std::string large(1 << 20, 'x');  // beyond any buffer: fails at the write, not only at the close
  for (const std::string& text : {std::string("short"), large}) {
    EXPECT_EQ(test::inputErrorOf([&] { writeTextFile("/dev/full", text, "test file"); }),
              "cannot write test file /dev/full: No space left on device");
    EXPECT_EQ(test::inputErrorOf([&] { writeTextFile(dir.file("full.gz"), text, "test file"); }),
              "cannot write test file " + dir.file("full.gz") + ": No space left on device");
  }
  const Features features = Risas().extract(test::renderFrame(SyntheticScene::demo(), test::demoCamera()));
  EXPECT_EQ(test::inputErrorOf([&] { writeFeatures("/dev/full", features); }),
            "cannot write features file /dev/full: No space left on device");
  EXPECT_EQ(test::inputErrorOf([&] { writeTumTrajectory("/dev/full", {{1.0, Eigen::Isometry3d::Identity()}}); }),
            "cannot write trajectory /dev/full: No space left on device");
  EXPECT_EQ(test::inputErrorOf([&] { RisasParams().save("/dev/full"); }),
            "cannot write parameter file /dev/full: No space left on device");
}

// Images likewise: cv::imwrite returns a bare false (and libpng prints its
// own line), true for a small image on a full disk, or throws for an
// extension it has no writer for.
TEST(WrittenImages, AreWholeOrAnErrorNamingTheFileAndTheReason) {
  const TempDir dir;
  const cv::Mat image(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  writeImage(dir.file("plain.png"), image, "test image");
  EXPECT_EQ(cv::norm(cv::imread(dir.file("plain.png")), image, cv::NORM_INF), 0.0);
  requireImageWriter(dir.file("fine.jpg"), "test image");
  for (const char* name : {"image.xyz", "image"}) {
    const std::string expected = "cannot write test image " + dir.file(name) + ": OpenCV has no image writer for " +
                                 (std::string(name) == "image" ? "a name without an extension" : "'.xyz'") +
                                 " (.png, .jpg, .tif, ...)";
    EXPECT_EQ(test::inputErrorOf([&] { requireImageWriter(dir.file(name), "test image"); }), expected);
    EXPECT_EQ(test::inputErrorOf([&] { writeImage(dir.file(name), image, "test image"); }), expected);
    EXPECT_FALSE(fs::exists(dir.file(name)));
  }
  const std::string missing =
      test::inputErrorOf([&] { writeImage(dir.file("no/such/image.png"), image, "test image"); });
  EXPECT_EQ(missing.rfind("cannot write test image " + dir.file("no/such/image.png") + ": ", 0), 0u) << missing;
  EXPECT_EQ(missing.find('\n'), std::string::npos) << missing;

  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  fs::create_symlink("/dev/full", dir.file("full.png"));
  const cv::Mat large(480, 640, CV_8UC3);
  cv::randu(large, 0, 256);  // beyond any buffer: fails at the write, not only at the close
  for (const cv::Mat& written : {image, large}) {
    EXPECT_EQ(test::inputErrorOf([&] { writeImage(dir.file("full.png"), written, "test image"); }),
              "cannot write test image " + dir.file("full.png") + ": No space left on device");
  }
}

TEST(FeaturesFile, RecordsTheDescriptorsLayoutAndChecksItAgainstTheirWidth) {
  const TempDir dir;
  Features f;
  f.keypoints.resize(2);
  f.descriptors = cv::Mat(2, 64, CV_32F, cv::Scalar(0.125f));
  writeFeatures(dir.file("unknown.yml"), f);  // as ORB's, or a file from before the layout was written
  EXPECT_EQ(readFeatures(dir.file("unknown.yml")).descriptor_layout, "");
  // Two layouts of one width: only the recorded layout tells them apart.
  for (const char* layout : {"n_ring=2 n_pie=8 n_bin=4 n_vec=0", "n_ring=1 n_pie=8 n_bin=8 n_vec=0"}) {
    f.descriptor_layout = layout;
    writeFeatures(dir.file("known.yml"), f);
    EXPECT_EQ(readFeatures(dir.file("known.yml")).descriptor_layout, layout);
  }
  // The shape labels' own histogram (shape_weight): 2 x 8 x (2 + 1 + 1) = 64 too.
  DescriptorParams own_shape;
  own_shape.n_bin = 2, own_shape.n_vec = 1, own_shape.shape_weight = 0.25;
  ASSERT_EQ(own_shape.dimension(), 64);
  f.descriptor_layout = own_shape.layout();
  EXPECT_EQ(f.descriptor_layout, "n_ring=2 n_pie=8 n_bin=2 n_vec=1 shape_weight=0.25");
  writeFeatures(dir.file("own_shape.yml"), f);
  EXPECT_EQ(readFeatures(dir.file("own_shape.yml")).descriptor_layout, f.descriptor_layout);
  for (const char* wrong : {"n_ring=1 n_pie=8 n_bin=8 n_vec=2", "n_ring=2 n_pie=8 n_bin=4", "rings: 2",
                            "n_ring=0 n_pie=8 n_bin=8 n_vec=0", "n_ring=99999999999 n_pie=8 n_bin=4 n_vec=0",
                            // each 64 columns if it were read: only the layout's own rules reject them
                            "n_ring=2 n_pie=8 n_bin=3 n_vec=0 shape_weight=1",  // no labels to weigh
                            "n_ring=2 n_pie=8 n_bin=2 n_vec=1 shape_weight=0",
                            "n_ring=2 n_pie=8 n_bin=2 n_vec=1 shape_weight=inf",
                            "n_ring=2 n_pie=8 n_bin=2 n_vec=1 shape_weight=0.25x",
                            "n_ring=2 n_pie=8 n_bin=2 n_vec=1shape_weight=0.25"}) {
    f.descriptor_layout = wrong;
    writeFeatures(dir.file("wrong.yml"), f);
    EXPECT_THROW(readFeatures(dir.file("wrong.yml")), InputError) << wrong;
  }
}

TEST(FeaturesFile, CorruptOrForeignFilesAreErrors) {
  const TempDir dir;
  EXPECT_THROW(readFeatures(dir.write("garbage.yml", "%YAML:1.0\nkeypoints: [1, 2\n")), InputError);
  EXPECT_THROW(readFeatures(dir.write("other.yml", "%YAML:1.0\nsomething: 3\n")), InputError);
  EXPECT_THROW(readFeatures(dir.file("missing.yml")), InputError);
  Features inconsistent;
  inconsistent.keypoints.resize(2);
  inconsistent.descriptors = cv::Mat(1, 192, CV_32F);
  EXPECT_THROW(writeFeatures(dir.file("x.yml"), inconsistent), InputError);
  EXPECT_THROW(writeFeatures("/nonexistent-dir/x.yml", Features{}), InputError);
}

// A features file's geometry in another depth than CV_32F (written by
// another program, or edited) is read as its numbers say; one of several
// channels is refused. Read element by element as floats, an 8-bit matrix
// once overran its rows (ASan: heap-buffer-overflow).
TEST(FeaturesFile, GeometryOfAnotherDepthIsConvertedAndSeveralChannelsRefused) {
  const TempDir dir;
  // Reading `text` as a features file is refused with `words` in the message.
  const auto expectRefused = [&](const char* name, const std::string& text, const std::string& words) {
    const std::string message = test::inputErrorOf([&] { readFeatures(dir.write(name, text)); });
    EXPECT_NE(message.find(words), std::string::npos) << message;
  };
  const auto file = [&](const char* depth, const char* radius_depth) {
    const std::string matrix = "!!opencv-matrix\n   rows: 2\n   cols: ";
    return std::string("%YAML:1.0\nkeypoints:\n   - [ 10., 20., 30., 0., 1., 0, -1 ]\n") +
           "   - [ 11., 21., 30., 0., 1., 0, -1 ]\n" +
           "descriptors: " + matrix + "2\n   dt: f\n   data: [ 0.5, 0.5, 0.25, 0.75 ]\n" +
           "points3d: " + matrix + "3\n   dt: " + depth + "\n   data: [ 1, 2, 3, 4, 5, 6 ]\n" +
           "normals: " + matrix + "3\n   dt: " + depth + "\n   data: [ 0, 0, 1, 0, 1, 0 ]\n" +
           "support_radius: " + matrix + "1\n   dt: " + radius_depth + "\n   data: [ 7, 8 ]\n";
  };
  for (const char* depth : {"u", "d", "i"}) {
    SCOPED_TRACE(depth);
    const Features f = readFeatures(dir.write("geometry.yml", file(depth, depth)));
    ASSERT_EQ(f.geometry.size(), 2u);
    EXPECT_EQ(f.geometry[1].point, cv::Point3f(4, 5, 6));
    EXPECT_EQ(f.geometry[1].normal, cv::Vec3f(0, 1, 0));
    EXPECT_EQ(f.geometry[1].support_radius, 8.0f);
  }
  const std::string two_channels = std::string("%YAML:1.0\nkeypoints:\n   - [ 10., 20., 30., 0., 1., 0, -1 ]\n") +
                                   "descriptors: !!opencv-matrix\n   rows: 1\n   cols: 1\n   dt: f\n   data: [ 1 ]\n" +
                                   "points3d: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: \"2f\"\n" +
                                   "   data: [ 1, 2, 3, 4, 5, 6 ]\n";
  expectRefused("channels.yml", two_channels, "points3d has 2 channels, not 1");
  // A count that its data does not hold is refused before OpenCV would
  // allocate it (the fuzz loop's find: 40 GB under ASan).
  const std::string huge = std::string("%YAML:1.0\nkeypoints:\n   - [ 10., 20., 30., 0., 1., 0, -1 ]\n") +
                           "descriptors: !!opencv-matrix\n   rows: 1000000000\n   cols: 10\n   dt: f\n" +
                           "   data: [ 1, 2 ]\n";
  expectRefused("huge.yml", huge, "descriptors says 1000000000 x 10 of 'f' but holds 2 numbers");
  // A rows that is no number reads in OpenCV as 2^31 - 1 (the fuzz loop's
  // find: 43 GB under ASan).
  std::string not_a_number = huge;
  not_a_number.replace(not_a_number.find("1000000000"), 10, "u1");
  expectRefused("rows.yml", not_a_number, "descriptors is not a matrix of rows, cols, dt and data");
  // A matrix node with a key that begins with ':' (the fuzz loop's find,
  // reduced): OpenCV's parser throws std::length_error there, which comes
  // out an InputError.
  const std::string colon_key = std::string("%YAML:1.0\nkeypoints:\n   - [ 2.5, 13., 10., -1., 0., 0, -1 ]\n") +
                                "descriptors: !!opencv-matrix\n   data: [ 0.5 ]\n   :ata: [ X ]\n";
  expectRefused("colon.yml", colon_key, "cannot parse features file");
}

}  // namespace
}  // namespace risas
