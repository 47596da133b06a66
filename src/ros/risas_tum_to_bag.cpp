// risas_tum_to_bag: a TUM RGB-D folder (rgb.txt, depth.txt; colour and depth
// paired by nearest stamp) into a bag with the topics of an OpenNI camera,
// stamped with the recording's colour stamps, depth as 32FC1 metres (the
// folder's 5000 units per metre, exactly), ready for `roslaunch risas
// bag.launch bag:=F.bag odometry:=true`.
#include "../tools/cli.hpp"
#include "bag_frames.hpp"

#include "risas/tum_sequence.hpp"

#include <iostream>

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_tum_to_bag", [&] {
    std::vector<risas::cli::Option> options = {
        {"tum", "DIR", "TUM RGB-D folder: rgb.txt, depth.txt"},
        {"out", "F.bag", "bag to write"},
        {"camera", "NS", "topic namespace (default camera)"},
        {"frame-id", "ID", "optical frame of the images (default camera_rgb_optical_frame)"}};
    for (const risas::cli::Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    const risas::cli::Args args(
        argc, argv,
        "risas_tum_to_bag --tum DIR --out F.bag --intrinsics K.txt | --fx F --fy F --cx C --cy C\n"
        "                 [--camera camera] [--frame-id camera_rgb_optical_frame]\n"
        "Writes <camera>/rgb/image_rect_color (bgr8), <camera>/depth_registered/image_raw (32FC1 m)\n"
        "and <camera>/rgb/camera_info for each associated colour/depth pair, at the colour stamps.",
        options);
    const std::string out = args.get("out"), ns = args.get("camera", "camera");
    const std::string frame_id = risas_ros::frameIdOption(args);
    risas::cli::requireWritable(out);
    const risas::Intrinsics K = risas::cli::intrinsicsFrom(args);
    const risas::TumSequence sequence = risas::cli::readTumSequenceNoting("risas_tum_to_bag", args.get("tum"));
    risas_ros::BagWriter bag(out);
    for (size_t i = 0; i < sequence.frames.size(); ++i) {
      const risas::TumFrame& f = sequence.frames[i];
      const risas::TumImages images = risas::readTumImages(f);
      std_msgs::Header header;
      header.seq = static_cast<uint32_t>(i);
      header.stamp = ros::Time(f.stamp);
      header.frame_id = frame_id;
      risas_ros::writeRgbdFrame(bag, ns, header, images.bgr, images.depth_metres, K);
    }
    bag.close();
    std::cout << sequence.frames.size() << " frames written to " << out << " (" << ns << "/rgb/image_rect_color, "
              << ns << "/depth_registered/image_raw, " << ns << "/rgb/camera_info)\n";
    return 0;
  });
}
