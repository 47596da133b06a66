// risas_render_synthetic: render the demo scene from an orbiting camera into
// the ManipulatorsDataset layout (rgb_k.png, depth_k.png, R1-k.txt, T1-k.txt,
// camera-intrinsics.txt), so every tool runs without a camera or the dataset.
#include "cli.hpp"

#include "risas/io.hpp"
#include "risas/synthetic_scene.hpp"

#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_render_synthetic", [&] {
    const risas::cli::Args args(
        argc, argv,
        "risas_render_synthetic --out DIR [--frames 4] [--step-deg 5]\n"
        "Renders the synthetic demo scene from a camera orbiting it, frame 1 first, into DIR\n"
        "in the ManipulatorsDataset layout, with exact poses (p1 = R pk + t).",
        {{"out", "DIR", "output folder (created)"},
         {"frames", "N", "number of frames (default 4)"},
         {"step-deg", "A", "orbit step between frames in degrees (default 5)"}});
    const std::filesystem::path dir = args.get("out");
    const int frames = args.getInt("frames", 4, 1, 10000);
    const double step = args.getDouble("step-deg", 5.0) * CV_PI / 180.0;
    risas::cli::makeOutputFolder(dir.string());

    const risas::SyntheticScene scene = risas::SyntheticScene::demo();
    const risas::Intrinsics K = risas::syntheticIntrinsics();
    risas::cli::writeIntrinsicsFile((dir / "camera-intrinsics.txt").string(), K);
    Eigen::Isometry3d world_T_first = Eigen::Isometry3d::Identity();
    for (int k = 1; k <= frames; ++k) {
      const Eigen::Isometry3d world_T_camera = risas::SyntheticScene::demoCamera((k - 1) * step);
      if (k == 1) world_T_first = world_T_camera;
      const risas::SyntheticRender render = scene.render(K, cv::Size(640, 480), world_T_camera);
      const std::string n = std::to_string(k);
      risas::writeImage((dir / ("rgb_" + n + ".png")).string(), render.bgr, "colour image");
      risas::writeImage((dir / ("depth_" + n + ".png")).string(), render.depth_mm, "depth image");
      const Eigen::Isometry3d first_T_k = world_T_first.inverse() * world_T_camera;
      risas::cli::writeMatrixFile((dir / ("R1-" + n + ".txt")).string(), first_T_k.linear());
      risas::cli::writeMatrixFile((dir / ("T1-" + n + ".txt")).string(), first_T_k.translation());
    }
    std::cout << frames << " frames written to " << dir.string() << "\n";
    return 0;
  });
}
