// libFuzzer target: io::loadTum on TUM trajectory text.
#include <superloc/io/tum.h>

#include <cmath>

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string& path = superloc::fuzz::scratchPath(".tum");
    superloc::fuzz::writeBytes(path, data, size);
    superloc::fuzz::expectLoadsOrThrowsOneLine([&] {
        const superloc::Trajectory traj = superloc::io::loadTum(path);
        // What loads is finite, time-ordered and has unit rotations.
        for (size_t i = 0; i < traj.size(); ++i) {
            if (!std::isfinite(traj[i].t) || !traj[i].pose.matrix().allFinite()) std::abort();
            if (i > 0 && traj[i].t < traj[i - 1].t) std::abort();
            const double det = traj[i].pose.linear().determinant();
            if (std::abs(det - 1.0) > 1e-6) std::abort();
        }
    });
    return 0;
}
