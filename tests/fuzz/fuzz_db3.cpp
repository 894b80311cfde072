// libFuzzer target: io::listRosbag + io::importRosbag on a .db3 file (fuzz_bag.h).
#include "fuzz_bag.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return superloc::fuzz::fuzzBagFile(".db3", data, size);
}
