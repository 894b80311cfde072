// Shared by the bag fuzz targets (fuzz_db3.cpp, fuzz_mcap.cpp, fuzz_ros1.cpp): the fuzzer's
// bytes as a bag file, listed and imported like `superloc-import --rosbag` does, with every
// Odometry topic mapped (the first to odom_alt, a second to gt) and a PoseStamped one to gt, so
// that each message type is decoded. Same contract as fuzz_common.h: loads or one-line error.
#pragma once

#include <superloc/io/rosbag.h>

#include "fuzz_common.h"

namespace superloc::fuzz {

inline int fuzzBagFile(const char* ext, const uint8_t* data, size_t size) {
    const std::string& path = scratchPath(ext);
    static const std::string out = path + ".rawlog";
    writeBytes(path, data, size);
    expectLoadsOrThrowsOneLine([&] {
        try {
            io::RosbagParams p;
            for (const auto& t : io::listRosbag(path)) {
                const bool odom =
                    t.type.find("nav_msgs/") == 0 && t.type.find("Odometry") != std::string::npos;
                const bool pose = t.type.find("PoseStamped") != std::string::npos;
                if (odom && p.odom_alt_topic == "none")
                    p.odom_alt_topic = t.topic;
                else if ((odom || pose) && p.gt_topic == "none")
                    p.gt_topic = t.topic;
            }
            const auto r = io::importRosbag(path, p, out);
            if (r.timed_scans > r.scans) std::abort();
        } catch (const std::exception& e) {
            // Every bag error names the file first (doc/io.md).
            if (std::string(e.what()).rfind(path + ": ", 0) != 0) {
                std::fprintf(stderr, "fuzz: error does not start with the file name: <<%s>>\n",
                             e.what());
                std::abort();
            }
            throw;
        }
    });
    return 0;
}

}  // namespace superloc::fuzz
