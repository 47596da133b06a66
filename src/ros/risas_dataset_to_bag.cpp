// risas_dataset_to_bag: an RGB-D image sequence (ManipulatorsDataset layout:
// rgb_k.png, depth_k.png, camera-intrinsics.txt here or above) into a bag with
// the topics of an OpenNI camera, ready for `roslaunch risas bag.launch`.
#include "../tools/cli.hpp"

#include "bag_frames.hpp"

#include "risas/errors.hpp"
#include "risas/io.hpp"

#include <iostream>

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_dataset_to_bag", [&] {
    const risas::cli::Args args(
        argc, argv,
        "risas_dataset_to_bag --data SEQUENCE_DIR --out F.bag [--rate 10] [--camera camera]\n"
        "                     [--frame-id camera_rgb_optical_frame]\n"
        "Writes <camera>/rgb/image_rect_color (bgr8), <camera>/depth_registered/image_raw\n"
        "(16UC1 mm) and <camera>/rgb/camera_info for the frames rgb_1, depth_1, rgb_2, ...",
        {{"data", "DIR", "sequence folder: rgb_k.png + depth_k.png, camera-intrinsics.txt in it or above"},
         {"out", "F.bag", "bag to write"},
         {"rate", "HZ", "frame rate of the stamps (default 10)"},
         {"camera", "NS", "topic namespace (default camera)"},
         {"frame-id", "ID", "optical frame of the images (default camera_rgb_optical_frame)"}});
    const std::string dir = args.get("data"), out = args.get("out");
    const double rate = args.getDouble("rate", 10.0);
    if (!(rate > 0.0)) throw risas::cli::UsageError("--rate must be positive");
    const std::string ns = args.get("camera", "camera");
    const std::string frame_id = risas_ros::frameIdOption(args);
    risas::cli::requireWritable(out);
    const risas::Intrinsics K = risas::findIntrinsics(dir);
    const std::vector<risas::SequenceFrame> frames = risas::listSequence(dir);
    if (frames.empty()) throw risas::InputError("no rgb_1.png/depth_1.png in " + dir);

    risas_ros::BagWriter bag(out);
    const ros::Time start(1.0e9);  // fixed, so the same sequence gives the same bag
    for (size_t i = 0; i < frames.size(); ++i) {
      const risas::RgbdImages images = risas::readRgbdImages(frames[i].rgb_path, frames[i].depth_path);
      std_msgs::Header header;
      header.seq = static_cast<uint32_t>(i);
      header.stamp = start + ros::Duration(i / rate);
      header.frame_id = frame_id;
      risas_ros::writeRgbdFrame(bag, ns, header, images.bgr, images.depth_mm, K);
    }
    bag.close();
    std::cout << frames.size() << " frames written to " << out << " (" << ns << "/rgb/image_rect_color, " << ns
              << "/depth_registered/image_raw, " << ns << "/rgb/camera_info)\n";
    return 0;
  });
}
