// Writes ImportExtras (CSV IMU / odometry) into a rawlog being imported, interleaved by time
// with the importer's own observations. Internal to module io.
#pragma once

#include <superloc/io/importers.h>
#include <superloc/io/rawlog.h>

#include <limits>

namespace superloc::io::detail {

class ExtrasWriter {
 public:
    ExtrasWriter(const ImportExtras& extras, ImportResult& result) : e_(extras), r_(result) {}

    /// Writes every pending sample with time <= t (call before writing an observation at t).
    void flushUntil(RawlogWriter& w, double t) {
        for (; imu_ < e_.imu.size() && e_.imu[imu_].t <= t; ++imu_, ++r_.imu)
            w.writeImu(e_.imu[imu_], e_.imu_label);
        for (; odom_ < e_.odom_alt.size() && e_.odom_alt[odom_].t <= t; ++odom_, ++r_.odom_alt)
            w.writePose(e_.odom_alt[odom_], e_.odom_alt_label);
    }
    /// Writes what is left (call before closing).
    void flushAll(RawlogWriter& w) { flushUntil(w, std::numeric_limits<double>::infinity()); }

 private:
    const ImportExtras& e_;
    ImportResult& r_;
    size_t imu_ = 0, odom_ = 0;
};

}  // namespace superloc::io::detail
