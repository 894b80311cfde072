// libFuzzer target: io::loadPointCloud on KITTI .bin (float32 x y z reflectance).
#include <superloc/io/point_cloud_io.h>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string& path = superloc::fuzz::scratchPath(".bin");
    superloc::fuzz::writeBytes(path, data, size);
    superloc::fuzz::expectLoadsOrThrowsOneLine([&] {
        size_t dropped = 0;
        const superloc::PointCloud c =
            superloc::io::loadPointCloud(path, superloc::io::CloudFormat::Auto, &dropped);
        // Attributes are either absent or one per point.
        if ((!c.intensity.empty() && c.intensity.size() != c.size()) ||
            (!c.normals.empty() && c.normals.size() != c.size()) ||
            (!c.rgb.empty() && c.rgb.size() != c.size()))
            std::abort();
    });
    return 0;
}
