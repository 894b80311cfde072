// libFuzzer target: io::loadPointCloud on PCD (binary, ASCII or compressed), read through PCL.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return superloc::fuzz::fuzzPointCloudFile(".pcd", data, size);
}
