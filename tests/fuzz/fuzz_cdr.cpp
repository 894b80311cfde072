// libFuzzer target: the CDR decoder of ROS 2 messages (modules/io/src/bag/cdr.h) and the shared
// PointCloud2 -> Scan conversion, without a container around them. The first byte picks the
// message type (PointCloud2, Imu, Odometry, PoseStamped, TFMessage), the rest is the message.
#include <cmath>

#include "../../modules/io/src/bag/cdr.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace superloc::io::detail;
    if (size < 1) return 0;
    const uint8_t kind = data[0] % 5;
    const uint8_t* msg = data + 1;
    const size_t n = size - 1;
    superloc::fuzz::expectLoadsOrThrowsOneLine([&] {
        switch (kind) {
            case 0: {
                const PointCloud2Msg m = cdrPointCloud2(msg, n);
                if (m.cloud.data_size &&
                    (m.cloud.data < msg || m.cloud.data + m.cloud.data_size > msg + n))
                    std::abort();  // the data view must lie inside the message
                superloc::Scan s;
                for (const char* field : {"auto", "none"}) {
                    const auto st = decodePointCloud2(m.cloud, {field, "auto", "auto"}, s);
                    if (!s.rel_time.empty() && s.rel_time.size() != s.size()) std::abort();
                    if (!s.intensity.empty() && s.intensity.size() != s.size()) std::abort();
                    for (const auto& p : s.points)
                        if (!p.allFinite()) std::abort();
                    (void)st;
                }
                break;
            }
            case 1:
                cdrImu(msg, n);
                break;
            case 2:
                cdrOdometry(msg, n);
                break;
            case 3:
                cdrPoseStamped(msg, n);
                break;
            default:
                cdrTfMessage(msg, n);
                break;
        }
    });
    return 0;
}
