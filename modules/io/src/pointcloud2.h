// sensor_msgs/PointCloud2 payload -> superloc::Scan, independent of any ROS library (the fields
// are passed in plain structs), so ROS 1 and ROS 2 readers share it. Internal to module io.
#pragma once

#include <superloc/core/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace superloc::io::detail {

/// sensor_msgs/PointField.
struct PointField2 {
    std::string name;
    uint32_t offset = 0;
    uint8_t datatype = 0;  ///< 1 INT8 2 UINT8 3 INT16 4 UINT16 5 INT32 6 UINT32 7 FLOAT32 8 FLOAT64
    uint32_t count = 1;
};

/// The layout and bytes of one sensor_msgs/PointCloud2 (data is not owned).
struct PointCloud2View {
    double stamp = 0;  ///< [s] header.stamp
    uint32_t height = 0, width = 0, point_step = 0, row_step = 0;
    bool is_bigendian = false;
    std::vector<PointField2> fields;
    const uint8_t* data = nullptr;
    size_t data_size = 0;
};

/// How per-point time is read: [rosbag] point_time_* keys.
struct PointTimeOptions {
    std::string field = "auto";      ///< auto = first of t, time, timestamp, offset_time; none
    std::string unit = "auto";       ///< auto (float: s, integer: ns), s, ms, us, ns
    std::string reference = "auto";  ///< auto, relative (to header.stamp), absolute
};

struct PointCloud2Stats {
    size_t invalid_points = 0;    ///< NaN/inf x/y/z dropped
    std::string time_field;       ///< the field per-point time came from ("" = none)
    bool time_absolute = false;   ///< the field held absolute times
};

/// `s` as it may appear inside a one-line error message: control and non-ASCII bytes as \xNN,
/// cut to `max_len` characters with "..." (names read from a file can hold anything).
std::string printable(const std::string& s, size_t max_len = 64);

/// Decodes x, y, z (+ intensity when present, as float) and per-point time relative to
/// `stamp` into scan.points/intensity/rel_time (scan.t = stamp). Throws std::runtime_error with
/// a short reason (no file/topic: the caller adds them) when x/y/z are missing, a field does not
/// fit in point_step, the data is shorter than the layout says, or the options are invalid.
PointCloud2Stats decodePointCloud2(const PointCloud2View& pc, const PointTimeOptions& opt,
                                   Scan& scan);

}  // namespace superloc::io::detail
