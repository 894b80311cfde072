// CDR (XCDR1) decoding of the ROS 2 messages the bag import reads. See cdr.h for the format.
#include "cdr.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace superloc::io::detail {

namespace {

[[noreturn]] void fail(const std::string& what, size_t pos, const std::string& why) {
    throw std::runtime_error("CDR: " + what + " at byte " + std::to_string(pos) + " " + why);
}

std::string hex2(uint8_t a, uint8_t b) {
    const char* d = "0123456789abcdef";
    return std::string("0x") + d[a >> 4] + d[a & 15] + d[b >> 4] + d[b & 15];
}

}  // namespace

CdrReader::CdrReader(const uint8_t* data, size_t size) : data_(data), size_(size) {
    if (size < 4)
        throw std::runtime_error("CDR: message of " + std::to_string(size) +
                                 " bytes has no 4-byte encapsulation header");
    if (data[0] != 0 || data[1] > 1)
        throw std::runtime_error("CDR: encapsulation " + hex2(data[0], data[1]) +
                                 " is not plain CDR (0x0000 big, 0x0001 little endian)");
    const bool little = data[1] == 1;
    swap_ = little != (__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__);
}

const uint8_t* CdrReader::take(size_t n, size_t align, const char* what) {
    // Alignment counts from the end of the 4-byte encapsulation header.
    const size_t aligned = 4 + (pos_ - 4 + align - 1) / align * align;
    if (aligned > size_ || n > size_ - aligned)
        fail(what, aligned, "runs past the end (" + std::to_string(size_) + " bytes)");
    pos_ = aligned + n;
    return data_ + aligned;
}

uint8_t CdrReader::u8(const char* what) { return *take(1, 1, what); }

uint32_t CdrReader::u32(const char* what) {
    uint8_t b[4];
    std::memcpy(b, take(4, 4, what), 4);
    if (swap_) std::reverse(b, b + 4);
    uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
}

double CdrReader::f64(const char* what) {
    uint8_t b[8];
    std::memcpy(b, take(8, 8, what), 8);
    if (swap_) std::reverse(b, b + 8);
    double v;
    std::memcpy(&v, b, 8);
    return v;
}

std::string CdrReader::string(const char* what) {
    const size_t at = pos_;
    const uint32_t n = u32(what);
    const uint8_t* p = bytes(n, what);
    // The length counts a terminating NUL; tolerate writers that leave it out (n = 0 too).
    size_t len = n;
    if (len > 0 && p[len - 1] == 0) --len;
    if (std::memchr(p, 0, len)) fail(what, at, "holds a NUL inside the string");
    return std::string(reinterpret_cast<const char*>(p), len);
}

uint32_t CdrReader::sequenceLength(const char* what, size_t min_element_bytes) {
    const size_t at = pos_;
    const uint32_t n = u32(what);
    if (min_element_bytes > 0 && uint64_t(n) * min_element_bytes > size_ - pos_)
        fail(what, at,
             "says " + std::to_string(n) + " elements, more than the " +
                 std::to_string(size_ - pos_) + " bytes left hold");
    return n;
}

const uint8_t* CdrReader::bytes(size_t n, const char* what) { return take(n, 1, what); }

namespace {

MsgHeader readHeader(CdrReader& r) {
    MsgHeader h;
    const int32_t sec = r.i32("header.stamp.sec");
    const uint32_t nsec = r.u32("header.stamp.nanosec");
    h.stamp = double(sec) + double(nsec) * 1e-9;
    h.frame_id = r.string("header.frame_id");
    return h;
}

Vec3d readVec3(CdrReader& r, const char* what) {
    Vec3d v;
    for (int i = 0; i < 3; ++i) v[i] = r.f64(what);
    return v;
}

PoseFields readPose(CdrReader& r, const char* position, const char* orientation) {
    PoseFields p;
    p.x = r.f64(position);
    p.y = r.f64(position);
    p.z = r.f64(position);
    p.qx = r.f64(orientation);
    p.qy = r.f64(orientation);
    p.qz = r.f64(orientation);
    p.qw = r.f64(orientation);
    return p;
}

void skipF64(CdrReader& r, int n, const char* what) {
    for (int i = 0; i < n; ++i) r.f64(what);
}

}  // namespace

PointCloud2Msg cdrPointCloud2(const uint8_t* data, size_t size) {
    CdrReader r(data, size);
    PointCloud2Msg m;
    m.header = readHeader(r);
    PointCloud2View& v = m.cloud;
    v.stamp = m.header.stamp;
    v.height = r.u32("height");
    v.width = r.u32("width");
    // A PointField is at least a string length, offset, datatype and count: 13 bytes.
    const uint32_t nf = r.sequenceLength("fields", 13);
    v.fields.resize(nf);
    for (auto& f : v.fields) {
        f.name = r.string("fields[].name");
        f.offset = r.u32("fields[].offset");
        f.datatype = r.u8("fields[].datatype");
        f.count = r.u32("fields[].count");
    }
    v.is_bigendian = r.boolean("is_bigendian");
    v.point_step = r.u32("point_step");
    v.row_step = r.u32("row_step");
    const uint32_t n = r.sequenceLength("data", 1);
    v.data = r.bytes(n, "data");
    v.data_size = n;
    r.boolean("is_dense");
    return m;
}

ImuMsg cdrImu(const uint8_t* data, size_t size) {
    CdrReader r(data, size);
    ImuMsg m;
    m.header = readHeader(r);
    skipF64(r, 4, "orientation");
    skipF64(r, 9, "orientation_covariance");
    m.angular_velocity = readVec3(r, "angular_velocity");
    skipF64(r, 9, "angular_velocity_covariance");
    m.linear_acceleration = readVec3(r, "linear_acceleration");
    skipF64(r, 9, "linear_acceleration_covariance");
    return m;
}

PoseMsg cdrOdometry(const uint8_t* data, size_t size) {
    CdrReader r(data, size);
    PoseMsg m;
    m.header = readHeader(r);
    m.child_frame_id = r.string("child_frame_id");
    m.pose = readPose(r, "pose.pose.position", "pose.pose.orientation");
    m.covariance.emplace();
    for (double& c : *m.covariance) c = r.f64("pose.covariance");
    skipF64(r, 6, "twist.twist");
    skipF64(r, 36, "twist.covariance");
    return m;
}

PoseMsg cdrPoseStamped(const uint8_t* data, size_t size) {
    CdrReader r(data, size);
    PoseMsg m;
    m.header = readHeader(r);
    m.pose = readPose(r, "pose.position", "pose.orientation");
    return m;
}

std::vector<TransformMsg> cdrTfMessage(const uint8_t* data, size_t size) {
    CdrReader r(data, size);
    // A TransformStamped is at least 8 (stamp) + 4 + 4 (two strings) + 56 (7 doubles) bytes.
    const uint32_t n = r.sequenceLength("transforms", 72);
    std::vector<TransformMsg> out(n);
    for (auto& x : out) {
        x.parent = readHeader(r).frame_id;
        x.child = r.string("transforms[].child_frame_id");
        x.T_parent_child =
            readPose(r, "transforms[].transform.translation", "transforms[].transform.rotation");
    }
    return out;
}

}  // namespace superloc::io::detail
