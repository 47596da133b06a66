// risas_extract: RISAS features of one RGB-D frame to a cv::FileStorage file.
#include "cli.hpp"

#include "risas/io.hpp"
#include "risas/risas.hpp"

#include <chrono>
#include <iostream>

int main(int argc, char** argv) {
  return risas::cli::runTool("risas_extract", [&] {
    using risas::cli::Option;
    std::vector<Option> options = {{"rgb", "R.png", "colour image (8-bit)"},
                                   {"depth", "D.png", "registered depth image (16-bit; millimetres unless --depth-units)"},
                                   {"out", "F.yml", "output file: keypoints, descriptors, points3d, normals"}};
    for (const Option& o : risas::cli::intrinsicsOptions()) options.push_back(o);
    options.push_back(risas::cli::depthUnitsOption());
    options.push_back(risas::cli::paramsOption());
    const risas::cli::Args args(argc, argv,
                                "risas_extract --rgb R.png --depth D.png --intrinsics K.txt --out F.yml [--params P.yml]\n"
                                "Detects and describes RISAS features of one registered RGB-D frame.",
                                options);
    const std::string out = args.get("out");
    risas::cli::requireWritable(out);
    const risas::RgbdFrame frame = risas::loadRgbdFrame(args.get("rgb"), args.get("depth"), risas::cli::intrinsicsFrom(args),
                                                        risas::cli::depthUnitsFrom(args));
    const auto risas = risas::Risas::create(risas::cli::paramsFrom(args));

    const auto start = std::chrono::steady_clock::now();
    const risas::Features features = risas->extract(frame);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    risas::writeFeatures(out, features);
    std::cout << features.keypoints.size() << " keypoints, " << risas->descriptorSize() << "-d descriptors, "
              << ms << " ms; written to " << out << "\n";
    return 0;
  });
}
