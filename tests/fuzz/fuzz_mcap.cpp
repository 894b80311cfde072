// libFuzzer target: io::listRosbag + io::importRosbag on a .mcap file (fuzz_bag.h).
#include "fuzz_bag.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return superloc::fuzz::fuzzBagFile(".mcap", data, size);
}
