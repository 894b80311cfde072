// libFuzzer target: io::loadPointCloud on KITTI .bin (float32 x y z reflectance).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return superloc::fuzz::fuzzPointCloudFile(".bin", data, size);
}
