// Private to io: ROS 2 messages in CDR (OMG XCDR version 1, as ROS 2's rmw serializes them),
// read by both ROS 2 bag readers (db3_reader.cpp, mcap_reader.cpp).
//
// The format: a 4-byte encapsulation header (0x00 0x01 = little endian, 0x00 0x00 = big
// endian, then 2 option bytes), then the message's fields in declaration order. Every
// primitive is aligned to its own size (at most 8) counted from the end of that header; a
// string is a uint32 length that includes a terminating NUL, then the bytes; a sequence
// (T[]) is a uint32 element count, then the elements; a fixed array (T[N]) has no count; a
// nested message is its fields inline. std_msgs/Header in ROS 2 is {builtin_interfaces/Time
// stamp {int32 sec, uint32 nanosec}, string frame_id} (no seq).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "bag_source.h"

namespace superloc::io::detail {

/// Reads CDR primitives with bounds checks; every error is a std::runtime_error naming what
/// was read and at which byte, e.g. "CDR: string length at byte 24 runs past the end (20 bytes)".
class CdrReader {
 public:
    /// Checks the encapsulation header (plain CDR, either byte order; others are refused).
    CdrReader(const uint8_t* data, size_t size);

    uint8_t u8(const char* what);
    bool boolean(const char* what) { return u8(what) != 0; }
    uint32_t u32(const char* what);
    int32_t i32(const char* what) { return int32_t(u32(what)); }
    double f64(const char* what);
    std::string string(const char* what);
    /// A sequence's element count, refused when `count * min_element_bytes` cannot fit in what
    /// is left (so a corrupt count never allocates).
    uint32_t sequenceLength(const char* what, size_t min_element_bytes);
    /// `n` raw bytes (no alignment), returned as a pointer into the message.
    const uint8_t* bytes(size_t n, const char* what);
    size_t position() const { return pos_; }

 private:
    const uint8_t* take(size_t n, size_t align, const char* what);
    const uint8_t* data_;
    size_t size_, pos_ = 4;
    bool swap_ = false;
};

/// ROS 2 message decoders (sensor_msgs/msg/PointCloud2, sensor_msgs/msg/Imu,
/// nav_msgs/msg/Odometry, geometry_msgs/msg/PoseStamped, tf2_msgs/msg/TFMessage).
PointCloud2Msg cdrPointCloud2(const uint8_t* data, size_t size);
ImuMsg cdrImu(const uint8_t* data, size_t size);
PoseMsg cdrOdometry(const uint8_t* data, size_t size);
PoseMsg cdrPoseStamped(const uint8_t* data, size_t size);
std::vector<TransformMsg> cdrTfMessage(const uint8_t* data, size_t size);

/// A CDR-serialized message of a ROS 2 bag (the bytes are not owned).
class CdrMessage : public BagMessage {
 public:
    CdrMessage(const std::string& topic, const std::string& type, int64_t time_ns,
               const uint8_t* data, size_t size)
        : topic_(topic), type_(type), time_ns_(time_ns), data_(data), size_(size) {}
    const std::string& topic() const override { return topic_; }
    const std::string& type() const override { return type_; }
    double bagTime() const override { return double(time_ns_) * 1e-9; }
    PointCloud2Msg pointCloud2() const override { return cdrPointCloud2(data_, size_); }
    ImuMsg imu() const override { return cdrImu(data_, size_); }
    PoseMsg odometry() const override { return cdrOdometry(data_, size_); }
    PoseMsg poseStamped() const override { return cdrPoseStamped(data_, size_); }
    std::vector<TransformMsg> tfMessage() const override { return cdrTfMessage(data_, size_); }

 private:
    const std::string& topic_;
    const std::string& type_;
    int64_t time_ns_;
    const uint8_t* data_;
    size_t size_;
};

}  // namespace superloc::io::detail
