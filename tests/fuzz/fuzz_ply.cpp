// libFuzzer target: io::loadPointCloud on PLY (ASCII, binary little- or big-endian).
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return superloc::fuzz::fuzzPointCloudFile(".ply", data, size);
}
